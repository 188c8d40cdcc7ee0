#include "core/base/text.h"

#include <algorithm>
#include <cstdio>

namespace sulcus {

std::string Shorten(std::string_view text, std::size_t max) {
  std::size_t cut = std::min(max, text.size());
  // Never in the middle of a UTF-8 character.
  while (cut > 0 && cut < text.size() &&
         (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80)
    --cut;
  std::string out(text.substr(0, cut));
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  if (text.size() > max) out += "... (" + std::to_string(text.size()) + " characters)";
  return out;
}

namespace {

// The next code point of `text` at `i` (advanced past it), or -1 for a byte
// that does not begin a well-formed UTF-8 sequence (i advanced by one).
long NextCodePoint(std::string_view text, std::size_t* i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = b(*i);
  int len = c < 0x80         ? 1
            : (c >> 5) == 6  ? 2
            : (c >> 4) == 14 ? 3
            : (c >> 3) == 30 ? 4
                             : 0;
  if (len == 0 || *i + len > text.size()) {
    ++*i;
    return -1;
  }
  long cp = len == 1 ? c : c & (0x7f >> len);
  for (int k = 1; k < len; ++k) {
    if ((b(*i + k) & 0xC0) != 0x80) {
      ++*i;
      return -1;
    }
    cp = (cp << 6) | (b(*i + k) & 0x3f);
  }
  // Overlong forms, surrogates and beyond U+10FFFF are not UTF-8.
  static const long min_of[5] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < min_of[len] || (cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) {
    ++*i;
    return -1;
  }
  *i += static_cast<std::size_t>(len);
  return cp;
}

bool Unsafe(long cp) {
  return cp < 0x20 || (cp >= 0x7f && cp <= 0x9f) || (cp >= 0x202A && cp <= 0x202E) ||
         (cp >= 0x2066 && cp <= 0x2069);
}

}  // namespace

std::string TerminalSafe(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size()) {
    const std::size_t from = i;
    const long cp = NextCodePoint(text, &i);
    char buf[32];
    if (cp < 0) {
      std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned char>(text[from]));
      out += buf;
    } else if (Unsafe(cp)) {
      if (cp < 0x100)
        std::snprintf(buf, sizeof buf, "\\x%02lX", cp);
      else
        std::snprintf(buf, sizeof buf, "\\u{%04lX}", cp);
      out += buf;
    } else {
      out.append(text.substr(from, i - from));
    }
  }
  return out;
}

std::string ShortenQuoted(std::string_view message, std::size_t max) {
  std::string out;
  std::size_t i = 0;
  while (i < message.size()) {
    const std::size_t open = message.find('\'', i);
    if (open == std::string_view::npos) break;
    const std::size_t close = message.find('\'', open + 1);
    if (close == std::string_view::npos) break;
    out.append(message.substr(i, open + 1 - i));
    const std::string_view quoted = message.substr(open + 1, close - open - 1);
    out += quoted.size() > max ? Shorten(quoted, max) : std::string(quoted);
    out += '\'';
    i = close + 1;
  }
  out.append(message.substr(std::min(i, message.size())));
  // An apostrophe in the prose ("the scene's") pairs quotes wrongly: any long
  // word left is cut too.
  std::string words;
  std::size_t start = 0;
  while (start <= out.size()) {
    const std::size_t end = std::min(out.find(' ', start), out.size());
    const std::string_view word = std::string_view(out).substr(start, end - start);
    words += word.size() > 4 * max ? Shorten(word, max) : std::string(word);
    if (end < out.size()) words += ' ';
    start = end + 1;
  }
  return words;
}

std::string FormatNumber(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string Join(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& x : items) s += (s.empty() ? "" : ", ") + x;
  return s;
}

std::string Join(const std::vector<int>& items) {
  std::string s;
  for (int x : items) s += (s.empty() ? "" : ", ") + std::to_string(x);
  return s;
}

std::string JsonQuote(std::string_view text) {
  std::string o = "\"";
  for (char c : text) {
    switch (c) {
      case '"':
        o += "\\\"";
        break;
      case '\\':
        o += "\\\\";
        break;
      case '\n':
        o += "\\n";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", static_cast<unsigned>(c));
          o += b;
        } else {
          o += c;
        }
    }
  }
  return o + "\"";
}

}  // namespace sulcus
