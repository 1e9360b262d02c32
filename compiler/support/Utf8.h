// A lenient UTF-8 decoder of our own (std::wstring_convert is deprecated and
// throws on the first bad byte). Every byte that is not part of a well-formed
// sequence decodes to one "escape" code point in the low-surrogate range,
// which no well-formed UTF-8 can produce: the lexer can tell the user which
// byte is wrong and where, and text that allows anything (comments, strings)
// keeps going with U+FFFD in its place.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace ldae::utf8 {

/// One decoded character: its code point and how many bytes it took.
struct Char {
  char32_t cp;
  uint32_t bytes;
};

/// Invalid byte `b` (0x80..0xff) decodes to kEscapeBase + b.
inline constexpr char32_t kEscapeBase = 0xDC00;
inline constexpr char32_t kReplacement = 0xFFFD;

inline bool isEscapedByte(char32_t cp) {
  return cp >= kEscapeBase + 0x80 && cp <= kEscapeBase + 0xFF;
}
inline uint8_t escapedByte(char32_t cp) {
  return static_cast<uint8_t>(cp - kEscapeBase);
}

/// The character starting at byte `i` of `s` (i < s.size()).
Char decodeAt(std::string_view s, size_t i);

/// Appends the UTF-8 of `cp`; escaped bytes and anything that is not a
/// Unicode scalar value become U+FFFD, so the output is always valid.
void append(std::string &out, char32_t cp);

/// Number of characters of `s` as decodeAt counts them.
size_t countChars(std::string_view s);

/// `s` with every invalid byte replaced by U+FFFD.
std::string sanitize(std::string_view s);

/// The longest prefix of `s` of at most `maxChars` characters.
std::string_view prefixChars(std::string_view s, size_t maxChars);

} // namespace ldae::utf8
