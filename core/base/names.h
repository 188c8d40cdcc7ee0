#pragma once
// A student's name: one spelling for one student. What is typed is trimmed and
// put in Unicode's composed normal form (NFC), so "Zoë" typed as o + combining
// diaeresis is the same student as "Zoë" typed with the precomposed letter;
// what could forge a line, hide a character or pass for another name is
// refused where it is typed (the window, the command line), never after the
// lesson. Uses ICU (normalisation, the confusable "skeletons" of UTS #39).

#include <cstddef>
#include <string>
#include <string_view>

namespace sulcus {

inline constexpr std::size_t kMaxNameChars = 120;

/// `typed` trimmed of white space at both ends and in NFC. Text that is not
/// valid UTF-8 is returned as it is (NameProblem says why it is refused).
std::string NormalName(std::string_view typed);

/// Why `name` cannot be a student's name ("" when it can): empty, more than
/// kMaxNameChars characters, not UTF-8, not normal (NormalName changes it),
/// holding a control character, a bidirectional override or an invisible
/// character (a zero-width space), or mixing scripts the way a look-alike does
/// ("alice" with a Cyrillic "а").
std::string NameProblem(std::string_view name);

/// A key that is the same for two names a reader could take for one another
/// ("alice" and "aIice", "rn" and "m", Latin and Cyrillic "a"), case aside:
/// the roster refuses a new name whose key another student's name has.
std::string NameLookAlikeKey(std::string_view name);

}  // namespace sulcus
