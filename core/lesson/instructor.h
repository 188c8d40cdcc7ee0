#pragma once
// The instructor's passphrase: set on first use, kept only as an Argon2id hash
// (libsodium's crypto_pwhash_str, with its interactive limits) in a file beside
// the results database, never in plain text. Students cannot open the
// instructor's view without it.

#include <filesystem>
#include <stdexcept>
#include <string>

namespace sulcus {

class InstructorLock {
 public:
  /// `file` holds the hash (created by Set).
  explicit InstructorLock(std::filesystem::path file);
  bool is_set() const;
  /// First use only: throws std::runtime_error when a passphrase is already set
  /// or this one is shorter than kMinLength, or the file cannot be written.
  void Set(const std::string& passphrase);
  /// True for the right passphrase; false for any other (and when none is set).
  bool Check(const std::string& passphrase) const;
  static constexpr std::size_t kMinLength = 8;

 private:
  std::filesystem::path file_;
};

}  // namespace sulcus
