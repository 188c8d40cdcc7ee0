#pragma once
// A student signs in at a station: the name on the class's roster, a
// passphrase set at first use. The station derives a key from the passphrase
// (Argon2id, with the student's salt, which the store gives to anyone) and
// sends the key to the store, which keeps only its SHA-256 and checks it
// itself: no station reads what the store keeps. A sign-in is a token; an
// attempt stored with it is marked as its student's own (ResultsStore::Store).

#include <filesystem>
#include <string>
#include <vector>

#include "core/lesson/results.h"

namespace sulcus {

/// The shortest passphrase a student may choose.
inline constexpr std::size_t kMinPassphraseChars = 8;

struct SignInResult {
  std::string token;       // for ResultsStore::Store
  bool first_use = false;  // the passphrase was set now
};

/// Signs `name` in at `store`: first use (no passphrase yet) sets `passphrase`
/// (at least kMinPassphraseChars characters), later ones check it. Throws
/// ResultsError saying what is wrong (a name not on the roster, a wrong or too
/// short passphrase, too many wrong ones) and never which part of a wrong
/// passphrase was wrong.
SignInResult SignIn(ResultsStore& store, const std::string& name,
                    const std::string& passphrase);

/// Puts each name on the roster (the instructor's): normalised (NormalName),
/// refused with the reason (NameProblem, a look-alike of another student's)
/// in `refused` as "name: why". Returns how many were new.
int AddNamesToRoster(ResultsStore& store, const std::vector<std::string>& names,
                     std::vector<std::string>* refused);

/// The names of a roster file: one a line, or a CSV whose first column is the
/// name (a header "name" is skipped); blank lines and lines starting with #
/// are skipped. Throws std::runtime_error naming the file and line of text
/// that is not UTF-8.
std::vector<std::string> ReadRosterFile(const std::string& path);

/// Where an attempt's folder keeps the sign-in it was taken under (read
/// only by this station's own account; used when the attempt is stored, also
/// later by a sync).
inline constexpr const char* kSignInFile = "sign-in";
/// Keeps a sign-in's token in an attempt's folder (readable by its owner only).
/// Throws std::runtime_error naming the file.
void KeepSignIn(const std::filesystem::path& attempt_dir, const std::string& token);
/// The token kept in an attempt's folder, "" when there is none.
std::string KeptSignIn(const std::filesystem::path& attempt_dir);

}  // namespace sulcus
