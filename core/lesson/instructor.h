#pragma once
// The instructor's passphrase: set on first use, kept only as an Argon2id hash
// (libsodium's crypto_pwhash_str, with its interactive limits), never in plain
// text: in a file beside a station's results database, or, with a lab's shared
// store, in the store's settings, so that it is the same on every station.
// Students cannot open the instructor's view without it.

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "core/lesson/results.h"

namespace sulcus {

class InstructorLock {
 public:
  /// `file` holds the hash (created by Set).
  explicit InstructorLock(std::filesystem::path file);
  /// The lock of a place: its folder's file for a station's SQLite store, the
  /// store's settings for a shared one (throws ResultsError when unreachable).
  explicit InstructorLock(const ResultsPlace& place);
  ~InstructorLock();
  InstructorLock(InstructorLock&&) noexcept;
  bool is_set() const;
  /// First use only: throws std::runtime_error when a passphrase is already set
  /// or this one is shorter than kMinLength, or the file cannot be written.
  void Set(const std::string& passphrase);
  /// True for the right passphrase; false for any other (and when none is set).
  bool Check(const std::string& passphrase) const;
  static constexpr std::size_t kMinLength = 8;

 private:
  std::string ReadHash() const;
  std::filesystem::path file_;
  std::unique_ptr<ResultsStore> store_;  // a shared store's settings, else the file
};

}  // namespace sulcus
