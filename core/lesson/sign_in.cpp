#include "core/lesson/sign_in.h"

#include <sodium.h>

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include "core/base/names.h"

namespace sulcus {
namespace {

std::string Hex(const unsigned char* data, std::size_t n) {
  std::string out(2 * n + 1, '\0');
  sodium_bin2hex(out.data(), out.size(), data, n);
  out.pop_back();
  return out;
}

// The key a passphrase gives with a salt: Argon2id (libsodium's interactive
// limits: 2 passes over 64 MiB), 32 bytes, in hex.
std::string DeriveKey(const std::string& passphrase, const std::string& salt_hex) {
  unsigned char salt[crypto_pwhash_SALTBYTES];
  if (sodium_hex2bin(salt, sizeof salt, salt_hex.data(), salt_hex.size(), nullptr,
                     nullptr, nullptr) != 0)
    throw ResultsError(
        "the store holds a damaged passphrase salt; the instructor resets "
        "the student's passphrase");
  unsigned char key[32];
  if (crypto_pwhash(key, sizeof key, passphrase.data(), passphrase.size(), salt,
                    crypto_pwhash_OPSLIMIT_INTERACTIVE,
                    crypto_pwhash_MEMLIMIT_INTERACTIVE,
                    crypto_pwhash_ALG_ARGON2ID13) != 0)
    throw ResultsError("not enough memory to check the passphrase (64 MiB)");
  return Hex(key, sizeof key);
}

}  // namespace

SignInResult SignIn(ResultsStore& store, const std::string& name,
                    const std::string& passphrase) {
  if (sodium_init() < 0) throw ResultsError("libsodium could not be initialised");
  const std::vector<std::string> roster = store.Roster();
  if (std::find(roster.begin(), roster.end(), name) == roster.end())
    throw ResultsError("\"" + name +
                       "\" is not on the class's roster; pick your name from the list, "
                       "or ask the instructor to add it");
  SignInResult out;
  std::string salt = store.PassphraseSalt(name);
  if (salt.empty()) {
    if (passphrase.size() < kMinPassphraseChars)
      throw ResultsError("choose a passphrase of at least " +
                         std::to_string(kMinPassphraseChars) +
                         " characters: it is set now, at your first sign-in");
    unsigned char raw[crypto_pwhash_SALTBYTES];
    randombytes_buf(raw, sizeof raw);
    salt = Hex(raw, sizeof raw);
    if (!store.SetPassphraseKey(name, salt, DeriveKey(passphrase, salt)))
      salt = store.PassphraseSalt(name);  // (set at another station meanwhile)
    else
      out.first_use = true;
  }
  out.token = store.SignInWithKey(name, DeriveKey(passphrase, salt));
  if (out.token.empty())
    throw ResultsError("the passphrase is not " + name +
                       "'s; try again, or ask the instructor to reset it");
  return out;
}

int AddNamesToRoster(ResultsStore& store, const std::vector<std::string>& names,
                     std::vector<std::string>* refused) {
  int added = 0;
  for (const std::string& typed : names) {
    const std::string name = NormalName(typed);
    if (const std::string why = NameProblem(name); !why.empty()) {
      if (refused) refused->push_back(name + ": " + why);
      continue;
    }
    try {
      added += store.AddToRoster(name, NameLookAlikeKey(name)) ? 1 : 0;
    } catch (const ResultsError& e) {
      if (refused) refused->push_back(name + ": " + e.what());
    }
  }
  return added;
}

std::vector<std::string> ReadRosterFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  std::vector<std::string> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (n == 1 && line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0)
      line.erase(0, 3);  // (a byte-order mark)
    std::string name;
    if (!line.empty() && line[0] == '"') {  // a quoted CSV field
      std::size_t i = 1;
      for (; i < line.size(); ++i) {
        if (line[i] == '"' && i + 1 < line.size() && line[i + 1] == '"') {
          name += '"';
          ++i;
        } else if (line[i] == '"') {
          break;
        } else {
          name += line[i];
        }
      }
    } else {
      name = line.substr(0, line.find(','));
    }
    const std::string normal = NormalName(name);
    if (normal.empty() || normal[0] == '#') continue;
    if (n == 1 && (normal == "name" || normal == "Name")) continue;
    if (NameProblem(normal).find("UTF-8") != std::string::npos)
      throw std::runtime_error(path + ":" + std::to_string(n) +
                               ": the line is not UTF-8 text (save the roster as UTF-8)");
    out.push_back(normal);
  }
  return out;
}

void KeepSignIn(const std::filesystem::path& attempt_dir, const std::string& token) {
  const std::filesystem::path file = attempt_dir / kSignInFile;
  {
    std::ofstream out(file, std::ios::trunc);
    if (!out) throw std::runtime_error(file.string() + ": cannot be written");
    std::filesystem::permissions(
        file, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
    out << token << '\n';
    if (!out.flush()) throw std::runtime_error(file.string() + ": cannot be written");
  }
}

std::string KeptSignIn(const std::filesystem::path& attempt_dir) {
  std::ifstream in(attempt_dir / kSignInFile);
  std::string token;
  if (in) std::getline(in, token);
  return token;
}

}  // namespace sulcus
