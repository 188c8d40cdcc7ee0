#pragma once
// Values shown back to the user in messages: never a megabyte token echoed whole,
// never a number printed as 309 digits.

#include <string>
#include <string_view>
#include <vector>

namespace sulcus {

/// `text` as written when it has at most `max` characters (bytes), else its
/// first `max` followed by "... (N characters)". Control characters (a NUL, a
/// newline) are shown as '?', so a message stays one readable line.
std::string Shorten(std::string_view text, std::size_t max = 80);

/// `message` with every value quoted in it ('...') of more than `max`
/// characters shortened as Shorten does: a reader's error can quote what it
/// found without echoing a megabyte token.
std::string ShortenQuoted(std::string_view message, std::size_t max = 80);

/// A number as a person reads it: printf's %g (six significant digits), so
/// 1e308 is "1e+308" and 0.25 is "0.25".
std::string FormatNumber(double x);

/// `text` as a JSON string, quoted: quotes, backslashes and control characters
/// escaped (UTF-8 passes as it is).
std::string JsonQuote(std::string_view text);

/// `text` safe to print on a terminal: control characters (C0, DEL, C1) and
/// the bidirectional overrides and isolates (U+202A to U+202E, U+2066 to
/// U+2069) shown as \xNN or \u{NNNN}; bytes that are not UTF-8 as \xNN.
std::string TerminalSafe(std::string_view text);

/// The items in order, separated by ", " (a list in a message: "47, 46, 45").
std::string Join(const std::vector<std::string>& items);
std::string Join(const std::vector<int>& items);

}  // namespace sulcus
