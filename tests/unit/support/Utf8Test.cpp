// The lenient UTF-8 decoder and the character-based line and column
// counting of SourceManager built on it.
#include "support/Diagnostics.h"
#include "support/Utf8.h"

#include <gtest/gtest.h>

using namespace ldae;

TEST(Utf8, DecodesWellFormedSequences) {
  std::string s = "a\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80";
  EXPECT_EQ(utf8::decodeAt(s, 0).cp, U'a');
  EXPECT_EQ(utf8::decodeAt(s, 1).cp, U'\u00e9');
  EXPECT_EQ(utf8::decodeAt(s, 1).bytes, 2u);
  EXPECT_EQ(utf8::decodeAt(s, 3).cp, U'\u20ac');
  EXPECT_EQ(utf8::decodeAt(s, 6).cp, U'\U0001F600');
  EXPECT_EQ(utf8::countChars(s), 4u);
}

TEST(Utf8, EveryInvalidByteIsOneEscapedCharacter) {
  // A lone continuation byte, a truncated sequence, an overlong '/', an
  // encoded surrogate and a code point above U+10FFFF.
  for (std::string bad : {"\x80", "\xe2\x82", "\xc0\xaf", "\xed\xa0\x80",
                          "\xf4\x90\x80\x80", "\xff"}) {
    utf8::Char c = utf8::decodeAt(bad, 0);
    EXPECT_TRUE(utf8::isEscapedByte(c.cp)) << bad;
    EXPECT_EQ(c.bytes, 1u);
    EXPECT_EQ(utf8::escapedByte(c.cp), static_cast<uint8_t>(bad[0]));
    EXPECT_EQ(utf8::countChars(bad), bad.size());
  }
  EXPECT_EQ(utf8::sanitize("a\xe9z"), "a\xef\xbf\xbdz");
  std::string out;
  utf8::append(out, utf8::kEscapeBase + 0xe9);
  EXPECT_EQ(out, "\xef\xbf\xbd");
}

TEST(Utf8, PrefixNeverCutsASequence) {
  EXPECT_EQ(utf8::prefixChars("\xc3\xa4\xc3\xa4\xc3\xa4", 2), "\xc3\xa4\xc3\xa4");
  EXPECT_EQ(utf8::prefixChars("ab", 5), "ab");
}

TEST(SourceLines, EndOfTextIsOnTheLastLineWithText) {
  SourceManager sm;
  uint32_t f = sm.addFile("m.lsd", "model M\n  x = '\xc3\xa4';\n\n  \n");
  SourceLoc end = sm.endOfText(f);
  EXPECT_EQ(end.line, 2u);
  EXPECT_EQ(end.col, 11u); // after 10 characters (11 bytes)
}

TEST(SourceLines, CaretCountsCharacters) {
  SourceManager sm;
  uint32_t f = sm.addFile("m.lsd", "\xc3\xa4\xc3\xa4 = \xff;\n");
  DiagnosticEngine diags(sm);
  Diagnostic &d =
      diags.report(DiagId::ErrorGeneric, SourceLoc{f, 1, 6}, {"bad"});
  EXPECT_EQ(diags.render(d), "m.lsd:1:6: error: bad\n"
                             "\xc3\xa4\xc3\xa4 = \xef\xbf\xbd;\n"
                             "     ^\n");
}
