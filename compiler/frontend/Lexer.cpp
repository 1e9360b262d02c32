// The lexer rules of grammar/Lsd.g4 as code. ANTLR's lexer takes the longest
// match over all rules (the earliest rule on a tie, so keywords beat IDENT)
// and falls back to the longest prefix it accepted; when it accepted none,
// it reports the token's first character and resumes one character past
// the point where the match died. Each case below follows that rule.
#include "frontend/Lexer.h"

#include "CommonTokenFactory.h"
#include "LsdParser.h"
#include "support/Utf8.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace ldae::frontend {
namespace {

/// The literal tokens of the grammar with their types, from the Lsd.tokens
/// file the ANTLR tool writes, so the types always match the parser's.
struct Literal {
  std::string_view text;
  size_t type;
};
constexpr Literal kLiterals[] = {
#include "LsdLiterals.inc"
};

consteval size_t literal(std::string_view text) {
  for (const Literal &l : kLiterals)
    if (l.text == text)
      return l.type;
  throw std::logic_error("not a literal token of grammar/Lsd.g4");
}

using Types = lsdparser::LsdParser;
constexpr size_t kIdent = Types::IDENT;

constexpr bool isKeyword(std::string_view text) {
  return !text.empty() && text[0] >= 'a' && text[0] <= 'z';
}

constexpr auto kKeywords = [] {
  constexpr size_t n = std::count_if(
      std::begin(kLiterals), std::end(kLiterals),
      [](const Literal &l) { return isKeyword(l.text); });
  std::array<Literal, n> out{};
  size_t i = 0;
  for (const Literal &l : kLiterals)
    if (isKeyword(l.text))
      out[i++] = l;
  std::sort(out.begin(), out.end(),
            [](const Literal &a, const Literal &b) { return a.text < b.text; });
  return out;
}();

constexpr size_t kLongestKeyword = [] {
  size_t n = 0;
  for (const Literal &l : kKeywords)
    n = std::max(n, l.text.size());
  return n;
}();

/// The type of each operator of one character that starts no longer token.
constexpr auto kOneChar = [] {
  std::array<size_t, 128> types{};
  for (char c : std::string_view(";(),*{}[]+-^"))
    for (const Literal &l : kLiterals)
      if (l.text == std::string_view(&c, 1))
        types[static_cast<unsigned char>(c)] = l.type;
  return types;
}();

constexpr char32_t kEof = ~char32_t(0);

bool isDigit(char32_t c) { return c >= '0' && c <= '9'; }
bool isIdentStart(char32_t c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
bool isIdentPart(char32_t c) { return isIdentStart(c) || isDigit(c); }
bool isSpace(char32_t c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f';
}

/// IDENT, or the keyword spelled by `name` (ASCII: IDENT admits no more).
size_t identType(std::u32string_view name) {
  if (name.size() > kLongestKeyword)
    return kIdent;
  char buf[kLongestKeyword];
  for (size_t i = 0; i < name.size(); ++i)
    buf[i] = static_cast<char>(name[i]);
  std::string_view key(buf, name.size());
  auto it = std::lower_bound(
      kKeywords.begin(), kKeywords.end(), key,
      [](const Literal &l, std::string_view k) { return l.text < k; });
  return it != kKeywords.end() && it->text == key ? it->type : kIdent;
}

LexErrorKind classify(char32_t c) {
  if (utf8::isEscapedByte(c))
    return LexErrorKind::InvalidUtf8;
  if (c < 0x20 || c == 0x7f || (c >= 0x80 && c < 0xa0))
    return LexErrorKind::ControlChar;
  return LexErrorKind::InvalidChar;
}

} // namespace

SourceStream::SourceStream(std::string_view text) {
  _data.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    utf8::Char c = utf8::decodeAt(text, i);
    char32_t cp = c.cp;
    if (cp == '\r' && (i + 1 == text.size() || text[i + 1] != '\n'))
      cp = '\n';
    else if (cp == 0xFEFF && i == 0)
      cp = ' '; // a byte-order mark: one column, like the renderer's
    _data.push_back(cp);
    i += c.bytes;
  }
}

std::string SourceStream::getText(const antlr4::misc::Interval &iv) {
  if (iv.a < 0 || iv.b < iv.a || static_cast<size_t>(iv.a) >= _data.size())
    return "";
  size_t stop = std::min(static_cast<size_t>(iv.b), _data.size() - 1);
  std::string out;
  for (size_t i = static_cast<size_t>(iv.a); i <= stop; ++i)
    utf8::append(out, _data[i]);
  return out;
}

Lexer::Lexer(SourceStream &input, ErrorHandler onError)
    : input_(input), text_(input.chars()), onError_(std::move(onError)) {}

antlr4::TokenFactory<antlr4::CommonToken> *Lexer::getTokenFactory() {
  return antlr4::CommonTokenFactory::DEFAULT.get();
}

char32_t Lexer::at(size_t i) const {
  return i < text_.size() ? text_[i] : kEof;
}

std::unique_ptr<antlr4::Token> Lexer::nextToken() {
  for (;;) {
    size_t start = pos_, line = line_, column = column_;
    Match m = start < text_.size() ? match(start)
                                   : Match{antlr4::Token::EOF, start};
    if (m.type == kError) {
      ++errors_;
      if (onError_)
        onError_(LexError{m.error, line, column,
                          m.error == LexErrorKind::InvalidUtf8
                              ? utf8::escapedByte(text_[start])
                              : text_[start]});
    }
    advanceTo(m.end);
    if (m.type == kSkip || m.type == kError)
      continue;
    // The stop index of the end-of-file token is start - 1, as ANTLR's.
    auto token = std::make_unique<antlr4::CommonToken>(
        std::make_pair(this, &input_), m.type,
        antlr4::Token::DEFAULT_CHANNEL, start, m.end - 1);
    token->setLine(line);
    token->setCharPositionInLine(column);
    return token;
  }
}

void Lexer::advanceTo(size_t end) {
  for (; pos_ < end; ++pos_) {
    if (text_[pos_] == '\n') {
      ++line_;
      column_ = 0;
    } else {
      ++column_;
    }
  }
}

Lexer::Match Lexer::match(size_t p) const {
  char32_t c = text_[p];
  auto op = [&](size_t type, size_t length) { return Match{type, p + length}; };
  if (isSpace(c)) {
    size_t q = p + 1;
    while (isSpace(at(q)))
      ++q;
    return {kSkip, q};
  }
  if (isIdentStart(c)) {
    size_t q = p + 1;
    while (isIdentPart(at(q)))
      ++q;
    return {identType(std::u32string_view(text_).substr(p, q - p)), q};
  }
  if (isDigit(c))
    return {Types::NUMBER, numberEnd(p, true)};
  char32_t next = at(p + 1);
  switch (c) {
  case '\'':
    return quotedName(p);
  case '"':
    return stringLiteral(p);
  case '/':
    return slash(p);
  case '.':
    if (isDigit(next))
      return {Types::NUMBER, numberEnd(p + 1, false)};
    switch (next) {
    case '*': return op(Types::DOTSTAR, 2);
    case '+': return op(literal(".+"), 2);
    case '-': return op(literal(".-"), 2);
    case '/': return op(literal("./"), 2);
    case '^': return op(literal(".^"), 2);
    default: return op(literal("."), 1);
    }
  case ':':
    return next == '=' ? op(literal(":="), 2) : op(literal(":"), 1);
  case '=':
    return next == '=' ? op(literal("=="), 2) : op(literal("="), 1);
  case '>':
    return next == '=' ? op(literal(">="), 2) : op(literal(">"), 1);
  case '<':
    if (next == '=')
      return op(literal("<="), 2);
    if (next == '>')
      return op(literal("<>"), 2);
    return op(literal("<"), 1);
  default:
    if (c < kOneChar.size() && kOneChar[c] != 0)
      return op(kOneChar[c], 1);
    return failAt(p, classify(c));
  }
}

/// DIGITS ('.' DIGITS?)? EXPONENT? from the first digit, without the
/// fraction after a leading '.'; an exponent without digits is left out, as
/// ANTLR falls back to the number before it.
size_t Lexer::numberEnd(size_t q, bool fraction) const {
  auto digits = [&](size_t i) {
    while (isDigit(at(i)))
      ++i;
    return i;
  };
  q = digits(q);
  if (fraction && at(q) == '.')
    q = digits(q + 1);
  if (at(q) == 'e' || at(q) == 'E') {
    size_t e = q + 1;
    if (at(e) == '+' || at(e) == '-')
      ++e;
    if (isDigit(at(e)))
      q = digits(e);
  }
  return q;
}

/// '\'' (~['\\\r\n] | '\\' .)+ '\''
Lexer::Match Lexer::quotedName(size_t p) const {
  for (size_t q = p + 1;;) {
    char32_t c = at(q);
    if (c == '\'' && q > p + 1)
      return {kIdent, q + 1};
    if (c == kEof || c == '\'' || c == '\r' || c == '\n')
      return failAt(q, LexErrorKind::BadQuotedName);
    if (c == '\\') {
      if (at(q + 1) == kEof)
        return failAt(q + 1, LexErrorKind::BadQuotedName);
      q += 2;
    } else {
      ++q;
    }
  }
}

/// '"' (~["\\] | '\\' .)* '"': only the end of the file stops it.
Lexer::Match Lexer::stringLiteral(size_t p) const {
  for (size_t q = p + 1;;) {
    char32_t c = at(q);
    if (c == '"')
      return {Types::STRING, q + 1};
    if (c == kEof || (c == '\\' && at(q + 1) == kEof))
      return failAt(text_.size(), LexErrorKind::UnterminatedString);
    q += c == '\\' ? 2 : 1;
  }
}

/// '/', a line comment, or a block comment. A block comment without its
/// '*/' is no error: the longest token ANTLR accepted is the '/' itself.
Lexer::Match Lexer::slash(size_t p) const {
  char32_t next = at(p + 1);
  if (next == '/') {
    size_t q = p + 2;
    while (q < text_.size() && text_[q] != '\r' && text_[q] != '\n')
      ++q;
    return {kSkip, q};
  }
  if (next == '*') {
    std::u32string_view rest = std::u32string_view(text_).substr(p + 2);
    size_t close = rest.find(U"*/");
    if (close != std::u32string_view::npos)
      return {kSkip, p + 2 + close + 2};
  }
  return {literal("/"), p + 1};
}

/// No token starts here: the match died at `stop`, and recovery skips the
/// character there too.
Lexer::Match Lexer::failAt(size_t stop, LexErrorKind kind) const {
  return {kError, std::min(stop + 1, text_.size()), kind};
}

} // namespace ldae::frontend
