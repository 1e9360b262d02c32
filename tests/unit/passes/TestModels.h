// Small models built with the IR API for the pass tests: a builder that
// gives every variable and equation a line in a fake source file, and the
// classic index examples (pendulum, Mattsson–Söderlind, RLC loop).
#pragma once

#include "ir/Model.h"
#include "passes/Pipeline.h"
#include "support/Diagnostics.h"

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace ldae::passtest {

/// Builds a model whose declarations and equations sit on numbered lines of
/// `file` (line = order of creation, starting at 2), so messages can cite
/// them.
class Builder {
public:
  explicit Builder(std::string name, std::string file = "test.lsd")
      : file_(std::move(file)) {
    model.name = std::move(name);
  }

  ir::Model model;

  ir::ExprRef var(const std::string &name, double start = 0,
                  bool fixed = false,
                  ir::StateSelect ss = ir::StateSelect::Default) {
    if (auto id = model.findVariable(name))
      return model.ctx().var(*id);
    ir::Variable v;
    v.name = name;
    v.start = start;
    v.hasStart = start != 0 || fixed;
    v.fixed = fixed;
    v.stateSelect = ss;
    v.loc = nextLoc("Real " + name + ";");
    return model.ctx().var(model.addVariable(v));
  }
  ir::ExprRef param(const std::string &name, double value) {
    ir::Parameter p;
    p.name = name;
    p.value = value;
    p.loc = nextLoc("parameter Real " + name + ";");
    return model.ctx().param(model.addParameter(p));
  }
  ir::ExprRef der(ir::ExprRef v, unsigned k = 1) {
    return model.ctx().var(v->var(), v->order() + k);
  }
  /// lhs = rhs, written as `text` on the next line.
  void eq(ir::ExprRef lhs, ir::ExprRef rhs, const std::string &text,
          ir::EquationOrigin origin = ir::EquationOrigin::Declared) {
    ir::Equation e;
    e.residual = model.ctx().sub(lhs, rhs);
    e.text = text;
    e.origin = origin;
    e.loc = nextLoc(text + ";");
    model.equations.push_back(e);
  }
  void initialEq(ir::ExprRef lhs, ir::ExprRef rhs, const std::string &text) {
    ir::Equation e;
    e.residual = model.ctx().sub(lhs, rhs);
    e.text = text;
    e.origin = ir::EquationOrigin::Initial;
    e.loc = nextLoc(text + ";");
    model.initialEquations.push_back(e);
  }

  /// Registers the source text; call once before analysis.
  SourceManager &sources() {
    if (!registered_) {
      std::string text = "model " + model.name + "\n";
      for (const std::string &l : lines_)
        text += "  " + l + "\n";
      uint32_t id = sm_.addFile(file_, text);
      (void)id;
      registered_ = true;
    }
    return sm_;
  }

  ir::ExprContext &ctx() { return model.ctx(); }

private:
  SourceLoc nextLoc(const std::string &line) {
    lines_.push_back(line);
    return SourceLoc{1, static_cast<uint32_t>(lines_.size() + 1), 3};
  }
  std::string file_;
  std::vector<std::string> lines_;
  SourceManager sm_;
  bool registered_ = false;
};

/// Runs the pipeline; returns the result, diagnostics in `messages`.
struct Outcome {
  passes::AnalysisResult result;
  bool ok = false;
  std::vector<Diagnostic> diags;
  std::string messages;
};

/// Options that stop at the index-1 system as index reduction builds it:
/// these tests check index reduction, not the causal form (see
/// tests/lang/analysis/causalize.lsd for that).
inline passes::PipelineOptions indexOneOptions() {
  passes::PipelineOptions opts;
  opts.causalize = false;
  return opts;
}

inline Outcome analyze(Builder &b,
                       passes::PipelineOptions opts = indexOneOptions()) {
  Outcome run;
  DiagnosticEngine diags(b.sources());
  run.ok = passes::runPipeline(b.model, opts, diags, run.result);
  run.diags = diags.diagnostics();
  for (const Diagnostic &d : run.diags) {
    run.messages += d.message + "\n";
    for (const Diagnostic &n : d.notes)
      run.messages += "  note: " + n.message + "\n";
  }
  return run;
}

/// The Cartesian pendulum in first-order form; `order` permutes the
/// declarations and equations (identity when empty).
inline void pendulumFirstOrder(Builder &b, std::vector<int> order = {},
                               double x0 = 1, double y0 = 0) {
  auto &c = b.ctx();
  std::vector<std::function<void()>> decls = {
      [&] { b.var("x", x0); }, [&] { b.var("y", y0); },
      [&] { b.var("u"); },     [&] { b.var("v"); },
      [&] { b.var("lam"); }};
  std::vector<int> perm = order.empty() ? std::vector<int>{0, 1, 2, 3, 4}
                                        : order;
  for (int i : perm)
    decls[i]();
  ir::ExprRef L = b.param("L", 1), g = b.param("g", 9.81);
  ir::ExprRef x = b.var("x"), y = b.var("y"), u = b.var("u"), v = b.var("v"),
              lam = b.var("lam");
  std::vector<std::function<void()>> eqs = {
      [&] { b.eq(b.der(x), u, "der(x) = u"); },
      [&] { b.eq(b.der(y), v, "der(y) = v"); },
      [&] { b.eq(b.der(u), c.neg(c.mul(lam, x)), "der(u) = -lam * x"); },
      [&] {
        b.eq(b.der(v), c.sub(c.neg(c.mul(lam, y)), g), "der(v) = -lam * y - g");
      },
      [&] {
        b.eq(c.add(c.pow(x, c.constant(2)), c.pow(y, c.constant(2))),
             c.pow(L, c.constant(2)), "x^2 + y^2 = L^2");
      }};
  for (int i : perm)
    eqs[i]();
}

} // namespace ldae::passtest
