// Runs our lexer (Lexer.h) and the ANTLR parser on one file. Syntax errors
// go through our DiagnosticEngine with messages of our own wording (the
// ANTLR ones list whole token sets); the default recovery continues after an
// error so one run reports several. ANTLR exceptions and our own abort
// signals never leave this file.
#include "frontend/Parser.h"
#include "frontend/AstBuilder.h"
#include "frontend/Lexer.h"

#include "LsdParser.h"
#include "antlr4-runtime.h"
#include "support/Utf8.h"

#include <fmt/format.h>

#include <new>
#include <optional>
#include <unordered_map>

namespace ldae::frontend {
namespace {

using namespace antlr4;

/// Thrown to abandon a parse (too deep, too many errors); caught in parseFile.
struct AbortParse {};

constexpr unsigned kMaxSyntaxErrors = 20;

struct ErrorSink {
  uint32_t file;
  const SourceManager &sources;
  DiagnosticEngine &diags;
  unsigned count = 0;

  void report(DiagId id, size_t line, size_t col, uint32_t length,
              std::vector<std::string> args) {
    SourceLoc loc{file, static_cast<uint32_t>(line),
                  static_cast<uint32_t>(col + 1)};
    reportAt(id, SourceRange{loc, std::max<uint32_t>(1, length)},
             std::move(args));
  }
  /// At token `t`; the end of file is shown just after the last text, on a
  /// line the user can see, rather than on the empty line after it.
  void report(DiagId id, Token *t, uint32_t length,
              std::vector<std::string> args) {
    if (!t || t->getType() == Token::EOF)
      reportAt(id, SourceRange{sources.endOfText(file), 1}, std::move(args));
    else
      report(id, t->getLine(), t->getCharPositionInLine(), length,
             std::move(args));
  }
  void reportAt(DiagId id, SourceRange range, std::vector<std::string> args) {
    diags.report(id, range, std::move(args));
    if (++count >= kMaxSyntaxErrors)
      throw AbortParse{};
  }
};

/// A token as messages show it: 'x', or "end of file".
std::string describeToken(Token *t) {
  if (!t || t->getType() == Token::EOF)
    return "end of file";
  std::string text = t->getText();
  if (utf8::countChars(text) > 40)
    text = std::string(utf8::prefixChars(text, 37)) + "...";
  return "'" + text + "'";
}

std::string describeTokenType(const dfa::Vocabulary &vocab, size_t type) {
  if (type == Token::EOF)
    return "end of file";
  if (type == lsdparser::LsdParser::IDENT)
    return "a name";
  if (type == lsdparser::LsdParser::NUMBER)
    return "a number";
  if (type == lsdparser::LsdParser::STRING)
    return "a string";
  std::string lit = vocab.getLiteralName(type);
  return lit.empty() ? vocab.getSymbolicName(type) : lit;
}

/// "';'", "';' or ','", or "" when the set is too large to be helpful.
std::string describeExpected(Parser *p, const misc::IntervalSet &set) {
  std::vector<ssize_t> types = set.toList();
  if (types.empty() || types.size() > 3)
    return "";
  std::string s;
  for (size_t i = 0; i < types.size(); ++i) {
    if (i)
      s += i + 1 == types.size() ? " or " : ", ";
    s += describeTokenType(p->getVocabulary(), static_cast<size_t>(types[i]));
  }
  return s;
}

uint32_t tokenLength(Token *t) {
  if (!t || t->getType() == Token::EOF)
    return 1;
  std::string text = t->getText();
  size_t nl = text.find('\n');
  return static_cast<uint32_t>(
      utf8::countChars(std::string_view(text).substr(0, nl)));
}

/// Words every syntax error itself and reports it to the sink.
class ErrorStrategy : public DefaultErrorStrategy {
public:
  explicit ErrorStrategy(ErrorSink &sink) : sink_(sink) {}

protected:
  void reportNoViableAlternative(Parser *p,
                                 const NoViableAltException &e) override {
    reportUnexpected(p, e.getOffendingToken(), e.getExpectedTokens());
  }
  void reportInputMismatch(Parser *p, const InputMismatchException &e) override {
    reportUnexpected(p, e.getOffendingToken(), e.getExpectedTokens());
  }
  void reportFailedPredicate(Parser *p,
                             const FailedPredicateException &e) override {
    reportUnexpected(p, e.getOffendingToken(), misc::IntervalSet());
  }
  void reportUnwantedToken(Parser *p) override {
    if (inErrorRecoveryMode(p))
      return;
    beginErrorCondition(p);
    reportUnexpected(p, p->getCurrentToken(), getExpectedTokens(p));
  }
  void reportMissingToken(Parser *p) override {
    if (inErrorRecoveryMode(p))
      return;
    beginErrorCondition(p);
    Token *t = p->getCurrentToken();
    std::string expected = describeExpected(p, getExpectedTokens(p));
    if (expected.empty())
      expected = "more input";
    sink_.report(DiagId::ErrSyntaxMissing, t, tokenLength(t),
                 {expected, describeToken(t)});
  }

  /// Never drop a ';' to repair an expression: the error is before it, and
  /// keeping it lets the next equation parse on its own.
  Token *singleTokenDeletion(Parser *p) override {
    if (p->getCurrentToken()->getText() == ";")
      return nullptr;
    return DefaultErrorStrategy::singleTokenDeletion(p);
  }

private:
  void reportUnexpected(Parser *p, Token *t, const misc::IntervalSet &set) {
    std::string expected = describeExpected(p, set);
    if (expected.empty())
      sink_.report(DiagId::ErrSyntaxUnexpected, t, tokenLength(t),
                   {describeToken(t)});
    else
      sink_.report(DiagId::ErrSyntaxUnexpectedExpected, t, tokenLength(t),
                   {describeToken(t), expected});
  }
  ErrorSink &sink_;
};

/// Lexer errors in our wording (ANTLR's only said "token recognition
/// error at: 'x'").
void reportLexError(ErrorSink &sink, const LexError &e) {
  switch (e.kind) {
  case LexErrorKind::InvalidUtf8:
    sink.report(DiagId::ErrInvalidUtf8, e.line, e.column, 1,
                {fmt::format("{:02x}", static_cast<uint32_t>(e.value))});
    break;
  case LexErrorKind::UnterminatedString:
    sink.report(DiagId::ErrLexUnterminated, e.line, e.column, 1, {"string"});
    break;
  case LexErrorKind::BadQuotedName:
    sink.report(DiagId::ErrLexBadQuotedName, e.line, e.column, 1, {});
    break;
  case LexErrorKind::ControlChar:
    sink.report(DiagId::ErrLexControlChar, e.line, e.column, 1,
                {fmt::format("{:04X}", static_cast<uint32_t>(e.value))});
    break;
  case LexErrorKind::InvalidChar: {
    std::string text;
    utf8::append(text, e.value);
    sink.report(DiagId::ErrLexInvalidChar, e.line, e.column, 1, {text});
    break;
  }
  }
}

/// The generated parser with a bound on rule nesting, so adversarial input
/// (ten thousand parentheses) gets a diagnostic instead of a stack overflow.
class GuardedParser : public lsdparser::LsdParser {
public:
  using LsdParser::LsdParser;
  bool tooDeep = false;
  Token *deepToken = nullptr;

  void enterRule(ParserRuleContext *ctx, size_t state,
                 size_t ruleIndex) override {
    if (depthOf(ctx) > kMaxParseDepth) {
      tooDeep = true;
      deepToken = getCurrentToken();
      throw AbortParse{};
    }
    LsdParser::enterRule(ctx, state, ruleIndex);
  }
  void enterOuterAlt(ParserRuleContext *ctx, size_t alt) override {
    LsdParser::enterOuterAlt(ctx, alt);
    depthOf(ctx);
  }

private:
  unsigned depthOf(tree::ParseTree *ctx) {
    if (!ctx)
      return 0;
    auto it = depth_.find(ctx);
    if (it != depth_.end())
      return it->second;
    unsigned d = depthOf(ctx->parent) + 1;
    depth_[ctx] = d;
    return d;
  }
  std::unordered_map<tree::ParseTree *, unsigned> depth_;
};

/// The parse of a file without syntax errors, the common case, done the
/// fast way (ANTLR's two-stage strategy): SLL prediction, no recovery, and
/// nothing reported. Unset when the file has an error (or nests too
/// deeply): the caller then parses it again with reportingParse, which
/// words every error exactly as a single parse would. SLL either gives the
/// tree full LL gives or fails, so the tree is the same.
std::optional<std::unique_ptr<ast::StoredDefinition>>
quickParse(uint32_t fileId, const SourceManager &sources,
           DiagnosticEngine &diags) {
  SourceStream input(sources.text(fileId));
  Lexer lexer(input);
  CommonTokenStream tokens(&lexer);
  tokens.fill();
  if (lexer.errorCount() != 0)
    return std::nullopt;
  GuardedParser parser(&tokens);
  parser.removeErrorListeners();
  parser.setErrorHandler(std::make_shared<BailErrorStrategy>());
  parser.getInterpreter<atn::ParserATNSimulator>()->setPredictionMode(
      atn::PredictionMode::SLL);
  ParserRuleContext *tree = nullptr;
  try {
    tree = parser.storedDefinition();
  } catch (const std::bad_alloc &) {
    throw;
  } catch (...) {
    return std::nullopt; // ParseCancellationException, AbortParse...
  }
  return buildAst(tree, fileId, input.chars(), diags);
}

/// The parse that recovers from syntax errors and reports them.
std::unique_ptr<ast::StoredDefinition>
reportingParse(uint32_t fileId, const SourceManager &sources,
               DiagnosticEngine &diags) {
  ErrorSink sink{fileId, sources, diags};
  SourceStream input(sources.text(fileId));
  Lexer lexer(input, [&sink](const LexError &e) { reportLexError(sink, e); });
  CommonTokenStream tokens(&lexer);
  GuardedParser parser(&tokens);
  parser.removeErrorListeners();
  parser.setErrorHandler(std::make_shared<ErrorStrategy>(sink));

  ParserRuleContext *tree = nullptr;
  try {
    tree = parser.storedDefinition();
  } catch (const AbortParse &) {
    if (parser.tooDeep) {
      Token *t = parser.deepToken;
      sink.count = 0; // always report the reason of the abort
      try {
        sink.report(DiagId::ErrNestingTooDeep, t, 1,
                    {std::to_string(kMaxParseDepth)});
      } catch (const AbortParse &) {
      }
    }
    return nullptr;
  } catch (const std::bad_alloc &) {
    throw; // out of memory is not a syntax error: the driver reports it
  } catch (const std::exception &e) {
    // The runtime should not throw past its error strategy; if it does,
    // the input is still the user's problem, not a crash.
    diags.report(DiagId::ErrSyntaxUnexpected, SourceLoc{fileId, 1, 1},
                 {std::string("input (") + e.what() + ")"});
    return nullptr;
  }
  if (sink.count != 0)
    return nullptr;
  return buildAst(tree, fileId, input.chars(), diags);
}

} // namespace

std::unique_ptr<ast::StoredDefinition>
parseFile(uint32_t fileId, const SourceManager &sources,
          DiagnosticEngine &diags) {
  // A UTF-16 file (a byte order mark, or ASCII with NULs between) is said
  // once for what it is, not as an invalid UTF-8 byte on every line.
  const std::string &text = sources.text(fileId);
  if (text.size() >= 2 &&
      ((text[0] == '\xff' && text[1] == '\xfe') ||
       (text[0] == '\xfe' && text[1] == '\xff') ||
       (text[0] != '\0' && text[1] == '\0') ||
       (text[0] == '\0' && text[1] != '\0'))) {
    diags.report(DiagId::ErrUtf16Source, SourceLoc{fileId, 1, 1}, {});
    return nullptr;
  }
  if (auto tree = quickParse(fileId, sources, diags))
    return std::move(*tree);
  return reportingParse(fileId, sources, diags);
}

} // namespace ldae::frontend
