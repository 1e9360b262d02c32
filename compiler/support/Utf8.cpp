#include "Utf8.h"

namespace ldae::utf8 {

namespace {
bool inRange(std::string_view s, size_t i, uint8_t lo, uint8_t hi) {
  if (i >= s.size())
    return false;
  auto b = static_cast<uint8_t>(s[i]);
  return b >= lo && b <= hi;
}
} // namespace

Char decodeAt(std::string_view s, size_t i) {
  auto b0 = static_cast<uint8_t>(s[i]);
  if (b0 < 0x80)
    return {b0, 1};
  // The well-formed sequences of the Unicode standard (table 3-7): the
  // second byte's range depends on the first, which excludes overlong
  // forms, surrogates and code points above U+10FFFF.
  uint8_t lo = 0x80, hi = 0xBF;
  uint32_t len = 0;
  if (b0 >= 0xC2 && b0 <= 0xDF)
    len = 2;
  else if (b0 >= 0xE0 && b0 <= 0xEF) {
    len = 3;
    if (b0 == 0xE0)
      lo = 0xA0;
    else if (b0 == 0xED)
      hi = 0x9F;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    len = 4;
    if (b0 == 0xF0)
      lo = 0x90;
    else if (b0 == 0xF4)
      hi = 0x8F;
  }
  if (len == 0 || !inRange(s, i + 1, lo, hi))
    return {kEscapeBase + b0, 1};
  for (uint32_t k = 2; k < len; ++k)
    if (!inRange(s, i + k, 0x80, 0xBF))
      return {kEscapeBase + b0, 1};
  char32_t cp = b0 & (len == 2 ? 0x1F : len == 3 ? 0x0F : 0x07);
  for (uint32_t k = 1; k < len; ++k)
    cp = (cp << 6) | (static_cast<uint8_t>(s[i + k]) & 0x3F);
  return {cp, len};
}

void append(std::string &out, char32_t cp) {
  if ((cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF)
    cp = kReplacement;
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

size_t countChars(std::string_view s) {
  size_t n = 0;
  for (size_t i = 0; i < s.size(); i += decodeAt(s, i).bytes)
    ++n;
  return n;
}

std::string sanitize(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (size_t i = 0; i < s.size();) {
    Char c = decodeAt(s, i);
    if (isEscapedByte(c.cp))
      append(out, kReplacement);
    else
      out.append(s.substr(i, c.bytes));
    i += c.bytes;
  }
  return out;
}

std::string_view prefixChars(std::string_view s, size_t maxChars) {
  size_t i = 0;
  for (size_t n = 0; n < maxChars && i < s.size(); ++n)
    i += decodeAt(s, i).bytes;
  return s.substr(0, i);
}

} // namespace ldae::utf8
