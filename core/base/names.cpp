#include "core/base/names.h"

#include <unicode/normalizer2.h>
#include <unicode/uchar.h>
#include <unicode/unistr.h>
#include <unicode/uspoof.h>
#include <unicode/utf8.h>

#include <cstdint>
#include <memory>

namespace sulcus {

namespace {

bool ValidUtf8(std::string_view s) {
  const auto* b = reinterpret_cast<const std::uint8_t*>(s.data());
  const auto n = static_cast<std::int32_t>(s.size());
  for (std::int32_t i = 0; i < n;) {
    UChar32 c;
    U8_NEXT(b, i, n, c);
    if (c < 0) return false;
  }
  return s.size() < 0x7fffffff;
}

struct SpoofCloser {
  void operator()(USpoofChecker* c) const { uspoof_close(c); }
};

// One checker per thread (a checker is not to be shared while it is set up;
// checking with one is cheap).
USpoofChecker* Checker() {
  thread_local std::unique_ptr<USpoofChecker, SpoofCloser> checker = [] {
    UErrorCode e = U_ZERO_ERROR;
    std::unique_ptr<USpoofChecker, SpoofCloser> c(uspoof_open(&e));
    uspoof_setChecks(c.get(), USPOOF_RESTRICTION_LEVEL | USPOOF_MIXED_NUMBERS, &e);
    // Latin with one of the scripts Latin is written with (Han, Kana,
    // Hangul), or any one script alone: "Zoë", "Алиса", "山田 Taro"; never
    // Latin with Cyrillic or Greek.
    uspoof_setRestrictionLevel(c.get(), USPOOF_MODERATELY_RESTRICTIVE);
    return c;
  }();
  return checker.get();
}

}  // namespace

std::string NormalName(std::string_view typed) {
  if (!ValidUtf8(typed)) return std::string(typed);
  UErrorCode e = U_ZERO_ERROR;
  const icu::Normalizer2* nfc = icu::Normalizer2::getNFCInstance(e);
  icu::UnicodeString s = icu::UnicodeString::fromUTF8(
      icu::StringPiece(typed.data(), static_cast<std::int32_t>(typed.size())));
  s = U_SUCCESS(e) ? nfc->normalize(s, e) : s;
  // Trimmed of every kind of white space (a no-break space too).
  std::int32_t from = 0, to = s.length();
  while (from < to && u_isUWhiteSpace(s.char32At(from))) from = s.moveIndex32(from, 1);
  while (to > from && u_isUWhiteSpace(s.char32At(s.moveIndex32(to, -1))))
    to = s.moveIndex32(to, -1);
  std::string out;
  s.tempSubStringBetween(from, to).toUTF8String(out);
  return out;
}

std::string NameProblem(std::string_view name) {
  if (name.empty()) return "a name is needed";
  if (!ValidUtf8(name)) return "the name is not valid UTF-8 text";
  const auto* b = reinterpret_cast<const std::uint8_t*>(name.data());
  const auto n = static_cast<std::int32_t>(name.size());
  std::size_t chars = 0;
  for (std::int32_t i = 0; i < n; ++chars) {
    UChar32 c;
    U8_NEXT(b, i, n, c);
    if (c < 0x20 || (c >= 0x7f && c <= 0x9f) || (c >= 0x202A && c <= 0x202E) ||
        (c >= 0x2066 && c <= 0x2069))
      return "the name holds a control character or a text-direction override";
    if (u_hasBinaryProperty(c, UCHAR_DEFAULT_IGNORABLE_CODE_POINT))
      return "the name holds an invisible character (a zero-width space or joiner)";
    if (u_iscntrl(c)) return "the name holds a line or paragraph separator";
  }
  if (chars > kMaxNameChars)
    return "the name has " + std::to_string(chars) + " characters; at most " +
           std::to_string(kMaxNameChars);
  if (NormalName(name) != name)
    return "the name has white space at an end or is not in Unicode's composed form";
  UErrorCode e = U_ZERO_ERROR;
  const std::int32_t found = uspoof_checkUTF8(Checker(), name.data(), n, nullptr, &e);
  if (U_SUCCESS(e) && (found & USPOOF_RESTRICTION_LEVEL))
    return "the name mixes alphabets the way a look-alike does (a Cyrillic or Greek "
           "letter among Latin ones); type it in one alphabet";
  if (U_SUCCESS(e) && (found & USPOOF_MIXED_NUMBERS))
    return "the name mixes digits of different scripts";
  return "";
}

namespace {

std::string Skeleton(const std::string& text) {
  UErrorCode e = U_ZERO_ERROR;
  std::string key(text.size() * 4 + 16, '\0');
  const auto n = static_cast<std::int32_t>(text.size());
  std::int32_t len = uspoof_getSkeletonUTF8(Checker(), 0, text.data(), n, key.data(),
                                            static_cast<std::int32_t>(key.size()), &e);
  if (e == U_BUFFER_OVERFLOW_ERROR) {
    e = U_ZERO_ERROR;
    key.resize(static_cast<std::size_t>(len));
    len = uspoof_getSkeletonUTF8(Checker(), 0, text.data(), n, key.data(), len, &e);
  }
  if (U_FAILURE(e)) return text;
  key.resize(static_cast<std::size_t>(len));
  return key;
}

}  // namespace

std::string NameLookAlikeKey(std::string_view name) {
  if (!ValidUtf8(name)) return std::string(name);
  // The skeleton (which maps "I" to "l"), case folded, and its skeleton again.
  icu::UnicodeString s = icu::UnicodeString::fromUTF8(Skeleton(std::string(name)));
  std::string folded;
  s.foldCase().toUTF8String(folded);
  return Skeleton(folded);
}

}  // namespace sulcus
