// Pass "linear": when the whole model is linear with constant
// coefficients, E x' = F x + f(t), the Wong sequences of the pencil (E, F)
// (seed 002) say whether it is well-posed (regular pencil: V ⊕ T = R^n),
// its index (the number of W-steps), dim V (the consistent subspace: the
// degrees of freedom) and dim W = dim T (the jump directions). A singular
// pencil is not well-posed: the report names the combinations of unknowns
// left free (V ∩ T) and, when the inputs make the equations inconsistent,
// the combination of equations that conflicts.
//
// It runs first, on the model as written (the system the SGA analyzes, so
// dim V = dim P_f compares like with like): alias elimination substitutes
// equations into others and can lower the index of the pencil (two
// capacitors in parallel: index 2 as written, 1 once v1 = v2 is
// substituted). Structure cannot see numerical cancellation (`der(x) +
// der(y)` in two equations), so a singular pencil that is structurally
// regular is diagnosed here: a warning for a report (`--analyze`), an
// error when the model is to be run. A structurally singular one is
// diagnosed by the passes that name its structure (sga, dm); this
// verdict (free directions, conflict) goes to its report.
//
// Higher derivatives are made first order (x, der(x), ... each a column,
// with rows der(x_k) = x_{k+1}). Linearity is decided per incidence: the
// partial derivative must be free of unknowns, time and pre(), or, when
// the simplifier left an unknown in it, evaluate to the same value at
// random points. Parameters count as constants; discrete variables and
// time may appear in f(t) only. A model that is not linear in this sense
// (even in one equation) gets no linear report: see docs/analysis.md.
#include "passes/Passes.h"
#include "passes/Results.h"

#include "graph/Matching.h"
#include "ir/Differentiate.h"
#include "ir/Evaluate.h"
#include "ir/Query.h"
#include "ir/Substitute.h"
#include "numeric/SparseWong.h"
#include "numeric/WongSequence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <random>

namespace ldae::passes {

namespace {

/// Conflicts are looked for (a polynomial left kernel, dense) only in
/// pencils up to this size, and up to this degree.
constexpr int kConflictMaxSize = 80;
constexpr int kConflictMaxDegree = 4;

/// The pencil of a linear model and what names its rows and columns.
struct LinearModel {
  numeric::SparsePencil pencil;
  std::vector<ir::VarKey> columns; // the state vector: x, der(x), ...
  std::vector<int> rowEquation;    // model equation index, or -1
  std::vector<ir::ExprRef> inputs; // f(t) per row (null: zero)
};

bool readsPre(ir::ExprRef e) {
  for (ir::ExprRef n : ir::topologicalOrder({&e, 1}))
    if (n->kind() == ir::ExprKind::Pre)
      return true;
  return false;
}

bool callsExternal(ir::ExprRef e) {
  for (ir::ExprRef n : ir::topologicalOrder({&e, 1}))
    if (n->kind() == ir::ExprKind::External)
      return true;
  return false;
}

/// The constant value of `partial`, or nullopt when it varies with the
/// unknowns or time.
std::optional<double> constantValue(ir::ExprRef partial,
                                    const ir::EvalEnv &params,
                                    std::mt19937 &rng) {
  if (readsPre(partial))
    return std::nullopt;
  if (ir::freeVariables(partial).empty() && !ir::dependsOnTime(partial)) {
    Expected<double> v = ir::evaluate(partial, params);
    if (!v || !std::isfinite(*v))
      return std::nullopt;
    return *v;
  }
  // C code is called only at values a run can reach: MSL's CombiTimeTable
  // read at a random time and event times crashed in getValue
  // (Interaction1). Such a coefficient is not known to be constant.
  if (callsExternal(partial))
    return std::nullopt;
  // The simplifier may leave a cancelling term ((x + 1)^2 - x^2 - 2x):
  // a value that does not move at random points is constant.
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::optional<double> first;
  for (int trial = 0; trial < 3; ++trial) {
    std::map<ir::VarKey, double> at;
    ir::EvalEnv env = params;
    env.time = u(rng);
    env.variable = [&](ir::VarKey k) {
      auto it = at.find(k);
      if (it == at.end())
        it = at.emplace(k, u(rng)).first;
      return it->second;
    };
    Expected<double> v = ir::evaluate(partial, env);
    if (!v || !std::isfinite(*v))
      return std::nullopt;
    if (!first)
      first = *v;
    else if (std::fabs(*v - *first) > 1e-9 * (1 + std::fabs(*first)))
      return std::nullopt;
  }
  return first;
}

/// E, F and f(t) of the model, or nullopt when it is not linear with
/// constant coefficients.
std::optional<LinearModel> extractPencil(PassContext &ctx) {
  ir::Model &model = ctx.model;
  ir::ExprContext &ec = model.ctx();
  LinearModel lm;
  // The highest order of each unknown in the equations.
  std::vector<int> highest(model.variables.size(), 0);
  for (const ir::Equation &eq : model.equations)
    for (ir::VarKey key : ir::freeVariables(eq.residual))
      highest[key.var] = std::max(highest[key.var], int(key.order));
  // Columns: each unknown at orders 0 .. max(highest - 1, 0).
  std::map<ir::VarKey, int> column; // key -> column (values)
  std::map<ir::VarId, int> top;     // var -> column its highest order hits
  std::vector<std::pair<int, int>> chain; // (col, col of its derivative)
  for (ir::VarId v = 0; v < model.variables.size(); ++v) {
    if (model.variables[v].isDiscrete)
      continue;
    int h = highest[v];
    for (int k = 0; k < std::max(h, 1); ++k) {
      column[{v, unsigned(k)}] = int(lm.columns.size());
      lm.columns.push_back({v, unsigned(k)});
      if (k > 0)
        chain.push_back({int(lm.columns.size()) - 2,
                         int(lm.columns.size()) - 1});
    }
    if (h >= 1)
      top[v] = int(lm.columns.size()) - 1;
  }
  ir::EvalEnv params = ctx.startEnv();
  params.variable = [](ir::VarKey) { return 0.0; };
  std::mt19937 rng(14);
  ir::Differentiator diff(ec);
  ir::Substitution zero(ec);
  for (const auto &[key, col] : column)
    zero.set(ec.var(key), ec.zero());
  for (const auto &[v, col] : top)
    zero.set(ec.var(v, lm.columns[col].order + 1), ec.zero());
  for (int e = 0; e < int(model.equations.size()); ++e) {
    ir::ExprRef r = model.equations[e].residual;
    int row = int(lm.rowEquation.size());
    for (ir::VarKey key : ir::freeVariables(r)) {
      auto it = column.find(key);
      auto t = top.find(key.var);
      bool derivative = t != top.end() &&
                        key.order == lm.columns[t->second].order + 1;
      if (it == column.end() && !derivative)
        continue; // a discrete variable: an input
      std::optional<double> c =
          constantValue(diff.partial(r, key), params, rng);
      if (!c)
        return std::nullopt;
      if (*c == 0)
        continue;
      if (derivative)
        lm.pencil.E.push_back({row, t->second, *c});
      else
        lm.pencil.F.push_back({row, it->second, -*c});
    }
    lm.rowEquation.push_back(e);
    lm.inputs.push_back(ec.neg(zero.apply(r)));
  }
  for (auto [col, next] : chain) {
    int row = int(lm.rowEquation.size());
    lm.pencil.E.push_back({row, col, 1.0});
    lm.pencil.F.push_back({row, next, 1.0});
    lm.rowEquation.push_back(-1);
    lm.inputs.push_back(nullptr);
  }
  lm.pencil.rows = int(lm.rowEquation.size());
  lm.pencil.cols = int(lm.columns.size());
  return lm;
}

/// Whether the pencil's incidence (entries of E or F) has a complete
/// matching: square and structurally nonsingular.
bool structurallyRegular(const numeric::SparsePencil &p) {
  if (p.rows != p.cols)
    return false;
  graph::BipartiteGraph g(p.rows, p.cols);
  std::vector<std::vector<char>> seen(p.rows);
  for (const auto *list : {&p.E, &p.F})
    for (const numeric::SparsePencil::Entry &e : *list)
      if (e.value != 0 &&
          std::find(g.rows[e.row].begin(), g.rows[e.row].end(), e.col) ==
              g.rows[e.row].end())
        g.addEdge(e.row, e.col);
  return graph::maximumMatching(g).size == p.rows;
}

/// `c` as a coefficient in front of a name: "", "-", "2.5*".
std::string coefficientText(double c, bool first) {
  double a = std::fabs(c);
  std::string sign = c < 0 ? (first ? "-" : " - ") : (first ? "" : " + ");
  if (std::fabs(a - 1) < 1e-9)
    return sign;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g*", a);
  return sign + buf;
}

/// The free directions named as text, at most: each costs a sweep over
/// the whole basis, and a model with one equation for 3000 unknowns
/// leaves 2999 (a report names eight of them anyway).
constexpr Eigen::Index kMaxDirectionTexts = 64;

/// The free directions as combinations of unknowns: the first rows of the
/// reduced row echelon form of the basis, each with a leading 1 (past
/// kMaxDirectionTexts rows the elimination stops; the rows named are still
/// free directions).
std::vector<std::string> directionTexts(const Eigen::MatrixXd &basis,
                                        const LinearModel &lm,
                                        const ir::Model &model) {
  // Column j of `d` is direction j, so the elimination works on contiguous
  // columns (the echelon form's rows are d's columns).
  Eigen::MatrixXd d = basis;
  const Eigen::Index unknowns = d.rows(), dirs = d.cols();
  const Eigen::Index named = std::min(dirs, kMaxDirectionTexts);
  Eigen::Index pr = 0;
  for (Eigen::Index c = 0; c < unknowns && pr < named; ++c) {
    Eigen::Index best;
    double mag = d.row(c).tail(dirs - pr).cwiseAbs().maxCoeff(&best);
    if (mag < 1e-9)
      continue;
    d.col(pr).swap(d.col(pr + best));
    d.col(pr) /= d(c, pr);
    for (Eigen::Index j = 0; j < dirs; ++j)
      if (j != pr && d(c, j) != 0)
        d.col(j) -= d(c, j) * d.col(pr);
    ++pr;
  }
  std::vector<std::string> out;
  for (Eigen::Index j = 0; j < pr; ++j) {
    std::string text;
    for (Eigen::Index c = 0; c < unknowns; ++c)
      if (std::fabs(d(c, j)) > 1e-9) {
        text += coefficientText(d(c, j), text.empty());
        text += model.variableName(lm.columns[c]);
      }
    out.push_back(text);
  }
  return out;
}

/// The first left-kernel combination of the equations whose input
/// condition fails, as text (empty when the inputs are consistent as far
/// as the search reaches). `rows` receives the equations involved.
std::string findConflict(PassContext &ctx, const LinearModel &lm,
                         std::vector<int> &rows) {
  const numeric::SparsePencil &p = lm.pencil;
  if (p.rows > kConflictMaxSize || p.cols > kConflictMaxSize)
    return "";
  Eigen::MatrixXd E, F;
  numeric::densePencil(p, E, F);
  ir::ExprContext &ec = ctx.model.ctx();
  ir::Differentiator diff(ec);
  // f^(k) of each row, made on demand.
  std::vector<std::vector<ir::ExprRef>> derivs(p.rows);
  auto input = [&](int row, int k) -> ir::ExprRef {
    std::vector<ir::ExprRef> &d = derivs[row];
    if (d.empty())
      d.push_back(lm.inputs[row] ? lm.inputs[row] : ec.zero());
    while (int(d.size()) <= k)
      d.push_back(diff.timeDerivative(d.back()));
    return d[k];
  };
  ir::EvalEnv env = ctx.startEnv();
  for (int degree = 0; degree <= kConflictMaxDegree; ++degree) {
    Eigen::MatrixXd w = numeric::leftPolynomialKernel(E, F, degree);
    for (Eigen::Index j = 0; j < w.cols(); ++j) {
      Eigen::VectorXd v = w.col(j) / w.col(j).cwiseAbs().maxCoeff();
      // Lead with a positive coefficient: "(a) - d/dt (b)".
      for (Eigen::Index i = 0; i < v.size(); ++i)
        if (std::fabs(v(i)) >= 1e-9) {
          if (v(i) < 0)
            v = -v;
          break;
        }
      std::vector<ir::ExprRef> terms;
      std::string comb;
      rows.clear();
      for (int k = 0; k <= degree; ++k)
        for (int i = 0; i < p.rows; ++i) {
          double c = v(k * p.rows + i);
          if (std::fabs(c) < 1e-9 || lm.rowEquation[i] < 0)
            continue;
          if (std::fabs(c - std::round(c)) < 1e-9)
            c = std::round(c);
          terms.push_back(ec.mul(ec.constant(c), input(i, k)));
          std::string eq = "(" + ctx.equationText(lm.rowEquation[i]) + ")";
          comb += coefficientText(c, comb.empty()) +
                  (k == 0 ? eq
                   : k == 1 ? "d/dt " + eq
                            : "d" + std::to_string(k) + "/dt" +
                                  std::to_string(k) + " " + eq);
          if (std::find(rows.begin(), rows.end(), lm.rowEquation[i]) ==
              rows.end())
            rows.push_back(lm.rowEquation[i]);
        }
      ir::ExprRef cond = ec.add(terms);
      bool violated = false;
      for (double t : {0.0, 0.37, 1.3}) {
        env.time = t;
        Expected<double> val = ir::evaluate(cond, env);
        if (val && std::fabs(*val) > 1e-8 * (1 + terms.size()))
          violated = true;
      }
      if (violated)
        return comb + " leaves " + ir::printLsd(cond, &ctx.model) +
               " = 0, which the inputs violate";
    }
  }
  rows.clear();
  return "";
}

class LinearPencilPass
    : public TypedPass<LinearPencilPass, Reads<>, Updates<>, Produces<>> {
public:
  LinearPencilPass() : TypedPass(PassId::Linear) {}

  bool runOn(PassContext &ctx) {
    ctx.report.linear.reset();
    std::optional<LinearModel> lm = extractPencil(ctx);
    if (!lm || lm->pencil.cols == 0)
      return true;
    numeric::PencilAnalysis a = numeric::analyzePencil(lm->pencil);
    if (!a.computed)
      return true;
    LinearReport rep;
    rep.regular = a.regular;
    rep.index = a.stepsW;
    rep.dimV = a.dimV;
    rep.dimW = a.dimW;
    std::vector<int> conflictRows;
    if (!a.regular) {
      rep.freeDirections = directionTexts(a.freeDirections, *lm, ctx.model);
      rep.freeCount = size_t(a.freeCount);
      rep.conflict = findConflict(ctx, *lm, conflictRows);
    }
    ctx.report.linear = rep;
    // Not regular but nothing free and no conflict: more equations than
    // unknowns, consistent (the SGA names the redundant ones).
    if (rep.freeDirections.empty() && rep.conflict.empty())
      return true;
    // A structurally singular model is diagnosed and refused by the passes
    // that name its structure (sga, dm): this verdict goes to the report
    // only. What structure cannot see (cancellation) is diagnosed here.
    if (!structurallyRegular(lm->pencil))
      return true;
    diagnose(ctx, rep, *lm, conflictRows, !ctx.opts.reportOnly);
    return ctx.opts.reportOnly;
  }

private:
  static void diagnose(PassContext &ctx, const LinearReport &rep,
                       const LinearModel &lm, const std::vector<int> &rows,
                       bool error) {
    std::string why;
    if (!rep.freeDirections.empty())
      why = "nothing determines " +
            quotedFew(rep.freeDirections, rep.freeCount);
    if (!rep.conflict.empty())
      why += (why.empty() ? "" : "; ") + rep.conflict;
    if (why.empty())
      why = "the solution is not unique";
    std::vector<int> involved = rows;
    if (involved.empty())
      for (int e : lm.rowEquation)
        if (e >= 0)
          involved.push_back(e);
    SourceLoc at = involved.empty() ? ctx.model.loc
                                    : ctx.model.equations[involved[0]].loc;
    Diagnostic &d = ctx.diags.report(error ? DiagId::ErrLinearSingularPencil
                                           : DiagId::WarnLinearSingularPencil,
                                     at, {why});
    for (size_t i = 0; i < involved.size() && i < 8; ++i)
      DiagnosticEngine::addNote(d, ctx.model.equations[involved[i]].loc,
                                DiagId::NoteEquationInvolved,
                                {ctx.equationText(involved[i])});
  }
};

} // namespace

std::unique_ptr<Pass> createLinearPencilPass() {
  return std::make_unique<LinearPencilPass>();
}

} // namespace ldae::passes
