// Runs ANTLR on one file. Syntax errors go through our DiagnosticEngine with
// messages of our own wording (the ANTLR ones list whole token sets); the
// default recovery continues after an error so one run reports several.
// ANTLR exceptions and our own abort signals never leave this file.
#include "frontend/Parser.h"
#include "frontend/AstBuilder.h"

#include "LsdLexer.h"
#include "LsdParser.h"
#include "antlr4-runtime.h"

#include <unordered_map>

namespace ldae::frontend {
namespace {

using namespace antlr4;

/// Thrown to abandon a parse (too deep, too many errors); caught in parseFile.
struct AbortParse {};

constexpr unsigned kMaxSyntaxErrors = 20;

struct ErrorSink {
  uint32_t file;
  DiagnosticEngine &diags;
  unsigned count = 0;

  void report(DiagId id, size_t line, size_t col, uint32_t length,
              std::vector<std::string> args) {
    SourceLoc loc{file, static_cast<uint32_t>(line),
                  static_cast<uint32_t>(col + 1)};
    diags.report(id, SourceRange{loc, std::max<uint32_t>(1, length)},
                 std::move(args));
    if (++count >= kMaxSyntaxErrors)
      throw AbortParse{};
  }
};

/// A token as messages show it: 'x', or "end of file".
std::string describeToken(Token *t) {
  if (!t || t->getType() == Token::EOF)
    return "end of file";
  std::string text = t->getText();
  if (text.size() > 40)
    text = text.substr(0, 37) + "...";
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
  return static_cast<uint32_t>(nl == std::string::npos ? text.size() : nl);
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
    sink_.report(DiagId::ErrSyntaxMissing, t->getLine(),
                 t->getCharPositionInLine(), tokenLength(t),
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
      sink_.report(DiagId::ErrSyntaxUnexpected, t->getLine(),
                   t->getCharPositionInLine(), tokenLength(t),
                   {describeToken(t)});
    else
      sink_.report(DiagId::ErrSyntaxUnexpectedExpected, t->getLine(),
                   t->getCharPositionInLine(), tokenLength(t),
                   {describeToken(t), expected});
  }
  ErrorSink &sink_;
};

/// Lexer errors: ANTLR says "token recognition error at: 'x'".
class LexerListener : public BaseErrorListener {
public:
  explicit LexerListener(ErrorSink &sink) : sink_(sink) {}
  void syntaxError(Recognizer *, Token *, size_t line, size_t col,
                   const std::string &msg, std::exception_ptr) override {
    std::string text;
    size_t at = msg.find("at: '");
    if (at != std::string::npos && msg.size() >= at + 6)
      text = msg.substr(at + 5, msg.size() - at - 6);
    if (text.rfind("\"", 0) == 0)
      sink_.report(DiagId::ErrLexUnterminated, line, col, 1, {"string"});
    else if (text.rfind("/*", 0) == 0)
      sink_.report(DiagId::ErrLexUnterminated, line, col, 2, {"comment"});
    else if (text.rfind("'", 0) == 0)
      sink_.report(DiagId::ErrLexBadQuotedName, line, col, 1, {});
    else
      sink_.report(DiagId::ErrLexInvalidChar, line, col, 1,
                   {text.empty() ? "?" : text.substr(0, 1)});
  }

private:
  ErrorSink &sink_;
};

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

} // namespace

std::unique_ptr<ast::StoredDefinition>
parseFile(uint32_t fileId, const SourceManager &sources,
          DiagnosticEngine &diags) {
  ErrorSink sink{fileId, diags};
  ANTLRInputStream input(sources.text(fileId));
  lsdparser::LsdLexer lexer(&input);
  LexerListener lexerListener(sink);
  lexer.removeErrorListeners();
  lexer.addErrorListener(&lexerListener);
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
        sink.report(DiagId::ErrNestingTooDeep, t ? t->getLine() : 1,
                    t ? t->getCharPositionInLine() : 0, 1,
                    {std::to_string(kMaxParseDepth)});
      } catch (const AbortParse &) {
      }
    }
    return nullptr;
  } catch (const std::exception &e) {
    // The runtime should not throw past its error strategy; if it does,
    // the input is still the user's problem, not a crash.
    diags.report(DiagId::ErrSyntaxUnexpected, SourceLoc{fileId, 1, 1},
                 {std::string("input (") + e.what() + ")"});
    return nullptr;
  }
  if (sink.count != 0)
    return nullptr;
  return buildAst(tree, fileId, sources, diags);
}

} // namespace ldae::frontend
