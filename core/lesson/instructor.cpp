#include "core/lesson/instructor.h"

#include <sodium.h>
#include <sys/stat.h>

#include <fstream>
#include <sstream>

namespace sulcus {
namespace {

void InitSodium() {
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
}

constexpr const char* kHashSetting = "instructor_pwhash";

}  // namespace

InstructorLock::InstructorLock(std::filesystem::path file) : file_(std::move(file)) {
  InitSodium();
}

InstructorLock::InstructorLock(const ResultsPlace& place)
    : file_(place.dir / "instructor.pwhash") {
  InitSodium();
  if (!place.url.empty()) store_ = OpenResults(place);
}

InstructorLock::~InstructorLock() = default;
InstructorLock::InstructorLock(InstructorLock&&) noexcept = default;

std::string InstructorLock::ReadHash() const {
  if (store_) return store_->Setting(kHashSetting).value_or("");
  std::ifstream in(file_);
  std::string hash;
  std::getline(in, hash);
  return hash;
}

bool InstructorLock::is_set() const { return !ReadHash().empty(); }

void InstructorLock::Set(const std::string& passphrase) {
  if (is_set())
    throw std::runtime_error("the instructor's passphrase is already set (" +
                             (store_ ? store_->where() : file_.string()) + ")");
  if (passphrase.size() < kMinLength)
    throw std::runtime_error("the passphrase needs at least " +
                             std::to_string(kMinLength) + " characters");
  char hash[crypto_pwhash_STRBYTES];
  if (crypto_pwhash_str(hash, passphrase.data(), passphrase.size(),
                        crypto_pwhash_OPSLIMIT_INTERACTIVE,
                        crypto_pwhash_MEMLIMIT_INTERACTIVE) != 0)
    throw std::runtime_error("out of memory while hashing the passphrase");
  if (store_) {
    if (!store_->SetSettingOnce(kHashSetting, hash))
      throw std::runtime_error("the instructor's passphrase is already set (" +
                               store_->where() + ")");
    return;
  }
  std::error_code ec;
  if (file_.has_parent_path())
    std::filesystem::create_directories(file_.parent_path(), ec);
  const std::filesystem::path tmp = file_.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << hash << '\n';
    if (!out)
      throw std::runtime_error(file_.string() + ": cannot write the passphrase's hash");
  }
  ::chmod(tmp.c_str(), 0600);  // only its owner reads even the hash
  std::filesystem::rename(tmp, file_);
}

bool InstructorLock::Check(const std::string& passphrase) const {
  const std::string hash = ReadHash();
  if (hash.empty()) return false;
  return crypto_pwhash_str_verify(hash.c_str(), passphrase.data(), passphrase.size()) ==
         0;
}

}  // namespace sulcus
