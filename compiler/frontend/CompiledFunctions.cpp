// Functions compiled as functions (MLS 12.4): a body the inliner cannot run
// symbolically (a while-loop whose condition reads variables, a loop longer
// than the inliner's budget) becomes C with the IR's external signature
// (ir/External.h), built by the system C compiler as an external
// function's wrapper is, and each output element of the call is an IR
// External node. The JIT and the interpreter call it as they call external
// C; where a derivative is needed, each partial is a central difference
// (docs/language.md). Every variable is a double (an Integer or Boolean
// value is exact in one) and every array has the size it has at this call:
// one C function is built per function and shapes of its arguments, and
// the functions it calls are built beside it the same way.
#include "frontend/ExternalLibraries.h"
#include "frontend/Flattener.h"
#include "ir/External.h"
#include "support/CLiteral.h"

#include <dlfcn.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <sstream>

namespace ldae::frontend {
namespace {

/// Iterations of all while-loops of one call before the call gives up (its
/// outputs NaN): a loop that never ends must not hang the run.
constexpr long kMaxRunTimeIterations = 100'000'000;
/// Doubles of arrays on one C function's stack.
constexpr int64_t kMaxStackElements = 1 << 16;

std::string number(double v) { return cDoubleLiteral(v); }

int64_t countOf(const std::vector<int64_t> &shape) {
  int64_t n = 1;
  for (int64_t d : shape)
    n *= d;
  return n;
}

/// The C function of a one-argument built-in over doubles, or null.
const char *unaryMath(const std::string &name) {
  static const std::map<std::string, const char *> fns = {
      {"abs", "fabs"},   {"sqrt", "sqrt"},   {"sin", "sin"},
      {"cos", "cos"},    {"tan", "tan"},     {"asin", "asin"},
      {"acos", "acos"},  {"atan", "atan"},   {"sinh", "sinh"},
      {"cosh", "cosh"},  {"tanh", "tanh"},   {"exp", "exp"},
      {"log", "log"},    {"log10", "log10"}, {"floor", "floor"},
      {"ceil", "ceil"},  {"integer", "floor"}, {"sign", "ldae_sign"}};
  auto it = fns.find(name);
  return it == fns.end() ? nullptr : it->second;
}


const char *kPrelude = R"C(#include <math.h>
#include <string.h>
static double ldae_sign(double x) { return (double)((x > 0) - (x < 0)); }
/* A 1-based subscript as a 0-based offset; out of range sets *bad. */
static long ldae_ix(double i, long n, int *bad) {
  long k = (long)i;
  if (!(i >= 1 && i <= (double)n) || (double)k != i) {
    *bad = 1;
    return 0;
  }
  return k - 1;
}
)C";

} // namespace

/// Translates function bodies to C: one translation unit holding a C
/// function per (function, argument shapes) reached from the first.
class FunctionTranslator {
public:
  explicit FunctionTranslator(Flattener &f) : f_(f) {}

  /// The C function computing `fn` for inputs of `inputShapes`; the
  /// outputs' shapes into `outputShapes`. nullopt after a reported error.
  std::optional<std::string>
  define(const ast::ClassDef &fn, const Flattener::FunctionParts &parts,
         const std::vector<std::vector<int64_t>> &inputShapes,
         std::vector<std::vector<int64_t>> &outputShapes, SourceRange at);

  std::string source() const {
    return kPrelude + prototypes_.str() + bodies_.str();
  }

private:
  /// A value in C: its shape and the C text of its element at a flat
  /// (row-major, 0-based) index given as C text; a scalar ignores it.
  struct CVal {
    std::vector<int64_t> shape;
    std::function<std::string(const std::string &)> at;
    bool scalar() const { return shape.empty(); }
  };
  struct Var {
    std::string c;
    std::vector<int64_t> shape;
  };
  /// The function being translated.
  struct Frame {
    const ast::ClassDef *fn = nullptr;
    const ast::ClassDef *scope = nullptr; // where its names are looked up
    std::vector<std::pair<std::string, Var>> vars; // innermost last
    std::vector<int> loops; // the break labels of the loops around
    std::ostringstream *pre = nullptr; // what the statement computes first
  };
  struct Spec {
    std::string name;
    std::vector<std::vector<int64_t>> outputShapes;
  };

  std::optional<std::string> statements(const std::vector<ast::Statement> &list,
                                        int indent);
  std::optional<std::string> statement(const ast::Statement &st, int indent);
  std::optional<std::string> assignTo(const ast::Expr &target, const CVal &v,
                                      const std::string &pad);
  std::optional<std::string> forLoop(const ast::Statement &st, size_t k,
                                     int label, int indent);
  std::optional<CVal> value(const ast::Expr &e);
  std::optional<std::string> scalar(const ast::Expr &e);
  std::optional<CVal> ref(const ast::Expr &e);
  std::optional<CVal> call(const ast::Expr &e);
  std::optional<std::vector<CVal>> userCall(const ast::Expr &e);
  std::optional<CVal> binary(const ast::Expr &e, const CVal &a,
                             const CVal &b);
  std::optional<CVal> constant(const ast::Expr &e);
  std::optional<int64_t> shapeInteger(const ast::Expr &e);
  const Var *findVar(const std::string &name) const;
  std::string temp() { return "t" + std::to_string(temps_++); }
  bool unsupported(const ast::Expr &e, const std::string &what);
  bool unsupported(const ast::Statement &st, const std::string &what);

  Flattener &f_;
  Frame *frame_ = nullptr;
  std::map<std::string, Spec> specs_; // by function and input shapes
  /// The sizes `end` stands for, innermost subscript last.
  std::vector<int64_t> endSize_;
  std::ostringstream prototypes_, bodies_;
  int temps_ = 0, labels_ = 0, functions_ = 0;
};

bool FunctionTranslator::unsupported(const ast::Expr &e,
                                     const std::string &what) {
  f_.report(DiagId::ErrUnsupported, SourceRange{e.loc, e.length},
            {what + " in a function compiled to run at run time"});
  return false;
}

bool FunctionTranslator::unsupported(const ast::Statement &st,
                                     const std::string &what) {
  f_.report(DiagId::ErrUnsupported, SourceRange{st.loc, st.length},
            {what + " in a function compiled to run at run time"});
  return false;
}

const FunctionTranslator::Var *
FunctionTranslator::findVar(const std::string &name) const {
  for (auto it = frame_->vars.rbegin(); it != frame_->vars.rend(); ++it)
    if (it->first == name)
      return &it->second;
  return nullptr;
}

std::optional<std::string> FunctionTranslator::define(
    const ast::ClassDef &fn, const Flattener::FunctionParts &parts,
    const std::vector<std::vector<int64_t>> &inputShapes,
    std::vector<std::vector<int64_t>> &outputShapes, SourceRange at) {
  std::string key = fn.qualifiedName() + "(";
  for (const auto &s : inputShapes) {
    key += "[";
    for (int64_t d : s)
      key += std::to_string(d) + ",";
    key += "]";
  }
  if (auto it = specs_.find(key); it != specs_.end()) {
    outputShapes = it->second.outputShapes;
    return it->second.name;
  }
  if (parts.body->isExternal || fn.impure) {
    f_.report(DiagId::ErrUnsupported, at,
              {(fn.impure ? "impure function '" : "external function '") +
               fn.name + "' called from a function compiled to run at run time"});
    return std::nullopt;
  }
  Frame frame;
  frame.fn = &fn;
  frame.scope = parts.body;
  Frame *outer = frame_;
  frame_ = &frame;
  struct Restore {
    FunctionTranslator &t;
    Frame *outer;
    ~Restore() { t.frame_ = outer; }
  } restore{*this, outer};

  // The variables' shapes: inputs from the arguments, the others from
  // their declared sizes, which read the inputs' sizes (size(u, 1)).
  std::string name = "ldaefn" + std::to_string(functions_++);
  std::ostringstream decl, init;
  std::vector<std::pair<const ast::Component *, Var>> outputs;
  int64_t stack = 0, inOffset = 0;
  size_t input = 0;
  for (size_t i = 0; i < parts.comps.size(); ++i) {
    const ast::Component &c = *parts.comps[i];
    if (!f_.isNumericType(c.typeName, *parts.owner[i])) {
      f_.report(DiagId::ErrUnsupported, c.typeName.loc,
                {"function variables of type '" + c.typeName.str() +
                 "' in a function compiled to run at run time"});
      return std::nullopt;
    }
    Var v;
    v.c = "v_" + c.name;
    bool isInput = c.prefix.causality == ast::Causality::Input;
    if (isInput) {
      if (input >= inputShapes.size()) {
        f_.report(DiagId::ErrMissingArgument, at, {c.name, fn.name});
        return std::nullopt;
      }
      v.shape = inputShapes[input++];
      if (v.shape.size() != c.dims.size()) {
        f_.report(DiagId::ErrArgumentType, at,
                  {c.name, fn.name,
                   c.dims.empty() ? "a scalar"
                                  : "an array of " +
                                        std::to_string(c.dims.size()) +
                                        " dimension(s)",
                   describeShape(v.shape)});
        return std::nullopt;
      }
    } else {
      for (const auto &d : c.dims) {
        std::optional<int64_t> n = shapeInteger(*d);
        if (!n)
          return std::nullopt;
        v.shape.push_back(*n);
      }
    }
    int64_t count = countOf(v.shape);
    stack += count;
    if (stack > kMaxStackElements) {
      f_.report(DiagId::ErrUnsupported, SourceRange{c.loc, c.length},
                {"arrays of more than " + std::to_string(kMaxStackElements) +
                 " elements in a function compiled to run at run time"});
      return std::nullopt;
    }
    if (v.shape.empty())
      decl << "  double " << v.c << " = 0;\n";
    else
      decl << "  double " << v.c << "[" << std::max<int64_t>(count, 1)
           << "] = {0};\n";
    if (isInput) {
      if (v.shape.empty())
        init << "  " << v.c << " = in[" << inOffset << "];\n";
      else
        init << "  memcpy(" << v.c << ", in + " << inOffset << ", "
             << count << " * sizeof(double));\n";
      inOffset += count;
    }
    frame.vars.emplace_back(c.name, v);
    if (c.prefix.causality == ast::Causality::Output)
      outputs.emplace_back(&c, v);
  }
  if (input != inputShapes.size()) {
    f_.report(DiagId::ErrCallArgCount, at,
              {fn.name, std::to_string(input),
               std::to_string(inputShapes.size())});
    return std::nullopt;
  }
  outputShapes.clear();
  for (const auto &o : outputs)
    outputShapes.push_back(o.second.shape);
  specs_[key] = Spec{name, outputShapes};

  // Bindings of outputs and locals, in declaration order.
  std::ostringstream body;
  for (size_t i = 0; i < parts.comps.size(); ++i) {
    const ast::Component &c = *parts.comps[i];
    if (c.prefix.causality == ast::Causality::Input || !c.mod ||
        !c.mod->value)
      continue;
    std::ostringstream pre;
    frame.pre = &pre;
    ast::Expr target;
    target.kind = ast::ExprKind::Ref;
    target.loc = c.loc;
    target.parts.push_back({c.name, {}});
    std::optional<CVal> v = value(*c.mod->value);
    if (!v)
      return std::nullopt;
    std::optional<std::string> code = assignTo(target, *v, "    ");
    if (!code)
      return std::nullopt;
    body << "  {\n" << pre.str() << *code << "  }\n";
  }
  std::optional<std::string> code = statements(parts.body->algorithm, 1);
  if (!code)
    return std::nullopt;
  prototypes_ << "static void " << name << "(const double *in, double *out);\n";
  bodies_ << "static void " << name << "(const double *in, double *out) {\n"
          << "  int bad = 0;\n  long iterations = 0;\n"
          << decl.str() << init.str() << body.str() << *code
          << "ldae_return:\n  (void)iterations;\n";
  int64_t outOffset = 0;
  for (const auto &[c, v] : outputs) {
    int64_t count = countOf(v.shape);
    for (int64_t k = 0; k < count; ++k)
      bodies_ << "  out[" << outOffset + k << "] = bad ? NAN : "
              << (v.shape.empty() ? v.c : v.c + "[" + std::to_string(k) + "]")
              << ";\n";
    outOffset += count;
  }
  bodies_ << "}\n";
  return name;
}

std::optional<std::string>
FunctionTranslator::statements(const std::vector<ast::Statement> &list,
                               int indent) {
  std::string out;
  for (const ast::Statement &st : list) {
    std::optional<std::string> s = statement(st, indent);
    if (!s)
      return std::nullopt;
    out += *s;
  }
  return out;
}

std::optional<std::string>
FunctionTranslator::statement(const ast::Statement &st, int indent) {
  std::string pad(2 * indent, ' '), inner(2 * indent + 2, ' ');
  std::ostringstream pre;
  std::ostringstream *outerPre = frame_->pre;
  frame_->pre = &pre;
  struct RestorePre {
    Frame &f;
    std::ostringstream *p;
    ~RestorePre() { f.pre = p; }
  } restorePre{*frame_, outerPre};
  auto block = [&](const std::string &code) {
    return pad + "{\n" + pre.str() + code + pad + "}\n";
  };
  switch (st.kind) {
  case ast::StatementKind::Assign: {
    std::optional<CVal> v = value(*st.rhs);
    if (!v)
      return std::nullopt;
    std::optional<std::string> code = assignTo(*st.lhs, *v, inner);
    if (!code)
      return std::nullopt;
    return block(*code);
  }
  case ast::StatementKind::TupleAssign: {
    std::optional<std::vector<CVal>> outs = userCall(*st.rhs);
    if (!outs)
      return std::nullopt;
    if (st.targets.size() > outs->size()) {
      f_.report(DiagId::ErrTooManyTargets, SourceRange{st.loc, st.length},
                {std::to_string(st.targets.size()),
                 std::to_string(outs->size())});
      return std::nullopt;
    }
    std::string code;
    for (size_t k = 0; k < st.targets.size(); ++k) {
      if (!st.targets[k])
        continue;
      std::optional<std::string> c = assignTo(*st.targets[k], (*outs)[k], inner);
      if (!c)
        return std::nullopt;
      code += *c;
    }
    return block(code);
  }
  case ast::StatementKind::Call: {
    const ast::Expr &c = *st.rhs;
    if (c.text == "assert") {
      // The message is not shown: a failed assertion makes the call's
      // outputs NaN, which the run reports where they are used.
      if (c.args.empty()) {
        unsupported(st, "an assert without a condition");
        return std::nullopt;
      }
      std::optional<std::string> cond = scalar(*c.args[0].value);
      if (!cond)
        return std::nullopt;
      return block(inner + "if (!(" + *cond + ")) {\n" + inner +
                   "  bad = 1;\n" + inner + "  goto ldae_return;\n" + inner +
                   "}\n");
    }
    if (!userCall(c))
      return std::nullopt;
    return block("");
  }
  case ast::StatementKind::If: {
    // Each elseif's condition is computed only where it is reached.
    std::function<std::optional<std::string>(size_t)> chain =
        [&](size_t k) -> std::optional<std::string> {
      if (k == st.conds.size())
        return k < st.branches.size() ? statements(st.branches[k], indent + 1)
                                      : std::string();
      std::ostringstream condPre;
      frame_->pre = &condPre;
      std::optional<std::string> cond = scalar(*st.conds[k]);
      if (!cond)
        return std::nullopt;
      std::optional<std::string> then = statements(st.branches[k], indent + 1);
      std::optional<std::string> rest = chain(k + 1);
      if (!then || !rest)
        return std::nullopt;
      return pad + "{\n" + condPre.str() + pad + "if (" + *cond + ") {\n" +
             *then + pad + "} else {\n" + *rest + pad + "}\n" + pad + "}\n";
    };
    return chain(0);
  }
  case ast::StatementKind::While: {
    int label = labels_++;
    frame_->loops.push_back(label);
    std::optional<std::string> cond = scalar(*st.conds[0]);
    std::optional<std::string> body =
        cond ? statements(st.branches[0], indent + 1) : std::nullopt;
    frame_->loops.pop_back();
    if (!body)
      return std::nullopt;
    return pad + "for (;;) {\n" + pre.str() + inner +
           "if (++iterations > " + std::to_string(kMaxRunTimeIterations) +
           ") {\n" + inner + "  bad = 1;\n" + inner + "  goto ldae_return;\n" +
           inner + "}\n" + inner + "if (!(" + *cond + "))\n" + inner +
           "  break;\n" + *body + pad + "}\nldae_break" +
           std::to_string(label) + ":;\n";
  }
  case ast::StatementKind::For: {
    int label = labels_++;
    frame_->loops.push_back(label);
    size_t vars = frame_->vars.size();
    std::optional<std::string> loop = forLoop(st, 0, label, indent);
    frame_->vars.resize(vars);
    frame_->loops.pop_back();
    if (!loop)
      return std::nullopt;
    return block(*loop) + "ldae_break" + std::to_string(label) + ":;\n";
  }
  case ast::StatementKind::Break:
    if (frame_->loops.empty()) {
      f_.report(DiagId::ErrMisplaced, SourceRange{st.loc, st.length},
                {"break", "a for or while loop"});
      return std::nullopt;
    }
    return pad + "goto ldae_break" + std::to_string(frame_->loops.back()) +
           ";\n";
  case ast::StatementKind::Return:
    return pad + "goto ldae_return;\n";
  case ast::StatementKind::When:
    f_.report(DiagId::ErrMisplaced, SourceRange{st.loc, st.length},
              {"when", "a model's equations"});
    return std::nullopt;
  }
  return std::nullopt;
}

std::optional<std::string>
FunctionTranslator::forLoop(const ast::Statement &st, size_t k, int label,
                            int indent) {
  std::string pad(2 * indent + 2, ' ');
  if (k == st.iterators.size())
    return statements(st.branches[0], indent + 1);
  const ast::ForIndex &it = st.iterators[k];
  if (!it.range || it.range->kind != ast::ExprKind::Range) {
    f_.report(DiagId::ErrUnsupported,
              SourceRange{it.range ? it.range->loc : it.loc, 1},
              {"a for-loop over anything but a range a:b or a:step:b in a "
               "function compiled to run at run time"});
    return std::nullopt;
  }
  const auto &ops = it.range->ops;
  std::optional<std::string> lo = scalar(*ops[0]);
  std::optional<std::string> step =
      ops.size() == 3 ? scalar(*ops[1]) : std::optional<std::string>("1.0");
  std::optional<std::string> hi = scalar(*ops.back());
  if (!lo || !step || !hi)
    return std::nullopt;
  std::string n = std::to_string(label) + "_" + std::to_string(k);
  Var v{"v_" + it.name + "_" + n, {}};
  frame_->vars.emplace_back(it.name, v);
  std::optional<std::string> body = forLoop(st, k + 1, label, indent);
  if (!body)
    return std::nullopt;
  // MLS 10.4.2.1: a:s:b holds a + i*s for i = 0 ... floor((b - a)/s).
  return pad + "double lo" + n + " = " + *lo + ", st" + n + " = " + *step +
         ", hi" + n + " = " + *hi + ";\n" + pad + "long n" + n + " = st" + n +
         " == 0 ? -1 : (long)floor((hi" + n + " - lo" + n + ") / st" + n +
         ");\n" + pad + "for (long i" + n + " = 0; i" + n + " <= n" + n +
         "; ++i" + n + ") {\n" + pad + "  double " + v.c + " = lo" + n +
         " + i" + n + " * st" + n + ";\n" + *body + pad + "}\n";
}

std::optional<std::string>
FunctionTranslator::assignTo(const ast::Expr &target, const CVal &v,
                             const std::string &pad) {
  if (target.kind != ast::ExprKind::Ref || target.parts.size() != 1 ||
      !findVar(target.parts[0].name)) {
    f_.report(DiagId::ErrBadAssignTarget, SourceRange{target.loc, target.length},
              {});
    return std::nullopt;
  }
  std::optional<CVal> lhs = ref(target);
  if (!lhs)
    return std::nullopt;
  if (lhs->shape != v.shape && !v.scalar()) {
    f_.report(DiagId::ErrShapeMismatch, SourceRange{target.loc, target.length},
              {":=", describeShape(lhs->shape), describeShape(v.shape)});
    return std::nullopt;
  }
  if (lhs->scalar())
    return pad + lhs->at("0") + " = " + v.at("0") + ";\n";
  // Through a copy: the right side may read the elements it replaces.
  std::string t = temp();
  std::string n = std::to_string(countOf(lhs->shape));
  return pad + "double " + t + "[" + n + "];\n" + pad +
         "for (long k = 0; k < " + n + "; ++k) " + t + "[k] = " + v.at("k") +
         ";\n" + pad + "for (long k = 0; k < " + n + "; ++k) " + lhs->at("k") +
         " = " + t + "[k];\n";
}

std::optional<std::string> FunctionTranslator::scalar(const ast::Expr &e) {
  std::optional<CVal> v = value(e);
  if (!v)
    return std::nullopt;
  if (!v->scalar()) {
    f_.report(DiagId::ErrShapeMismatch, SourceRange{e.loc, e.length},
              {"here", "a scalar", describeShape(v->shape)});
    return std::nullopt;
  }
  return v->at("0");
}

std::optional<FunctionTranslator::CVal>
FunctionTranslator::value(const ast::Expr &e) {
  auto scalarOf = [](std::string c) {
    return CVal{{}, [c](const std::string &) { return c; }};
  };
  switch (e.kind) {
  case ast::ExprKind::Number:
    return scalarOf(number(e.number));
  case ast::ExprKind::Bool:
    return scalarOf(e.boolean ? "1.0" : "0.0");
  case ast::ExprKind::Ref:
    return ref(e);
  case ast::ExprKind::Call:
    return call(e);
  case ast::ExprKind::Unary: {
    std::optional<CVal> a = value(*e.ops[0]);
    if (!a)
      return std::nullopt;
    const char *op = e.unOp == ast::UnOp::Neg ? "-" : e.unOp == ast::UnOp::Not ? "!" : "+";
    auto f = a->at;
    return CVal{a->shape,
                [f, op](const std::string &k) { return std::string("(") + op + f(k) + ")"; }};
  }
  case ast::ExprKind::Binary: {
    std::optional<CVal> a = value(*e.ops[0]), b = a ? value(*e.ops[1]) : std::nullopt;
    if (!b)
      return std::nullopt;
    return binary(e, *a, *b);
  }
  case ast::ExprKind::Sum: {
    std::optional<CVal> acc = value(*e.ops[0]);
    if (!acc)
      return std::nullopt;
    if (e.negated[0]) {
      auto f = acc->at;
      acc->at = [f](const std::string &k) { return "(-" + f(k) + ")"; };
    }
    for (size_t i = 1; i < e.ops.size(); ++i) {
      std::optional<CVal> b = value(*e.ops[i]);
      if (!b)
        return std::nullopt;
      if (!acc->scalar() && !b->scalar() && acc->shape != b->shape) {
        f_.report(DiagId::ErrShapeMismatch, SourceRange{e.loc, e.length},
                  {e.negated[i] ? "-" : "+", describeShape(acc->shape),
                   describeShape(b->shape)});
        return std::nullopt;
      }
      auto fa = acc->at, fb = b->at;
      std::string op = e.negated[i] ? " - " : " + ";
      acc = CVal{acc->scalar() ? b->shape : acc->shape,
                 [fa, fb, op](const std::string &k) {
                   return "(" + fa(k) + op + fb(k) + ")";
                 }};
    }
    return acc;
  }
  case ast::ExprKind::If: {
    // cond, then, {cond, then}, else
    std::optional<CVal> result = value(*e.ops.back());
    if (!result)
      return std::nullopt;
    for (size_t i = e.ops.size() - 1; i >= 2; i -= 2) {
      std::optional<std::string> cond = scalar(*e.ops[i - 2]);
      std::optional<CVal> then = cond ? value(*e.ops[i - 1]) : std::nullopt;
      if (!then)
        return std::nullopt;
      if (then->shape != result->shape) {
        f_.report(DiagId::ErrShapeMismatch, SourceRange{e.loc, e.length},
                  {"if", describeShape(then->shape),
                   describeShape(result->shape)});
        return std::nullopt;
      }
      auto ft = then->at, fe = result->at;
      std::string c = *cond;
      result = CVal{then->shape, [c, ft, fe](const std::string &k) {
                      return "(" + c + " ? " + ft(k) + " : " + fe(k) + ")";
                    }};
    }
    return result;
  }
  case ast::ExprKind::Array: {
    if (!e.iterators.empty()) {
      unsupported(e, "an array constructor with 'for'");
      return std::nullopt;
    }
    std::vector<CVal> elems;
    for (const auto &op : e.ops) {
      std::optional<CVal> v = value(*op);
      if (!v)
        return std::nullopt;
      if (!elems.empty() && v->shape != elems[0].shape) {
        f_.report(DiagId::ErrShapeMismatch, SourceRange{op->loc, op->length},
                  {"{...}", describeShape(elems[0].shape),
                   describeShape(v->shape)});
        return std::nullopt;
      }
      elems.push_back(std::move(*v));
    }
    std::vector<int64_t> shape{int64_t(elems.size())};
    if (!elems.empty())
      shape.insert(shape.end(), elems[0].shape.begin(), elems[0].shape.end());
    int64_t inner = elems.empty() ? 1 : countOf(elems[0].shape);
    std::string t = temp();
    *frame_->pre << "  double " << t << "[" << std::max<int64_t>(1, countOf(shape))
                 << "];\n";
    for (size_t i = 0; i < elems.size(); ++i)
      *frame_->pre << "  for (long k = 0; k < " << inner << "; ++k) " << t
                   << "[" << int64_t(i) * inner << " + k] = " << elems[i].at("k")
                   << ";\n";
    return CVal{shape, [t](const std::string &k) { return t + "[" + k + "]"; }};
  }
  default:
    unsupported(e, "this expression");
    return std::nullopt;
  }
}

std::optional<FunctionTranslator::CVal>
FunctionTranslator::binary(const ast::Expr &e, const CVal &a, const CVal &b) {
  using ast::BinOp;
  const char *op = nullptr;
  bool elementwise = true, power = false;
  switch (e.binOp) {
  case BinOp::Add: case BinOp::EAdd: op = " + "; break;
  case BinOp::Sub: case BinOp::ESub: op = " - "; break;
  case BinOp::Mul: op = " * "; elementwise = a.scalar() || b.scalar(); break;
  case BinOp::EMul: op = " * "; break;
  case BinOp::Div: op = " / "; elementwise = b.scalar(); break;
  case BinOp::EDiv: op = " / "; break;
  case BinOp::Pow: power = true; elementwise = a.scalar() && b.scalar(); break;
  case BinOp::EPow: power = true; break;
  case BinOp::Lt: op = " < "; break;
  case BinOp::Le: op = " <= "; break;
  case BinOp::Gt: op = " > "; break;
  case BinOp::Ge: op = " >= "; break;
  case BinOp::Eq: op = " == "; break;
  case BinOp::Ne: op = " != "; break;
  case BinOp::And: op = " && "; break;
  case BinOp::Or: op = " || "; break;
  }
  auto fa = a.at, fb = b.at;
  if (elementwise) {
    if (!a.scalar() && !b.scalar() && a.shape != b.shape) {
      f_.report(DiagId::ErrShapeMismatch, SourceRange{e.loc, e.length},
                {"this operator", describeShape(a.shape), describeShape(b.shape)});
      return std::nullopt;
    }
    std::string o = op ? op : "";
    return CVal{a.scalar() ? b.shape : a.shape,
                [fa, fb, o, power](const std::string &k) {
                  return power ? "pow(" + fa(k) + ", " + fb(k) + ")"
                               : "(" + fa(k) + o + fb(k) + ")";
                }};
  }
  if (e.binOp != BinOp::Mul || a.shape.size() > 2 || b.shape.size() > 2) {
    unsupported(e, "this array operator");
    return std::nullopt;
  }
  // Matrix products (MLS 10.6.4): (m x n)(n x p), vectors as one side.
  int64_t m = a.shape.size() == 2 ? a.shape[0] : 1;
  int64_t n = a.shape.back();
  int64_t nb = b.shape[0], p = b.shape.size() == 2 ? b.shape[1] : 1;
  if (n != nb) {
    f_.report(DiagId::ErrShapeMismatch, SourceRange{e.loc, e.length},
              {"*", describeShape(a.shape), describeShape(b.shape)});
    return std::nullopt;
  }
  std::vector<int64_t> shape;
  if (a.shape.size() == 2)
    shape.push_back(m);
  if (b.shape.size() == 2)
    shape.push_back(p);
  std::string t = temp(), M = std::to_string(m), N = std::to_string(n),
              P = std::to_string(p);
  *frame_->pre << "  double " << t << "[" << m * p << "];\n"
               << "  for (long i = 0; i < " << M << "; ++i)\n"
               << "    for (long j = 0; j < " << P << "; ++j) {\n"
               << "      double s = 0;\n"
               << "      for (long l = 0; l < " << N << "; ++l) s += "
               << fa("(i * " + N + " + l)") << " * " << fb("(l * " + P + " + j)")
               << ";\n      " << t << "[i * " << P << " + j] = s;\n    }\n";
  return CVal{shape, [t](const std::string &k) { return t + "[" + k + "]"; }};
}

std::optional<FunctionTranslator::CVal>
FunctionTranslator::ref(const ast::Expr &e) {
  const Var *var = e.parts.size() == 1 ? findVar(e.parts[0].name) : nullptr;
  if (!var)
    return constant(e);
  const auto &subs = e.parts[0].subscripts;
  if (subs.empty()) {
    std::string c = var->c;
    if (var->shape.empty())
      return CVal{{}, [c](const std::string &) { return c; }};
    return CVal{var->shape, [c](const std::string &k) { return c + "[" + k + "]"; }};
  }
  if (subs.size() != var->shape.size()) {
    f_.report(DiagId::ErrShapeMismatch, SourceRange{e.loc, e.length},
              {"[]", describeShape(var->shape),
               std::to_string(subs.size()) + " subscript(s)"});
    return std::nullopt;
  }
  // Each subscript a 0-based offset in C, or free (`:`).
  std::vector<std::string> offset(subs.size());
  std::vector<int64_t> shape;
  for (size_t d = 0; d < subs.size(); ++d) {
    const ast::Expr &s = *subs[d];
    if (s.kind == ast::ExprKind::Colon) {
      shape.push_back(var->shape[d]);
      continue;
    }
    endSize_.push_back(var->shape[d]);
    std::optional<std::string> i = scalar(s);
    endSize_.pop_back();
    if (!i)
      return std::nullopt;
    offset[d] = "ldae_ix(" + *i + ", " + std::to_string(var->shape[d]) + ", &bad)";
  }
  std::string c = var->c;
  std::vector<int64_t> dims = var->shape;
  return CVal{shape, [c, dims, offset](const std::string &k) {
                // The free dimensions' indices from k, last fastest.
                std::string flat = "0";
                int64_t freeStride = 1;
                std::vector<std::string> idx(dims.size());
                for (size_t d = dims.size(); d-- > 0;)
                  if (offset[d].empty()) {
                    idx[d] = "((" + k + ") / " + std::to_string(freeStride) +
                             " % " + std::to_string(dims[d]) + ")";
                    freeStride *= dims[d];
                  } else {
                    idx[d] = offset[d];
                  }
                for (size_t d = 0; d < dims.size(); ++d)
                  flat = "(" + flat + ") * " + std::to_string(dims[d]) + " + " +
                         idx[d];
                return c + "[" + flat + "]";
              }};
}

std::optional<FunctionTranslator::CVal>
FunctionTranslator::constant(const ast::Expr &e) {
  if (e.kind == ast::ExprKind::End) {
    if (endSize_.empty()) {
      unsupported(e, "'end' outside a subscript");
      return std::nullopt;
    }
    std::string n = number(double(endSize_.back()));
    return CVal{{}, [n](const std::string &) { return n; }};
  }
  // A name that is no variable of the function: a constant of a package
  // (Modelica.Constants.eps), an enumeration literal.
  Env none;
  std::optional<Value> v = f_.lower(e, Scope{nullptr, frame_->scope}, &none);
  if (!v)
    return std::nullopt;
  if (v->isString) {
    unsupported(e, "a String");
    return std::nullopt;
  }
  std::vector<std::string> elems;
  for (ir::ExprRef x : v->elems) {
    std::optional<double> c = f_.constantValue(x);
    if (!c) {
      unsupported(e, "'" + e.refName() + "', which is not a constant,");
      return std::nullopt;
    }
    elems.push_back(number(*c));
  }
  if (v->shape.empty())
    return CVal{{}, [c = elems[0]](const std::string &) { return c; }};
  std::string t = temp();
  *frame_->pre << "  static const double " << t << "[] = {";
  for (size_t i = 0; i < elems.size(); ++i)
    *frame_->pre << (i ? ", " : "") << elems[i];
  *frame_->pre << "};\n";
  return CVal{v->shape, [t](const std::string &k) { return t + "[" + k + "]"; }};
}

std::optional<int64_t> FunctionTranslator::shapeInteger(const ast::Expr &e) {
  // A size written with the sizes of the variables (size(u, 1)) and
  // constants: known for this call's shapes.
  if (e.kind == ast::ExprKind::Call && e.text == "size" && e.args.size() == 2 &&
      e.args[0].value->kind == ast::ExprKind::Ref &&
      e.args[0].value->parts.size() == 1) {
    const Var *v = findVar(e.args[0].value->parts[0].name);
    std::optional<int64_t> d = v ? shapeInteger(*e.args[1].value) : std::nullopt;
    if (v && d && *d >= 1 && size_t(*d) <= v->shape.size())
      return v->shape[*d - 1];
  }
  if (e.kind == ast::ExprKind::Binary &&
      (e.binOp == ast::BinOp::Mul || e.binOp == ast::BinOp::Add ||
       e.binOp == ast::BinOp::Sub)) {
    std::optional<int64_t> a = shapeInteger(*e.ops[0]);
    std::optional<int64_t> b = a ? shapeInteger(*e.ops[1]) : std::nullopt;
    if (b)
      return e.binOp == ast::BinOp::Mul ? *a * *b
             : e.binOp == ast::BinOp::Add ? *a + *b
                                          : *a - *b;
  }
  if (e.kind == ast::ExprKind::Sum) {
    int64_t acc = 0;
    for (size_t i = 0; i < e.ops.size(); ++i) {
      std::optional<int64_t> v = shapeInteger(*e.ops[i]);
      if (!v)
        return std::nullopt;
      acc += e.negated[i] ? -*v : *v;
    }
    return acc;
  }
  if (e.kind == ast::ExprKind::Ref && e.parts.size() == 1 &&
      findVar(e.parts[0].name)) {
    f_.report(DiagId::ErrUnsupported, SourceRange{e.loc, e.length},
              {"an array size that reads the variable '" + e.parts[0].name +
               "' in a function compiled to run at run time"});
    return std::nullopt;
  }
  Env none;
  std::optional<int64_t> n =
      f_.evalInteger(e, Scope{nullptr, frame_->scope}, &none, "array size");
  if (n && (*n < 0 || *n > kMaxStackElements)) {
    unsupported(e, "an array size of " + std::to_string(*n));
    return std::nullopt;
  }
  return n;
}

std::optional<FunctionTranslator::CVal>
FunctionTranslator::call(const ast::Expr &e) {
  std::string name =
      e.parts.size() == 1 ? e.parts[0].name
      : e.parts.size() == 3 && e.parts[0].name == "Modelica" &&
              e.parts[1].name == "Math"
          ? e.parts[2].name
          : "";
  bool local = e.parts.size() == 1 && findVar(name);
  auto args = [&](size_t n) -> std::optional<std::vector<CVal>> {
    if (e.args.size() != n || !e.iterators.empty()) {
      f_.report(DiagId::ErrCallArgCount, SourceRange{e.loc, e.length},
                {name, std::to_string(n), std::to_string(e.args.size())});
      return std::nullopt;
    }
    std::vector<CVal> out;
    for (const ast::Arg &a : e.args) {
      std::optional<CVal> v = value(*a.value);
      if (!v)
        return std::nullopt;
      out.push_back(std::move(*v));
    }
    return out;
  };
  if (!local && !name.empty()) {
    if (const char *fn = unaryMath(name)) {
      auto a = args(1);
      if (!a)
        return std::nullopt;
      auto f = (*a)[0].at;
      std::string c = fn;
      return CVal{(*a)[0].shape,
                  [f, c](const std::string &k) { return c + "(" + f(k) + ")"; }};
    }
    if (name == "noEvent" || (name == "smooth" && e.args.size() == 2)) {
      auto a = args(e.args.size());
      if (!a)
        return std::nullopt;
      return a->back();
    }
    static const std::map<std::string, std::string> binaryFns = {
        {"atan2", "atan2(A, B)"},
        {"min", "fmin(A, B)"},
        {"max", "fmax(A, B)"},
        {"mod", "((A) - floor((A) / (B)) * (B))"},
        {"rem", "((A) - trunc((A) / (B)) * (B))"},
        {"div", "trunc((A) / (B))"}};
    if (auto it = binaryFns.find(name);
        it != binaryFns.end() && e.args.size() == 2) {
      auto a = args(2);
      if (!a)
        return std::nullopt;
      std::string pattern = it->second;
      auto fa = (*a)[0].at, fb = (*a)[1].at;
      if (!(*a)[0].scalar() || !(*a)[1].scalar()) {
        unsupported(e, "'" + name + "' of arrays");
        return std::nullopt;
      }
      return CVal{{}, [pattern, fa, fb](const std::string &k) {
                    std::string s;
                    for (char ch : pattern)
                      s += ch == 'A' ? fa(k) : ch == 'B' ? fb(k) : std::string(1, ch);
                    return s;
                  }};
    }
    if ((name == "sum" || name == "product" || name == "min" ||
         name == "max") && e.args.size() == 1) {
      auto a = args(1);
      if (!a)
        return std::nullopt;
      const CVal &v = (*a)[0];
      std::string t = temp(), n = std::to_string(countOf(v.shape));
      const char *start = name == "sum" ? "0.0" : name == "product" ? "1.0"
                          : name == "min" ? "HUGE_VAL" : "(-HUGE_VAL)";
      std::string step = name == "sum" ? t + " += X" : name == "product" ? t + " *= X"
                         : name == "min" ? t + " = fmin(" + t + ", X)"
                                         : t + " = fmax(" + t + ", X)";
      std::string x = v.at("k");
      step.replace(step.find('X'), 1, x);
      *frame_->pre << "  double " << t << " = " << start << ";\n"
                   << "  for (long k = 0; k < " << n << "; ++k) " << step << ";\n";
      return CVal{{}, [t](const std::string &) { return t; }};
    }
    if (name == "size") {
      if (e.args.empty() || e.args[0].value->kind != ast::ExprKind::Ref ||
          e.args[0].value->parts.size() != 1 ||
          !findVar(e.args[0].value->parts[0].name)) {
        unsupported(e, "this size()");
        return std::nullopt;
      }
      const Var *v = findVar(e.args[0].value->parts[0].name);
      if (e.args.size() == 2) {
        std::optional<int64_t> n = shapeInteger(e);
        if (!n)
          return std::nullopt;
        return CVal{{}, [c = number(double(*n))](const std::string &) { return c; }};
      }
      std::vector<std::string> dims;
      for (int64_t d : v->shape)
        dims.push_back(number(double(d)));
      std::string t = temp();
      *frame_->pre << "  static const double " << t << "[] = {";
      for (size_t i = 0; i < dims.size(); ++i)
        *frame_->pre << (i ? ", " : "") << dims[i];
      *frame_->pre << (dims.empty() ? "0" : "") << "};\n";
      return CVal{{int64_t(dims.size())},
                  [t](const std::string &k) { return t + "[" + k + "]"; }};
    }
    if (name == "zeros" || name == "ones" || name == "fill") {
      size_t first = name == "fill" ? 1 : 0;
      std::optional<std::string> fillValue =
          name == "fill" ? (e.args.empty() ? std::nullopt : scalar(*e.args[0].value))
                         : std::optional<std::string>(name == "ones" ? "1.0" : "0.0");
      if (!fillValue)
        return std::nullopt;
      std::vector<int64_t> shape;
      for (size_t i = first; i < e.args.size(); ++i) {
        std::optional<int64_t> n = shapeInteger(*e.args[i].value);
        if (!n)
          return std::nullopt;
        shape.push_back(*n);
      }
      std::string c = *fillValue;
      return CVal{shape, [c](const std::string &) { return c; }};
    }
    static const char *const kRunTimeOnly[] = {
        "der",     "pre",    "edge",     "change",   "sample", "initial",
        "terminal", "delay", "reinit",   "homotopy", "String", "cardinality"};
    for (const char *r : kRunTimeOnly)
      if (name == r) {
        unsupported(e, "'" + name + "()'");
        return std::nullopt;
      }
  }
  std::optional<std::vector<CVal>> outs = userCall(e);
  if (!outs)
    return std::nullopt;
  if (outs->empty()) {
    f_.report(DiagId::ErrFunctionNoOutput, SourceRange{e.loc, e.length},
              {e.text});
    return std::nullopt;
  }
  return (*outs)[0];
}

std::optional<std::vector<FunctionTranslator::CVal>>
FunctionTranslator::userCall(const ast::Expr &e) {
  SourceRange where{e.loc, e.length};
  if (e.kind != ast::ExprKind::Call) {
    unsupported(e, "this call");
    return std::nullopt;
  }
  ast::Name fname = e.calleeName();
  const ast::ClassDef *fn = f_.classes().resolveClass(
      fname, e.global ? nullptr : frame_->scope, frame_->scope->file);
  for (unsigned guard = 0; fn && fn->isShort && guard < 16; ++guard)
    fn = f_.classes().resolveClass(fn->shortBase, fn->parent, fn->file);
  if (!fn)
    return std::nullopt;
  if (fn->kind != ast::ClassKind::Function) {
    f_.report(DiagId::ErrNotAFunction, SourceRange{fname.loc, fname.length},
              {fname.str(), ast::classKindName(fn->kind)});
    return std::nullopt;
  }
  std::optional<Flattener::FunctionParts> parts = f_.functionParts(*fn, where);
  if (!parts)
    return std::nullopt;
  std::vector<const ast::Component *> inputs;
  std::vector<const ast::ClassDef *> inputOwner;
  for (size_t i = 0; i < parts->comps.size(); ++i)
    if (parts->comps[i]->prefix.causality == ast::Causality::Input) {
      inputs.push_back(parts->comps[i]);
      inputOwner.push_back(parts->owner[i]);
    }
  // Positional arguments, then named ones, then defaults (constants).
  std::vector<const ast::Expr *> bound(inputs.size(), nullptr);
  size_t positional = 0;
  for (const ast::Arg &a : e.args) {
    size_t k = positional;
    if (a.name.empty()) {
      ++positional;
    } else {
      for (k = 0; k < inputs.size() && inputs[k]->name != a.name; ++k) {
      }
    }
    if (k >= inputs.size()) {
      f_.report(a.name.empty() ? DiagId::ErrCallArgCount : DiagId::ErrNoSuchInput,
                SourceRange{a.value->loc, a.value->length},
                a.name.empty() ? std::vector<std::string>{fn->name,
                                                          std::to_string(inputs.size()),
                                                          std::to_string(e.args.size())}
                               : std::vector<std::string>{fn->name, a.name});
      return std::nullopt;
    }
    bound[k] = a.value.get();
  }
  std::vector<CVal> in;
  std::vector<std::vector<int64_t>> shapes;
  for (size_t k = 0; k < inputs.size(); ++k) {
    std::optional<CVal> v;
    if (bound[k]) {
      v = value(*bound[k]);
    } else if (inputs[k]->mod && inputs[k]->mod->value) {
      Frame *caller = frame_;
      Frame defaults;
      defaults.scope = inputOwner[k];
      defaults.pre = caller->pre;
      frame_ = &defaults;
      v = constant(*inputs[k]->mod->value);
      frame_ = caller;
    } else {
      f_.report(DiagId::ErrMissingArgument, where, {inputs[k]->name, fn->name});
      return std::nullopt;
    }
    if (!v)
      return std::nullopt;
    shapes.push_back(v->shape);
    in.push_back(std::move(*v));
  }
  std::vector<std::vector<int64_t>> outShapes;
  std::optional<std::string> callee = define(*fn, *parts, shapes, outShapes, where);
  if (!callee)
    return std::nullopt;
  int64_t nin = 0, nout = 0;
  for (const CVal &v : in)
    nin += countOf(v.shape);
  for (const auto &s : outShapes)
    nout += countOf(s);
  std::string ti = temp(), to = temp();
  std::ostringstream &pre = *frame_->pre;
  pre << "  double " << ti << "[" << std::max<int64_t>(1, nin) << "], " << to
      << "[" << std::max<int64_t>(1, nout) << "];\n";
  int64_t off = 0;
  for (const CVal &v : in) {
    int64_t n = countOf(v.shape);
    pre << "  for (long k = 0; k < " << n << "; ++k) " << ti << "[" << off
        << " + k] = " << v.at("k") << ";\n";
    off += n;
  }
  pre << "  " << *callee << "(" << ti << ", " << to << ");\n";
  std::vector<CVal> outs;
  off = 0;
  for (const auto &s : outShapes) {
    std::string base = std::to_string(off);
    outs.push_back(CVal{s, [to, base](const std::string &k) {
                          return to + "[" + base + " + " + k + "]";
                        }});
    off += countOf(s);
  }
  return outs;
}

std::optional<std::vector<Value>>
Flattener::compiledCall(const ast::ClassDef &fn, const FunctionParts &parts,
                        const Env &fenv, SourceRange at) {
  std::vector<std::vector<int64_t>> inputShapes;
  std::vector<ir::ExprRef> in;
  for (const ast::Component *c : parts.comps)
    if (c->prefix.causality == ast::Causality::Input) {
      const Value *v = const_cast<Env &>(fenv).find(c->name);
      if (!v || v->isString) {
        report(DiagId::ErrUnsupported, at,
               {"String inputs of function '" + fn.name +
                "', which runs compiled at run time"});
        return std::nullopt;
      }
      inputShapes.push_back(v->shape);
      in.insert(in.end(), v->elems.begin(), v->elems.end());
    }
  FunctionTranslator translator(*this);
  std::vector<std::vector<int64_t>> outputShapes;
  std::optional<std::string> inner =
      translator.define(fn, parts, inputShapes, outputShapes, at);
  if (!inner)
    return std::nullopt;
  std::string source = translator.source();
  std::string symbol = "ldaecompiled_" + sha256Hex(source).substr(0, 16);
  source += "void " + symbol + "(const double *in, double *out) { " + *inner +
            "(in, out); }\n";
  CBuild build;
  build.source = source;
  build.libraries = {"m"};
  auto loaded = loadCBuild(build, opts_.cacheDir);
  if (!loaded) {
    report(DiagId::ErrExternalBuild, at, {fn.name, loaded.error()});
    return std::nullopt;
  }
  auto entry =
      reinterpret_cast<ir::ExternalEntry>(dlsym(loaded->handle, symbol.c_str()));
  if (!entry) {
    report(DiagId::ErrExternalBuild, at, {fn.name, dlerror()});
    return std::nullopt;
  }
  ir::ExternalFunction f;
  f.name = fn.name;
  f.symbol = symbol;
  f.numInputs = in.size();
  for (const auto &s : outputShapes)
    f.numOutputs += countOf(s);
  f.entry = entry;
  f.objects = {loaded->path};
  if (!externalCallFits(fn, f, at))
    return std::nullopt;
  uint32_t id = ir::registerExternal(f);
  std::vector<Value> results;
  unsigned base = 0;
  for (const auto &s : outputShapes) {
    Value v;
    v.shape = s;
    for (int64_t k = 0; k < countOf(s); ++k)
      v.elems.push_back(ctx().external(id, base + unsigned(k), in));
    base += unsigned(countOf(s));
    results.push_back(std::move(v));
  }
  return results;
}

} // namespace ldae::frontend
