// The hand-written lexer: token types, positions, every literal form and
// every lexical error, then the same tokens and errors as the lexer ANTLR
// generates from grammar/Lsd.g4 (linked into this test only) on the corpus,
// mutated corpus files and random bytes.
#include "frontend/Lexer.h"

#include "Corpus.h"

#include "LsdLexer.h"
#include "LsdParser.h"
#include "antlr4-runtime.h"
#include "support/Utf8.h"

#include <gtest/gtest.h>

#include <random>

using namespace ldae::frontend;
using namespace std::string_literals;
using P = lsdparser::LsdParser;

namespace {

struct Tok {
  size_t type, start, stop, line, column;
  std::string text;
  bool operator==(const Tok &) const = default;
};

struct Err {
  int kind; // a LexErrorKind, or kUnterminatedComment
  size_t line, column;
  char32_t value;
  bool operator==(const Err &) const = default;
};

/// What the old error listener called an error at "/*"; the hand-written
/// lexer never reports it, and neither does ANTLR's (it accepts the '/').
constexpr int kUnterminatedComment = 100;

struct Lexed {
  std::vector<Tok> tokens;
  std::vector<Err> errors;
  bool operator==(const Lexed &) const = default;
};

void PrintTo(const Tok &t, std::ostream *os) {
  *os << t.type << " [" << t.start << "," << t.stop << "] " << t.line << ":"
      << t.column << " '" << t.text << "'";
}

void PrintTo(const Lexed &l, std::ostream *os) {
  for (const Tok &t : l.tokens) {
    *os << "\n  ";
    PrintTo(t, os);
  }
  for (const Err &e : l.errors)
    *os << "\n  error " << e.kind << " " << e.line << ":" << e.column << " "
        << static_cast<uint32_t>(e.value);
}

Tok tokOf(antlr4::Token &t) {
  return {t.getType(), t.getStartIndex(), t.getStopIndex(), t.getLine(),
          t.getCharPositionInLine(), t.getText()};
}

/// Stops at end of file, or after more tokens than a file can hold.
template <class Source> std::vector<Tok> drain(Source &lexer, size_t bound) {
  std::vector<Tok> out;
  for (size_t i = 0; i <= bound; ++i) {
    auto t = lexer.nextToken();
    out.push_back(tokOf(*t));
    if (t->getType() == antlr4::Token::EOF)
      break;
  }
  return out;
}

Lexed lexOurs(std::string_view text) {
  SourceStream input(text);
  Lexed out;
  Lexer lexer(input, [&](const LexError &e) {
    out.errors.push_back(
        {static_cast<int>(e.kind), e.line, e.column, e.value});
  });
  out.tokens = drain(lexer, input.chars().size() + 1);
  return out;
}

/// The generated lexer, its errors classified as the listener that went
/// with it did: by the character where the failed token starts.
class ReferenceListener : public antlr4::BaseErrorListener {
public:
  ReferenceListener(const SourceStream &input, std::vector<Err> &errors)
      : chars_(input.chars()), errors_(errors) {}
  void syntaxError(antlr4::Recognizer *recognizer, antlr4::Token *,
                   size_t line, size_t column, const std::string &,
                   std::exception_ptr) override {
    size_t start = static_cast<antlr4::Lexer *>(recognizer)->tokenStartCharIndex;
    char32_t c = chars_.at(start);
    char32_t next = start + 1 < chars_.size() ? chars_[start + 1] : 0;
    Err e{0, line, column, c};
    if (ldae::utf8::isEscapedByte(c))
      e = {static_cast<int>(LexErrorKind::InvalidUtf8), line, column,
           ldae::utf8::escapedByte(c)};
    else if (c == '"')
      e.kind = static_cast<int>(LexErrorKind::UnterminatedString);
    else if (c == '/' && next == '*')
      e.kind = kUnterminatedComment;
    else if (c == '\'')
      e.kind = static_cast<int>(LexErrorKind::BadQuotedName);
    else if (c < 0x20 || c == 0x7f || (c >= 0x80 && c < 0xa0))
      e.kind = static_cast<int>(LexErrorKind::ControlChar);
    else
      e.kind = static_cast<int>(LexErrorKind::InvalidChar);
    errors_.push_back(e);
  }

private:
  const std::u32string &chars_;
  std::vector<Err> &errors_;
};

Lexed lexReference(std::string_view text) {
  SourceStream input(text);
  Lexed out;
  ReferenceListener listener(input, out.errors);
  lsdparser::LsdLexer lexer(&input);
  lexer.removeErrorListeners();
  lexer.addErrorListener(&listener);
  out.tokens = drain(lexer, input.chars().size() + 1);
  return out;
}

std::vector<size_t> types(std::string_view text) {
  std::vector<size_t> out;
  for (const Tok &t : lexOurs(text).tokens)
    out.push_back(t.type);
  return out;
}

const antlr4::dfa::Vocabulary &vocabulary() {
  static antlr4::ANTLRInputStream empty;
  static lsdparser::LsdLexer reference(&empty);
  return reference.getVocabulary();
}

size_t literalType(const std::string &literal) {
  const antlr4::dfa::Vocabulary &vocab = vocabulary();
  for (size_t t = 1; t <= vocab.getMaxTokenType(); ++t)
    if (vocab.getLiteralName(t) == "'" + literal + "'")
      return t;
  ADD_FAILURE() << "no literal " << literal;
  return 0;
}

constexpr size_t kEof = antlr4::Token::EOF;

// ------------------------------------------------------------ token kinds

TEST(Lexer, EveryLiteralOfTheVocabularyHasItsType) {
  const antlr4::dfa::Vocabulary &vocab = vocabulary();
  size_t literals = 0;
  for (size_t type = 1; type <= vocab.getMaxTokenType(); ++type) {
    std::string lit = vocab.getLiteralName(type);
    if (lit.empty())
      continue;
    ++literals;
    std::string text = lit.substr(1, lit.size() - 2);
    EXPECT_EQ(types(text), (std::vector<size_t>{type, kEof})) << text;
  }
  EXPECT_EQ(literals, 87u); // 27 operators, 59 keywords, '.*'
}

TEST(Lexer, Names) {
  EXPECT_EQ(types("x _a1 ender end_ End"),
            (std::vector<size_t>{P::IDENT, P::IDENT, P::IDENT, P::IDENT,
                                 P::IDENT, kEof}));
  EXPECT_EQ(types("end constrainedbyx"),
            (std::vector<size_t>{P::END, P::IDENT, kEof}));
  Lexed q = lexOurs(R"('r1.v' 'a\'b' 'a\\' 'Δx')");
  ASSERT_EQ(q.tokens.size(), 5u);
  EXPECT_TRUE(q.errors.empty());
  EXPECT_EQ(q.tokens[0].text, "'r1.v'");
  EXPECT_EQ(q.tokens[1].text, R"('a\'b')");
  EXPECT_EQ(q.tokens[2].text, R"('a\\')");
  EXPECT_EQ(q.tokens[3].text, "'Δx'");
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(q.tokens[i].type, P::IDENT);
  // An escape may take a line break into the name.
  Lexed nl = lexOurs("'a\\\nb' c");
  EXPECT_TRUE(nl.errors.empty());
  EXPECT_EQ(nl.tokens[1], (Tok{P::IDENT, 7, 7, 2, 3, "c"}));
}

TEST(Lexer, Numbers) {
  for (const char *n : {"1", "12", "1.", "1.5", ".5", "1e3", "1E+3", "1.e-3",
                        ".5e2", "0.25E10"}) {
    Lexed l = lexOurs(n);
    ASSERT_EQ(l.tokens.size(), 2u) << n;
    EXPECT_EQ(l.tokens[0].type, P::NUMBER) << n;
    EXPECT_EQ(l.tokens[0].text, n);
  }
  // An exponent without digits is not part of the number.
  EXPECT_EQ(types("1e"), (std::vector<size_t>{P::NUMBER, P::IDENT, kEof}));
  EXPECT_EQ(types("1e+"),
            (std::vector<size_t>{P::NUMBER, P::IDENT, literalType("+"), kEof}));
  EXPECT_EQ(types(".5.3"), (std::vector<size_t>{P::NUMBER, P::NUMBER, kEof}));
  EXPECT_EQ(types("1..2"), (std::vector<size_t>{P::NUMBER, P::NUMBER, kEof}));
  EXPECT_EQ(types("1.*2"), (std::vector<size_t>{P::NUMBER, literalType("*"),
                                                P::NUMBER, kEof}));
  EXPECT_EQ(types("a.*b"),
            (std::vector<size_t>{P::IDENT, P::DOTSTAR, P::IDENT, kEof}));
}

TEST(Lexer, Strings) {
  Lexed l = lexOurs(R"("" "a\"b" "x\\" "two
lines")");
  ASSERT_EQ(l.tokens.size(), 5u);
  EXPECT_TRUE(l.errors.empty());
  EXPECT_EQ(l.tokens[1].text, R"("a\"b")");
  EXPECT_EQ(l.tokens[2].text, R"("x\\")");
  EXPECT_EQ(l.tokens[3], (Tok{P::STRING, 16, 26, 1, 16, "\"two\nlines\""}));
  // An invalid byte in a string is read as U+FFFD.
  Lexed bad = lexOurs("\"caf\xe9\"");
  EXPECT_TRUE(bad.errors.empty());
  EXPECT_EQ(bad.tokens[0].text, "\"caf\xEF\xBF\xBD\"");
}

TEST(Lexer, OperatorsTakeTheLongestMatch) {
  EXPECT_EQ(types(":=:"),
            (std::vector<size_t>{literalType(":="), literalType(":"), kEof}));
  EXPECT_EQ(types("<>=<="), (std::vector<size_t>{literalType("<>"),
                                                 literalType("="),
                                                 literalType("<="), kEof}));
  EXPECT_EQ(types(".//"),
            (std::vector<size_t>{literalType("./"), literalType("/"), kEof}));
  EXPECT_EQ(types("===="),
            (std::vector<size_t>{literalType("=="), literalType("=="), kEof}));
}

// -------------------------------------------------------------- positions

TEST(Lexer, PositionsCountCharactersAndLines) {
  Lexed l = lexOurs("model 'Δ'\r\n  x\ry;");
  ASSERT_EQ(l.tokens.size(), 6u);
  EXPECT_EQ(l.tokens[0], (Tok{P::MODEL, 0, 4, 1, 0, "model"}));
  EXPECT_EQ(l.tokens[1], (Tok{P::IDENT, 6, 8, 1, 6, "'Δ'"}));
  EXPECT_EQ(l.tokens[2], (Tok{P::IDENT, 13, 13, 2, 2, "x"})); // after CR LF
  EXPECT_EQ(l.tokens[3], (Tok{P::IDENT, 15, 15, 3, 0, "y"})); // a lone CR
  EXPECT_EQ(l.tokens[5], (Tok{kEof, 17, 16, 3, 2, "<EOF>"}));
  // A byte-order mark is one column of white space.
  EXPECT_EQ(lexOurs("\xEF\xBB\xBFx").tokens[0], (Tok{P::IDENT, 1, 1, 1, 1, "x"}));
  EXPECT_EQ(lexOurs("").tokens[0].type, kEof);
}

TEST(Lexer, CommentsAndWhiteSpaceAreSkipped) {
  EXPECT_EQ(types(" \t\f\n// a 'line\nx /* a \"block */ y /**/ /*/ */ z"),
            (std::vector<size_t>{P::IDENT, P::IDENT, P::IDENT, kEof}));
  // A block comment ends at the first '*/'.
  EXPECT_EQ(types("/* a */ */"),
            (std::vector<size_t>{literalType("*"), literalType("/"), kEof}));
  // Without its end it is no comment: '/' '*' and the rest are tokens.
  Lexed open = lexOurs("x /* y");
  EXPECT_TRUE(open.errors.empty());
  EXPECT_EQ(types("x /* y"), (std::vector<size_t>{P::IDENT, literalType("/"),
                                                  literalType("*"), P::IDENT,
                                                  kEof}));
  // Invalid bytes are fine in comments.
  EXPECT_EQ(lexOurs("// caf\xe9\n/* \xff */x").errors.size(), 0u);
}

// ----------------------------------------------------------------- errors

Err err(LexErrorKind kind, size_t line, size_t column, char32_t value) {
  return {static_cast<int>(kind), line, column, value};
}

TEST(Lexer, UnterminatedStringRunsToTheEnd) {
  Lexed l = lexOurs("x = \"doc\n  y;\n");
  EXPECT_EQ(l.errors,
            (std::vector<Err>{err(LexErrorKind::UnterminatedString, 1, 4, '"')}));
  EXPECT_EQ(l.tokens.size(), 3u); // x = EOF
  EXPECT_EQ(lexOurs("\"a\\").errors.size(), 1u);
}

TEST(Lexer, BadQuotedNames) {
  // Empty: both quotes are skipped.
  Lexed empty = lexOurs("'' x");
  EXPECT_EQ(empty.errors,
            (std::vector<Err>{err(LexErrorKind::BadQuotedName, 1, 0, '\'')}));
  EXPECT_EQ(empty.tokens[0], (Tok{P::IDENT, 3, 3, 1, 3, "x"}));
  // Cut by a line end: the name and the line break are skipped.
  Lexed cut = lexOurs("a 'b c\nd");
  EXPECT_EQ(cut.errors,
            (std::vector<Err>{err(LexErrorKind::BadQuotedName, 1, 2, '\'')}));
  EXPECT_EQ(types("a 'b c\nd"), (std::vector<size_t>{P::IDENT, P::IDENT, kEof}));
  EXPECT_EQ(cut.tokens[1], (Tok{P::IDENT, 7, 7, 2, 0, "d"}));
  EXPECT_EQ(lexOurs("'a\\").errors.size(), 1u);
  EXPECT_EQ(lexOurs("'a").errors.size(), 1u);
}

TEST(Lexer, StrayCharacters) {
  Lexed l = lexOurs("a $\x01\xff!\xc2\x85@\n\0b"s);
  EXPECT_EQ(l.errors,
            (std::vector<Err>{err(LexErrorKind::InvalidChar, 1, 2, '$'),
                              err(LexErrorKind::ControlChar, 1, 3, 1),
                              err(LexErrorKind::InvalidUtf8, 1, 4, 0xff),
                              err(LexErrorKind::InvalidChar, 1, 5, '!'),
                              err(LexErrorKind::ControlChar, 1, 6, 0x85),
                              err(LexErrorKind::InvalidChar, 1, 7, '@'),
                              err(LexErrorKind::ControlChar, 2, 0, 0)}));
  EXPECT_EQ(types("a $\x01\xff!\xc2\x85@\n\0b"s),
            (std::vector<size_t>{P::IDENT, P::IDENT, kEof}));
}

TEST(Lexer, AHandlerThatThrowsStopsTheLexer) {
  SourceStream input("a $ b");
  Lexer lexer(input, [](const LexError &) { throw 1; });
  EXPECT_EQ(lexer.nextToken()->getType(), P::IDENT);
  EXPECT_THROW(lexer.nextToken(), int);
  EXPECT_EQ(lexer.errorCount(), 1u);
}

// ------------------------------------------- the same as ANTLR's lexer

std::vector<std::string> readCorpus() {
  return ldae::readTestCorpus(
      {"/examples", "/tests/lang", "/stdlib", "/tests/models"});
}

TEST(LexerMatchesAntlr, Corpus) {
  std::vector<std::string> corpus = readCorpus();
  ASSERT_GT(corpus.size(), 100u);
  for (const std::string &text : corpus)
    ASSERT_EQ(lexOurs(text), lexReference(text)) << text;
}

// Pieces that start, end or break tokens.
const std::string_view kPieces[] = {
    "'", "\"", "\\", "/*", "*/", "//", "\n", "\r", "\r\n", ".", "e", "E",
    "+", "-", "1", "0.", ".5", "*", "/", "=", ":", "<", ">", "^", "$", "\t",
    "\xff", "\xc3", "\xa9", "\xe2\x82", "\x01", std::string_view("\0", 1),
    "Δ", "end", "x", " ", "'a", "\"s", "\\'", "\\\"", "\xEF\xBB\xBF",
};

TEST(LexerMatchesAntlr, MutatedCorpus) {
  std::vector<std::string> corpus = readCorpus();
  std::mt19937 rng(13);
  auto pick = [&](size_t n) {
    return std::uniform_int_distribution<size_t>(0, n - 1)(rng);
  };
  for (int round = 0; round < 3000; ++round) {
    std::string text = corpus[pick(corpus.size())];
    if (text.size() > 3000)
      text.resize(3000);
    for (int k = 1 + static_cast<int>(pick(6)); k > 0; --k) {
      size_t at = text.empty() ? 0 : pick(text.size() + 1);
      std::string p(kPieces[pick(std::size(kPieces))]);
      if (pick(3) == 0 && at < text.size())
        text.erase(at, 1 + pick(std::min<size_t>(8, text.size() - at)));
      else
        text.insert(at, p);
    }
    ASSERT_EQ(lexOurs(text), lexReference(text)) << text;
  }
}

TEST(LexerMatchesAntlr, RandomPieces) {
  std::mt19937 rng(7);
  auto pick = [&](size_t n) {
    return std::uniform_int_distribution<size_t>(0, n - 1)(rng);
  };
  for (int round = 0; round < 40000; ++round) {
    std::string text;
    for (int k = static_cast<int>(pick(12)); k > 0; --k) {
      size_t piece = pick(std::size(kPieces) + 1);
      if (piece == std::size(kPieces))
        text += static_cast<char>(pick(256)); // any byte
      else
        text += kPieces[piece];
    }
    ASSERT_EQ(lexOurs(text), lexReference(text)) << text;
  }
}

} // namespace
