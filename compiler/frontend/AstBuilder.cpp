// ANTLR parse tree -> AST. Runs only on trees without syntax errors, so every
// mandatory child is present. Constructs that parse but that ldaec does not
// implement are reported here, once, with their location.
#include "frontend/AstBuilder.h"

#include "LsdParser.h"
#include "antlr4-runtime.h"
#include "support/Utf8.h"

#include <cmath>
#include <cstdlib>
#include <unordered_map>

namespace ldae::frontend {
namespace {

using namespace lsdparser;
using antlr4::ParserRuleContext;
using antlr4::Token;
using antlr4::tree::ParseTree;
using antlr4::tree::TerminalNode;

class AstBuilder {
public:
  AstBuilder(uint32_t file, const std::u32string &chars,
             DiagnosticEngine &diags)
      : file_(file), text_(chars), diags_(diags) {}

  std::unique_ptr<ast::StoredDefinition>
  build(LsdParser::StoredDefinitionContext *ctx) {
    auto def = std::make_unique<ast::StoredDefinition>();
    def->file = file_;
    if (auto *w = ctx->withinClause()) {
      def->hasWithin = true;
      if (w->name())
        def->within = name(w->name());
      def->within.loc = loc(w);
      def->within.length = length(w);
    }
    for (auto *c : ctx->classDefinition())
      def->classes.push_back(classDefinition(c, nullptr));
    checkUnique(def->classes, nullptr, "this file");
    return def;
  }

private:
  // ---------------------------------------------------------- locations
  SourceLoc loc(Token *t) const {
    return SourceLoc{file_, static_cast<uint32_t>(t->getLine()),
                     static_cast<uint32_t>(t->getCharPositionInLine() + 1)};
  }
  SourceLoc loc(ParserRuleContext *c) const { return loc(c->getStart()); }
  SourceLoc loc(TerminalNode *n) const { return loc(n->getSymbol()); }

  /// Columns from the start of `c` to its end, or to the end of its first
  /// line when it spans several. Token indices count characters, as
  /// `text_` does.
  uint32_t length(ParserRuleContext *c) const {
    Token *a = c->getStart(), *b = c->getStop();
    if (!a || !b || b->getStopIndex() < a->getStartIndex())
      return 1;
    size_t begin = a->getStartIndex(), end = b->getStopIndex() + 1;
    // On one line (the common case) no scan: scanning every node of a
    // 100,000-term line to its end would be quadratic.
    if (a->getLine() == b->getLine() &&
        b->getText().find('\n') == std::string::npos)
      return static_cast<uint32_t>(std::max<size_t>(1, end - begin));
    size_t nl = text_.find('\n', begin);
    if (nl != std::string::npos && nl < end)
      end = nl;
    return static_cast<uint32_t>(std::max<size_t>(1, end - begin));
  }

  /// The source text of `c` with runs of whitespace collapsed to one space.
  std::string sourceText(ParserRuleContext *c) const {
    Token *a = c->getStart(), *b = c->getStop();
    if (!a || !b || b->getStopIndex() < a->getStartIndex() ||
        b->getStopIndex() >= text_.size())
      return "";
    std::string out;
    bool space = false;
    for (size_t i = a->getStartIndex(); i <= b->getStopIndex(); ++i) {
      char32_t ch = text_[i];
      if (ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r') {
        space = true;
        continue;
      }
      if (space && !out.empty())
        out += ' ';
      space = false;
      utf8::append(out, ch);
    }
    return out;
  }

  /// The classes and components of one class (or the classes of a file)
  /// share one namespace: a second declaration of a name is an error with
  /// a note at the first, whatever the kinds and types.
  void checkUnique(const std::vector<std::unique_ptr<ast::ClassDef>> &classes,
                   const std::vector<ast::Component> *components,
                   const std::string &where) {
    std::unordered_map<std::string, SourceLoc> first;
    auto check = [&](const std::string &name, SourceLoc at, uint32_t length) {
      auto [it, added] = first.emplace(name, at);
      if (added)
        return;
      Diagnostic &d = diags_.report(DiagId::ErrDeclaredTwice,
                                    SourceRange{at, length}, {name, where});
      DiagnosticEngine::addNote(d, it->second, DiagId::NoteDeclaredHere,
                                {name});
    };
    for (const auto &c : classes)
      check(c->name, c->loc, c->length);
    if (components)
      for (const ast::Component &c : *components)
        check(c.name, c.loc, c.length);
  }

  void unsupported(SourceLoc where, const std::string &what) {
    diags_.report(DiagId::ErrUnsupported, where, {what});
  }

  // ------------------------------------------------------------ names
  static std::string ident(TerminalNode *n) { return identText(n->getText()); }
  /// A quoted identifier 'r1.v' names `r1.v`.
  static std::string identText(const std::string &s) {
    if (s.size() >= 2 && s.front() == '\'') {
      std::string out;
      for (size_t i = 1; i + 1 < s.size(); ++i) {
        if (s[i] == '\\' && i + 2 < s.size())
          ++i;
        out += s[i];
      }
      return out;
    }
    return s;
  }

  ast::Name name(LsdParser::NameContext *c, bool global = false) {
    ast::Name n;
    n.global = global;
    n.loc = loc(c);
    n.length = length(c);
    for (auto *id : c->IDENT())
      n.parts.push_back(ident(id));
    return n;
  }

  ast::Name typeSpecifier(LsdParser::TypeSpecifierContext *c) {
    bool global = c->children.size() > 1;
    ast::Name n = name(c->name(), global);
    n.loc = loc(c);
    n.length = length(c);
    return n;
  }

  std::string stringComment(LsdParser::StringCommentContext *c) {
    std::string s;
    if (!c)
      return s;
    for (auto *str : c->STRING())
      s += unquote(str->getText());
    return s;
  }

  static std::string unquote(const std::string &s) {
    std::string out;
    for (size_t i = 1; i + 1 < s.size(); ++i) {
      if (s[i] == '\\' && i + 2 < s.size()) {
        ++i;
        switch (s[i]) {
        case 'n':
          out += '\n';
          break;
        case 't':
          out += '\t';
          break;
        default:
          out += s[i];
        }
        continue;
      }
      out += s[i];
    }
    return out;
  }

  // ---------------------------------------------------------- classes
  std::unique_ptr<ast::ClassDef>
  classDefinition(LsdParser::ClassDefinitionContext *c, ast::ClassDef *parent) {
    auto cls = std::make_unique<ast::ClassDef>();
    cls->parent = parent;
    cls->file = file_;
    cls->encapsulated = c->ENCAPSULATED() != nullptr;
    auto *p = c->classPrefixes();
    cls->partial = p->PARTIAL() != nullptr;
    cls->impure = p->IMPURE() != nullptr;
    cls->expandable = p->EXPANDABLE() != nullptr;
    if (p->MODEL())
      cls->kind = ast::ClassKind::Model;
    else if (p->CLASS())
      cls->kind = ast::ClassKind::Class;
    else if (p->RECORD())
      cls->kind = ast::ClassKind::Record;
    else if (p->BLOCK())
      cls->kind = ast::ClassKind::Block;
    else if (p->CONNECTOR())
      cls->kind = ast::ClassKind::Connector;
    else if (p->TYPE())
      cls->kind = ast::ClassKind::Type;
    else if (p->PACKAGE())
      cls->kind = ast::ClassKind::Package;
    else if (p->FUNCTION())
      cls->kind = ast::ClassKind::Function;
    else
      cls->kind = ast::ClassKind::Operator;

    auto *spec = c->classSpecifier();
    cls->loc = loc(spec);
    if (auto *lc = dynamic_cast<LsdParser::LongClassContext *>(spec)) {
      cls->name = ident(lc->IDENT(0));
      cls->length = static_cast<uint32_t>(utf8::countChars(lc->IDENT(0)->getText()));
      cls->description = stringComment(lc->stringComment());
      if (lc->endName) {
        std::string endName = identText(lc->endName->getText());
        if (endName != cls->name)
          diags_.report(DiagId::ErrEndNameMismatch, loc(lc->endName),
                        {endName, cls->name});
      }
      composition(lc->composition(), *cls);
      checkUnique(cls->classes, &cls->components, ldae::quoted(cls->name));
    } else if (auto *sc = dynamic_cast<LsdParser::ShortClassContext *>(spec)) {
      cls->name = ident(sc->IDENT());
      cls->length = static_cast<uint32_t>(utf8::countChars(sc->IDENT()->getText()));
      cls->isShort = true;
      auto *bp = sc->basePrefix();
      if (bp->INPUT())
        cls->shortPrefix.causality = ast::Causality::Input;
      else if (bp->OUTPUT())
        cls->shortPrefix.causality = ast::Causality::Output;
      cls->shortBase = typeSpecifier(sc->typeSpecifier());
      if (sc->arraySubscripts())
        cls->shortDims = subscripts(sc->arraySubscripts());
      if (sc->classModification()) {
        cls->shortMod = std::make_unique<ast::Modification>();
        cls->shortMod->loc = loc(sc->classModification());
        classModification(sc->classModification(), *cls->shortMod);
      }
      cls->description = stringComment(sc->comment()->stringComment());
    } else if (auto *ec = dynamic_cast<LsdParser::EnumClassContext *>(spec)) {
      cls->name = ident(ec->IDENT());
      cls->isEnumeration = true;
      if (ec->enumList())
        for (auto *lit : ec->enumList()->enumLiteral())
          cls->enumLiterals.push_back(ident(lit->IDENT()));
    } else if (auto *xc = dynamic_cast<LsdParser::ExtendsClassContext *>(spec)) {
      cls->name = ident(xc->IDENT(0));
      unsupported(loc(xc), "'extends' class redefinitions");
      composition(xc->composition(), *cls);
    }
    return cls;
  }

  void composition(LsdParser::CompositionContext *c, ast::ClassDef &cls) {
    bool isProtected = false;
    for (ParseTree *child : c->children) {
      if (auto *t = dynamic_cast<TerminalNode *>(child)) {
        size_t type = t->getSymbol()->getType();
        if (type == LsdParser::PUBLIC)
          isProtected = false;
        else if (type == LsdParser::PROTECTED)
          isProtected = true;
        else if (type == LsdParser::EXTERNAL) {
          cls.isExternal = true;
          cls.external.loc = loc(t);
          cls.external.length = 8;
        }
      } else if (auto *ls = dynamic_cast<LsdParser::LanguageSpecificationContext *>(child)) {
        cls.external.language = unquote(ls->STRING()->getText());
      } else if (auto *xc = dynamic_cast<LsdParser::ExternalCallContext *>(child)) {
        cls.external.loc = loc(xc);
        cls.external.length = length(xc);
        if (xc->componentReference())
          cls.external.output = componentReference(xc->componentReference());
        cls.external.function = ident(xc->IDENT());
        if (xc->expressionList())
          for (auto *x : xc->expressionList()->expression())
            cls.external.args.push_back(expression(x));
      } else if (auto *el = dynamic_cast<LsdParser::ElementListContext *>(child)) {
        for (auto *e : el->element())
          element(e, cls, isProtected);
      } else if (auto *eq = dynamic_cast<LsdParser::EquationSectionContext *>(child)) {
        auto &list = eq->INITIAL() ? cls.initialEquations : cls.equations;
        for (auto *e : eq->equation())
          list.push_back(equation(e));
      } else if (auto *al = dynamic_cast<LsdParser::AlgorithmSectionContext *>(child)) {
        if (al->INITIAL() || cls.kind != ast::ClassKind::Function) {
          auto &section = (al->INITIAL() ? cls.initialAlgorithms
                                         : cls.modelAlgorithms)
                              .emplace_back();
          for (auto *s : al->statement())
            section.push_back(statement(s));
          continue;
        }
        for (auto *s : al->statement())
          cls.algorithm.push_back(statement(s));
      } else if (auto *an = dynamic_cast<LsdParser::AnnotationContext *>(child)) {
        cls.annotations.push_back(annotation(an));
      }
    }
  }

  ast::ModificationPtr annotation(LsdParser::AnnotationContext *c) {
    auto m = std::make_unique<ast::Modification>();
    m->loc = loc(c);
    classModification(c->classModification(), *m);
    return m;
  }

  void element(LsdParser::ElementContext *c, ast::ClassDef &cls,
               bool isProtected) {
    if (auto *ic = c->importClause()) {
      ast::Import imp;
      imp.loc = loc(ic);
      if (ic->IDENT() && ic->children.size() > 2 &&
          ic->children[2]->getText() == "=") {
        imp.alias = ident(ic->IDENT());
        imp.path = name(ic->name()).parts;
      } else {
        imp.path = name(ic->name()).parts;
        imp.wildcard = ic->DOTSTAR() != nullptr || ic->getText().find(".*") !=
                                                       std::string::npos;
        if (ic->importList())
          for (auto *id : ic->importList()->IDENT())
            imp.names.push_back(ident(id));
      }
      cls.imports.push_back(std::move(imp));
      return;
    }
    if (auto *ec = c->extendsClause()) {
      ast::Extends ext;
      ext.loc = loc(ec);
      ext.base = typeSpecifier(ec->typeSpecifier());
      if (ec->classModification()) {
        ext.mod = std::make_unique<ast::Modification>();
        ext.mod->loc = loc(ec->classModification());
        classModification(ec->classModification(), *ext.mod);
      }
      cls.extends.push_back(std::move(ext));
      return;
    }
    if (auto *an = c->annotation()) {
      cls.annotations.push_back(annotation(an));
      return;
    }
    bool inner = false, outer = false, redeclare = false, isFinal = false;
    for (ParseTree *child : c->children)
      if (auto *t = dynamic_cast<TerminalNode *>(child)) {
        size_t type = t->getSymbol()->getType();
        if (type == LsdParser::INNER)
          inner = true;
        else if (type == LsdParser::OUTER)
          outer = true;
        else if (type == LsdParser::REDECLARE)
          redeclare = true;
        else if (type == LsdParser::FINAL)
          isFinal = true;
      }
    if (redeclare)
      unsupported(loc(c), "'redeclare'");
    if (auto *cd = c->classDefinition()) {
      cls.classes.push_back(classDefinition(cd, &cls));
      return;
    }
    auto *cc = c->componentClause();
    if (!cc)
      return;
    ast::TypePrefix prefix = typePrefix(cc->typePrefix());
    ast::Name type = typeSpecifier(cc->typeSpecifier());
    for (auto *decl : cc->componentList()->componentDeclaration()) {
      ast::Component comp;
      comp.name = ident(decl->IDENT());
      comp.loc = loc(decl);
      comp.length = static_cast<uint32_t>(utf8::countChars(decl->IDENT()->getText()));
      comp.text = sourceText(decl);
      // Drop the trailing description from the text: `x = 1 "doc"`.
      if (auto *sc = decl->comment()->stringComment(); sc && sc->getStart() &&
                                                      !sc->STRING().empty()) {
        std::string doc = sourceText(sc);
        if (comp.text.size() >= doc.size() &&
            comp.text.compare(comp.text.size() - doc.size(), doc.size(), doc) == 0) {
          comp.text.erase(comp.text.size() - doc.size());
          while (!comp.text.empty() && comp.text.back() == ' ')
            comp.text.pop_back();
        }
      }
      comp.prefix = prefix;
      comp.typeName = type;
      if (decl->arraySubscripts())
        comp.dims = subscripts(decl->arraySubscripts());
      if (cc->arraySubscripts())
        for (auto &d : subscripts(cc->arraySubscripts()))
          comp.dims.push_back(std::move(d));
      if (decl->modification())
        comp.mod = modification(decl->modification());
      if (decl->expression()) {
        comp.condition = expression(decl->expression());
        comp.conditionText = sourceText(decl->expression());
      }
      comp.description = stringComment(decl->comment()->stringComment());
      comp.isProtected = isProtected;
      comp.isFinal = isFinal;
      comp.isInner = inner;
      comp.isOuter = outer;
      comp.isRedeclare = redeclare;
      cls.components.push_back(std::move(comp));
    }
  }

  ast::TypePrefix typePrefix(LsdParser::TypePrefixContext *c) {
    ast::TypePrefix p;
    for (ParseTree *child : c->children) {
      auto *t = dynamic_cast<TerminalNode *>(child);
      if (!t)
        continue;
      switch (t->getSymbol()->getType()) {
      case LsdParser::FLOW:
        p.flow = true;
        break;
      case LsdParser::STREAM:
        p.stream = true;
        unsupported(loc(t), "'stream' connectors");
        break;
      case LsdParser::DISCRETE:
        p.variability = ast::Variability::Discrete;
        break;
      case LsdParser::PARAMETER:
        p.variability = ast::Variability::Parameter;
        break;
      case LsdParser::CONSTANT:
        p.variability = ast::Variability::Constant;
        break;
      case LsdParser::INPUT:
        p.causality = ast::Causality::Input;
        break;
      case LsdParser::OUTPUT:
        p.causality = ast::Causality::Output;
        break;
      default:
        break;
      }
    }
    return p;
  }

  // -------------------------------------------------------- modifiers
  ast::ModificationPtr modification(LsdParser::ModificationContext *c) {
    auto m = std::make_unique<ast::Modification>();
    m->loc = loc(c);
    if (c->classModification())
      classModification(c->classModification(), *m);
    if (c->expression())
      m->value = expression(c->expression());
    return m;
  }

  /// `redeclare [each] [final] Type name(mods)` in a modification: a
  /// modifier of `name` that carries its new declaration.
  ast::Modifier redeclaration(LsdParser::ElementRedeclarationContext *er) {
    auto *cc = er->componentClause1();
    auto comp = std::make_shared<ast::Component>();
    comp->name = ident(cc->IDENT());
    comp->loc = loc(cc);
    comp->length = static_cast<uint32_t>(
        utf8::countChars(cc->IDENT()->getText()));
    comp->text = sourceText(cc);
    comp->prefix = typePrefix(cc->typePrefix());
    comp->typeName = typeSpecifier(cc->typeSpecifier());
    if (cc->arraySubscripts())
      comp->dims = subscripts(cc->arraySubscripts());
    if (cc->modification())
      comp->mod = modification(cc->modification());
    comp->description = stringComment(cc->comment()->stringComment());
    comp->isFinal = er->FINAL() != nullptr;
    comp->isRedeclare = true;
    ast::Modifier mod;
    mod.each = er->EACH() != nullptr;
    mod.final = comp->isFinal;
    mod.loc = loc(cc->IDENT());
    mod.length = comp->length;
    mod.path = {comp->name};
    mod.text = sourceText(er);
    mod.redeclared = std::move(comp);
    return mod;
  }

  void classModification(LsdParser::ClassModificationContext *c,
                         ast::Modification &m) {
    if (!c->argumentList())
      return;
    for (auto *arg : c->argumentList()->argument()) {
      auto *em = dynamic_cast<LsdParser::ElementModificationContext *>(arg);
      if (!em) {
        auto *er = dynamic_cast<LsdParser::ElementRedeclarationContext *>(arg);
        if (!er || !er->componentClause1()) {
          unsupported(loc(arg), "'redeclare' of a class");
          continue;
        }
        m.args.push_back(redeclaration(er));
        continue;
      }
      ast::Modifier mod;
      mod.each = em->EACH() != nullptr;
      mod.final = em->FINAL() != nullptr;
      mod.loc = loc(em->name());
      mod.length = length(em->name());
      mod.path = name(em->name()).parts;
      mod.text = sourceText(em);
      if (em->modification())
        mod.mod = modification(em->modification());
      m.args.push_back(std::move(mod));
    }
  }

  // -------------------------------------------------------- equations
  ast::Equation equation(LsdParser::EquationContext *c) {
    ast::Equation eq;
    auto *body = c->equationBody();
    eq.loc = loc(body);
    eq.length = length(body);
    eq.text = sourceText(body);
    if (auto *s = dynamic_cast<LsdParser::SimpleEquationContext *>(body)) {
      eq.kind = ast::EquationKind::Simple;
      eq.lhs = simpleExpression(s->simpleExpression());
      eq.rhs = expression(s->expression());
    } else if (auto *i = dynamic_cast<LsdParser::IfEquationContext *>(body)) {
      eq.kind = ast::EquationKind::If;
      for (auto *e : i->expression())
        eq.conds.push_back(expression(e));
      for (auto *l : i->equationList())
        eq.branches.push_back(equationList(l));
    } else if (auto *f = dynamic_cast<LsdParser::ForEquationContext *>(body)) {
      eq.kind = ast::EquationKind::For;
      eq.iterators = forIndices(f->forIndices());
      eq.branches.push_back(equationList(f->equationList()));
    } else if (auto *k = dynamic_cast<LsdParser::ConnectEquationContext *>(body)) {
      eq.kind = ast::EquationKind::Connect;
      eq.lhs = componentReference(k->componentReference(0));
      eq.rhs = componentReference(k->componentReference(1));
    } else if (auto *w = dynamic_cast<LsdParser::WhenEquationContext *>(body)) {
      eq.kind = ast::EquationKind::When;
      for (auto *e : w->expression())
        eq.conds.push_back(expression(e));
      for (auto *l : w->equationList())
        eq.branches.push_back(equationList(l));
    } else if (auto *call = dynamic_cast<LsdParser::CallEquationContext *>(body)) {
      eq.kind = ast::EquationKind::Call;
      eq.lhs = callExpr(call, call->componentReference(), call->functionCallArgs());
    }
    return eq;
  }

  std::vector<ast::Equation> equationList(LsdParser::EquationListContext *c) {
    std::vector<ast::Equation> list;
    for (auto *e : c->equation())
      list.push_back(equation(e));
    return list;
  }

  ast::Statement statement(LsdParser::StatementContext *c) {
    ast::Statement st;
    auto *body = c->statementBody();
    st.loc = loc(body);
    st.length = length(body);
    if (auto *a = dynamic_cast<LsdParser::AssignStatementContext *>(body)) {
      if (a->expression()) {
        st.kind = ast::StatementKind::Assign;
        st.lhs = componentReference(a->componentReference());
        st.rhs = expression(a->expression());
      } else {
        st.kind = ast::StatementKind::Call;
        st.rhs = callExpr(a, a->componentReference(), a->functionCallArgs());
      }
    } else if (auto *t = dynamic_cast<LsdParser::TupleAssignStatementContext *>(body)) {
      st.kind = ast::StatementKind::TupleAssign;
      st.targets = outputList(t->outputExpressionList());
      st.rhs = callExpr(t, t->componentReference(), t->functionCallArgs());
    } else if (auto *i = dynamic_cast<LsdParser::IfStatementContext *>(body)) {
      st.kind = ast::StatementKind::If;
      for (auto *e : i->expression())
        st.conds.push_back(expression(e));
      for (auto *l : i->statementList())
        st.branches.push_back(statementList(l));
    } else if (auto *f = dynamic_cast<LsdParser::ForStatementContext *>(body)) {
      st.kind = ast::StatementKind::For;
      st.iterators = forIndices(f->forIndices());
      st.branches.push_back(statementList(f->statementList()));
    } else if (auto *w = dynamic_cast<LsdParser::WhileStatementContext *>(body)) {
      st.kind = ast::StatementKind::While;
      st.conds.push_back(expression(w->expression()));
      st.branches.push_back(statementList(w->statementList()));
    } else if (auto *wh = dynamic_cast<LsdParser::WhenStatementContext *>(body)) {
      st.kind = ast::StatementKind::When;
      for (auto *e : wh->expression())
        st.conds.push_back(expression(e));
      for (auto *l : wh->statementList())
        st.branches.push_back(statementList(l));
    } else if (dynamic_cast<LsdParser::BreakStatementContext *>(body)) {
      st.kind = ast::StatementKind::Break;
    } else {
      st.kind = ast::StatementKind::Return;
    }
    return st;
  }

  std::vector<ast::Statement> statementList(LsdParser::StatementListContext *c) {
    std::vector<ast::Statement> list;
    for (auto *s : c->statement())
      list.push_back(statement(s));
    return list;
  }

  std::vector<ast::ForIndex> forIndices(LsdParser::ForIndicesContext *c) {
    std::vector<ast::ForIndex> list;
    for (auto *fi : c->forIndex()) {
      ast::ForIndex idx;
      idx.name = ident(fi->IDENT());
      idx.loc = loc(fi);
      if (fi->expression())
        idx.range = expression(fi->expression());
      list.push_back(std::move(idx));
    }
    return list;
  }

  // ------------------------------------------------------ expressions
  ast::ExprPtr make(ast::ExprKind kind, ParserRuleContext *c) {
    auto e = std::make_unique<ast::Expr>();
    e->kind = kind;
    e->loc = loc(c);
    e->length = length(c);
    return e;
  }

  ast::ExprPtr binary(ast::BinOp op, ast::ExprPtr a, ast::ExprPtr b,
                      ParserRuleContext *c) {
    auto e = make(ast::ExprKind::Binary, c);
    e->loc = a->loc;
    e->binOp = op;
    e->ops.push_back(std::move(a));
    e->ops.push_back(std::move(b));
    return e;
  }

  ast::ExprPtr unary(ast::UnOp op, ast::ExprPtr a, ParserRuleContext *c) {
    auto e = make(ast::ExprKind::Unary, c);
    e->unOp = op;
    e->ops.push_back(std::move(a));
    return e;
  }

  ast::ExprPtr expression(LsdParser::ExpressionContext *c) {
    if (auto *p = dynamic_cast<LsdParser::PlainExpressionContext *>(c))
      return simpleExpression(p->simpleExpression());
    auto *ic = static_cast<LsdParser::IfExpressionContext *>(c);
    auto e = make(ast::ExprKind::If, c);
    for (auto *x : ic->expression())
      e->ops.push_back(expression(x));
    return e;
  }

  ast::ExprPtr simpleExpression(LsdParser::SimpleExpressionContext *c) {
    auto parts = c->logicalExpression();
    if (parts.size() == 1)
      return logicalExpression(parts[0]);
    auto e = make(ast::ExprKind::Range, c);
    // `a:b:c` is start a, step b, stop c.
    for (auto *p : parts)
      e->ops.push_back(logicalExpression(p));
    return e;
  }

  ast::ExprPtr logicalExpression(LsdParser::LogicalExpressionContext *c) {
    auto terms = c->logicalTerm();
    ast::ExprPtr e = logicalTerm(terms[0]);
    for (size_t i = 1; i < terms.size(); ++i)
      e = binary(ast::BinOp::Or, std::move(e), logicalTerm(terms[i]), c);
    return e;
  }

  ast::ExprPtr logicalTerm(LsdParser::LogicalTermContext *c) {
    auto factors = c->logicalFactor();
    ast::ExprPtr e = logicalFactor(factors[0]);
    for (size_t i = 1; i < factors.size(); ++i)
      e = binary(ast::BinOp::And, std::move(e), logicalFactor(factors[i]), c);
    return e;
  }

  ast::ExprPtr logicalFactor(LsdParser::LogicalFactorContext *c) {
    ast::ExprPtr e = relation(c->relation());
    if (c->NOT())
      return unary(ast::UnOp::Not, std::move(e), c);
    return e;
  }

  ast::ExprPtr relation(LsdParser::RelationContext *c) {
    auto sides = c->arithmeticExpression();
    ast::ExprPtr e = arithmetic(sides[0]);
    if (sides.size() == 1)
      return e;
    std::string op = c->relOp()->getText();
    ast::BinOp b = op == "<"    ? ast::BinOp::Lt
                   : op == "<=" ? ast::BinOp::Le
                   : op == ">"  ? ast::BinOp::Gt
                   : op == ">=" ? ast::BinOp::Ge
                   : op == "==" ? ast::BinOp::Eq
                                : ast::BinOp::Ne;
    return binary(b, std::move(e), arithmetic(sides[1]), c);
  }

  static ast::BinOp addOp(const std::string &op) {
    if (op == "+")
      return ast::BinOp::Add;
    if (op == "-")
      return ast::BinOp::Sub;
    if (op == ".+")
      return ast::BinOp::EAdd;
    return ast::BinOp::ESub;
  }

  ast::ExprPtr withSign(LsdParser::AddOpContext *op, ast::ExprPtr e,
                        ParserRuleContext *c) {
    if (!op)
      return e;
    std::string s = op->getText();
    auto u = unary(s == "-" || s == ".-" ? ast::UnOp::Neg : ast::UnOp::Plus,
                   std::move(e), c);
    u->loc = loc(op);
    return u;
  }

  ast::ExprPtr arithmetic(LsdParser::ArithmeticExpressionContext *c) {
    // Children: [addOp] term (addOp term)*. A chain is one n-ary Sum, so a
    // printed sum of ten thousand flows is not ten thousand nested nodes.
    auto terms = c->term();
    if (terms.size() == 1)
      return withSign(c->addOp().empty() ? nullptr : c->addOp(0), term(terms[0]),
                      terms[0]);
    auto e = make(ast::ExprKind::Sum, c);
    LsdParser::AddOpContext *pending = nullptr;
    for (ParseTree *child : c->children) {
      if (auto *op = dynamic_cast<LsdParser::AddOpContext *>(child)) {
        pending = op;
        continue;
      }
      auto *t = dynamic_cast<LsdParser::TermContext *>(child);
      if (!t)
        continue;
      std::string op = pending ? pending->getText() : "+";
      e->negated.push_back(op == "-" || op == ".-");
      e->ops.push_back(term(t));
      pending = nullptr;
    }
    return e;
  }

  ast::ExprPtr term(LsdParser::TermContext *c) {
    ast::ExprPtr e = factor(c->factor());
    auto ops = c->mulOp();
    auto rhs = c->signedFactor();
    for (size_t i = 0; i < ops.size() && i < rhs.size(); ++i) {
      std::string op = ops[i]->getText();
      ast::BinOp b = op == "*"    ? ast::BinOp::Mul
                     : op == "/"  ? ast::BinOp::Div
                     : op == ".*" ? ast::BinOp::EMul
                                  : ast::BinOp::EDiv;
      ast::ExprPtr r = withSign(rhs[i]->addOp(), factor(rhs[i]->factor()), rhs[i]);
      e = binary(b, std::move(e), std::move(r), c);
    }
    return e;
  }

  ast::ExprPtr factor(LsdParser::FactorContext *c) {
    ast::ExprPtr e = primary(c->primary());
    if (!c->powOp())
      return e;
    auto *operand = c->powOperand();
    ast::ExprPtr exp = withSign(operand->addOp(), primary(operand->primary()),
                                operand);
    ast::BinOp b =
        c->powOp()->getText() == "^" ? ast::BinOp::Pow : ast::BinOp::EPow;
    return binary(b, std::move(e), std::move(exp), c);
  }

  ast::ExprPtr primary(LsdParser::PrimaryContext *c) {
    if (auto *n = dynamic_cast<LsdParser::NumberPrimaryContext *>(c)) {
      auto e = make(ast::ExprKind::Number, c);
      e->number = std::strtod(n->NUMBER()->getText().c_str(), nullptr);
      e->text = n->NUMBER()->getText();
      // 1e309 would silently become infinity and poison every value
      // computed from it.
      if (!std::isfinite(e->number))
        diags_.report(DiagId::ErrNumberTooLarge,
                      SourceRange{e->loc, e->length}, {e->text});
      return e;
    }
    if (auto *s = dynamic_cast<LsdParser::StringPrimaryContext *>(c)) {
      auto e = make(ast::ExprKind::String, c);
      e->text = unquote(s->STRING()->getText());
      return e;
    }
    if (auto *b = dynamic_cast<LsdParser::BoolPrimaryContext *>(c)) {
      auto e = make(ast::ExprKind::Bool, c);
      e->boolean = b->TRUE() != nullptr;
      return e;
    }
    if (auto *call = dynamic_cast<LsdParser::CallPrimaryContext *>(c))
      return callExpr(call, call->componentReference(), call->functionCallArgs());
    if (auto *r = dynamic_cast<LsdParser::RefPrimaryContext *>(c))
      return componentReference(r->componentReference());
    if (auto *p = dynamic_cast<LsdParser::ParenPrimaryContext *>(c)) {
      auto list = outputList(p->outputExpressionList());
      if (list.size() == 1 && list[0]) {
        // Keep the parenthesis in the underline.
        list[0]->loc = loc(c);
        list[0]->length = length(c);
        return std::move(list[0]);
      }
      auto e = make(ast::ExprKind::Tuple, c);
      e->ops = std::move(list);
      return e;
    }
    if (auto *m = dynamic_cast<LsdParser::MatrixPrimaryContext *>(c)) {
      auto e = make(ast::ExprKind::Matrix, c);
      for (auto *row : m->expressionList()) {
        std::vector<ast::ExprPtr> r;
        for (auto *x : row->expression())
          r.push_back(expression(x));
        e->rows.push_back(std::move(r));
      }
      return e;
    }
    if (auto *a = dynamic_cast<LsdParser::ArrayPrimaryContext *>(c)) {
      auto e = make(ast::ExprKind::Array, c);
      for (auto *x : a->arrayArguments()->expression())
        e->ops.push_back(expression(x));
      if (a->arrayArguments()->forIndices())
        e->iterators = forIndices(a->arrayArguments()->forIndices());
      return e;
    }
    return make(ast::ExprKind::End, c);
  }

  std::vector<ast::ExprPtr>
  outputList(LsdParser::OutputExpressionListContext *c) {
    // Children: [expr] (',' [expr])*; an omitted expression is nullptr.
    std::vector<ast::ExprPtr> list;
    bool haveSlot = false;
    for (ParseTree *child : c->children) {
      if (auto *x = dynamic_cast<LsdParser::ExpressionContext *>(child)) {
        list.push_back(expression(x));
        haveSlot = true;
      } else {
        if (!haveSlot)
          list.push_back(nullptr);
        haveSlot = false;
      }
    }
    if (!haveSlot && !list.empty())
      list.push_back(nullptr);
    return list;
  }

  ast::ExprPtr componentReference(LsdParser::ComponentReferenceContext *c) {
    auto e = make(ast::ExprKind::Ref, c);
    e->global = !c->children.empty() &&
                dynamic_cast<TerminalNode *>(c->children[0]) != nullptr;
    for (auto *part : c->refPart()) {
      ast::RefPart rp;
      rp.name = ident(part->IDENT());
      if (part->arraySubscripts())
        rp.subscripts = subscripts(part->arraySubscripts());
      e->parts.push_back(std::move(rp));
    }
    return e;
  }

  std::vector<ast::ExprPtr> subscripts(LsdParser::ArraySubscriptsContext *c) {
    std::vector<ast::ExprPtr> subs;
    for (auto *s : c->subscript()) {
      if (s->expression())
        subs.push_back(expression(s->expression()));
      else
        subs.push_back(make(ast::ExprKind::Colon, s));
    }
    return subs;
  }

  ast::ExprPtr callExpr(ParserRuleContext *c,
                        LsdParser::ComponentReferenceContext *ref,
                        LsdParser::FunctionCallArgsContext *args) {
    auto e = make(ast::ExprKind::Call, c);
    if (ref) {
      ast::ExprPtr r = componentReference(ref);
      e->global = r->global;
      e->parts = std::move(r->parts);
      for (auto &p : e->parts)
        if (!p.subscripts.empty())
          unsupported(e->loc, "subscripted function names");
      e->text = e->refName();
    } else {
      // der(...), initial(), pure(...)
      e->text = c->getStart()->getText();
      e->parts.push_back(ast::RefPart{e->text, {}});
    }
    auto *fa = args->functionArguments();
    if (!fa)
      return e;
    for (auto *arg : fa->functionArgument()) {
      if (arg->FUNCTION()) {
        // A function value (MLS 12.4.2.1): the function's name and the
        // inputs it binds, as a call that is not made here.
        auto f = make(ast::ExprKind::Call, arg);
        ast::Name n = name(arg->name());
        for (const std::string &part : n.parts)
          f->parts.push_back(ast::RefPart{part, {}});
        f->text = n.str();
        f->partialApplication = true;
        if (auto *named = arg->namedArguments())
          for (size_t i = 0; i < named->IDENT().size(); ++i) {
            ast::Arg bound;
            bound.name = ident(named->IDENT(i));
            bound.value = expression(named->expression(i));
            f->args.push_back(std::move(bound));
          }
        ast::Arg a;
        a.value = std::move(f);
        e->args.push_back(std::move(a));
        continue;
      }
      ast::Arg a;
      if (arg->IDENT())
        a.name = ident(arg->IDENT());
      a.value = expression(arg->expression());
      e->args.push_back(std::move(a));
    }
    if (fa->forIndices())
      e->iterators = forIndices(fa->forIndices());
    return e;
  }

  uint32_t file_;
  const std::u32string &text_; // the decoded file, as the lexer read it
  DiagnosticEngine &diags_;
};

} // namespace

std::unique_ptr<ast::StoredDefinition>
buildAst(antlr4::ParserRuleContext *storedDefinition, uint32_t fileId,
         const std::u32string &chars, DiagnosticEngine &diags) {
  auto *ctx = dynamic_cast<LsdParser::StoredDefinitionContext *>(storedDefinition);
  if (!ctx)
    return nullptr;
  AstBuilder builder(fileId, chars, diags);
  return builder.build(ctx);
}

} // namespace ldae::frontend
