// Pass "init": the initialization system of the index-1 system at the
// start time: every residual (so every constraint index reduction found),
// the fixed start values and the initial equations, over y and the
// derivatives of the states. Start values without `fixed` are guesses.
// Over-specified conditions are found structurally (Dulmage–Mendelsohn:
// which fixed values over-determine what, how many the model can take,
// which to free), then checked numerically: redundant conditions that
// agree are accepted with a warning, conflicting ones are an error. A rank
// check at the start point catches dependencies structure cannot see.
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/SystemStructure.h"

#include "graph/DulmageMendelsohn.h"
#include "graph/Matching.h"
#include "ir/Differentiate.h"
#include "ir/Evaluate.h"
#include "ir/Query.h"
#include "numeric/Newton.h"
#include "numeric/Rank.h"

#include <algorithm>
#include <unordered_set>
#include <cmath>

namespace ldae::passes {

namespace {

constexpr int kDenseLimit = 400;

/// Rows of the initialization system and how to evaluate them.
struct InitSystem {
  graph::BipartiteGraph g;
  std::vector<ir::ExprRef> expr; // residual rows (nullptr for fixed rows)
  std::vector<int> fixedUnknown; // per row: the fixed unknown or -1
  std::vector<SourceLoc> loc;
  std::vector<std::string> text; // empty: print `expr` when needed
  std::vector<double> start; // per column
  std::vector<std::string> colName;
  std::vector<int> colOfDerivative; // unknown -> column of y' or -1
};

/// The start environment with the unknowns read from column values `x`
/// (kept by reference).
ir::EvalEnv envAt(const PassContext &s, const InitSystem &is,
                  const SystemLayout &layout, const std::vector<double> &x) {
  ir::EvalEnv env = s.initializationEnv();
  env.variable = [&is, &layout, &x](ir::VarKey k) {
    SlotRead sr = layout.read(k);
    if (sr.unknown < 0)
      return 0.0;
    int c = sr.derivative ? is.colOfDerivative[sr.unknown] : sr.unknown;
    return c >= 0 ? x[c] : 0.0;
  };
  return env;
}

/// Evaluates rows `rows` at column values `x` (columns outside `cols` at
/// their start values).
Eigen::VectorXd evalRows(const PassContext &s, const InitSystem &is,
                         const SystemLayout &layout,
                         const std::vector<int> &rows,
                         const std::vector<double> &x) {
  ir::EvalEnv env = envAt(s, is, layout, x);
  Eigen::VectorXd r(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    int row = rows[i];
    if (is.fixedUnknown[row] >= 0) {
      r[i] = x[is.fixedUnknown[row]] - is.start[is.fixedUnknown[row]];
      continue;
    }
    auto v = ir::evaluate(is.expr[row], env);
    r[i] = v ? *v : std::numeric_limits<double>::quiet_NaN();
  }
  return r;
}

/// `rows` as a function of the values of `cols` (the other columns at
/// their start values), for compiler/numeric.
numeric::ResidualFn rowsFunction(const PassContext &s, const InitSystem &is,
                                 const SystemLayout &layout,
                                 const std::vector<int> &rows,
                                 const std::vector<int> &cols) {
  return [&, x = is.start](const Eigen::VectorXd &v,
                           Eigen::VectorXd &r) mutable {
    for (size_t k = 0; k < cols.size(); ++k)
      x[cols[k]] = v[k];
    r = evalRows(s, is, layout, rows, x);
    return true; // a NaN row is a failed evaluation for the caller
  };
}

/// The start values of `cols`.
Eigen::VectorXd startOf(const InitSystem &is, const std::vector<int> &cols) {
  Eigen::VectorXd x(cols.size());
  for (size_t k = 0; k < cols.size(); ++k)
    x[k] = is.start[cols[k]];
  return x;
}

/// Gauss–Newton on `rows` over `cols` from the start values (residuals
/// below 1e-9 in the units of the unknowns); true if they can all hold.
bool solvable(const PassContext &s, const InitSystem &is,
              const SystemLayout &layout, const std::vector<int> &rows,
              const std::vector<int> &cols) {
  Eigen::VectorXd x = startOf(is, cols);
  return numeric::gaussNewton(rowsFunction(s, is, layout, rows, cols), {}, x)
      .converged();
}

/// The analysis of the pass, reported into `rep` as it goes (the report
/// of a failed initialization says how far it got).
bool analyzeInitialization(PassContext &s, const ir::DaeSystem &sys,
                           const BltResult &blt, InitReport &rep) {
  const ir::StateSet &st = sys.stateSets[0];
  const int n = static_cast<int>(sys.unknowns.size());
  SystemLayout layout(sys, 0);
  rep.analyzed = true;

  InitSystem is;
  is.colOfDerivative.assign(n, -1);
  for (int u = 0; u < n; ++u) {
    is.start.push_back(sys.unknowns[u].start);
    is.colName.push_back(sys.unknowns[u].name);
  }
  for (int u = 0; u < n; ++u)
    if (st.differential[u]) {
      is.colOfDerivative[u] = static_cast<int>(is.start.size());
      is.start.push_back(sys.unknowns[u].startDerivative);
      is.colName.push_back("der(" + sys.unknowns[u].name + ")");
    }
  is.g.numCols = static_cast<int>(is.start.size());
  auto addRow = [&](ir::ExprRef e, int fixed, SourceLoc loc, std::string text,
                    const std::vector<SlotRead> *known = nullptr) {
    std::vector<int> cols;
    if (fixed >= 0) {
      cols.push_back(fixed);
    } else {
      std::vector<SlotRead> reads;
      if (!known) {
        for (ir::VarKey k : variablesOf(e)) {
          SlotRead sr = layout.read(k);
          if (sr.unknown >= 0)
            reads.push_back(sr);
        }
        known = &reads;
      }
      for (SlotRead sr : *known)
        cols.push_back(sr.derivative ? is.colOfDerivative[sr.unknown]
                                     : sr.unknown);
      std::sort(cols.begin(), cols.end());
      cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
    }
    is.g.addRow(std::move(cols));
    is.expr.push_back(e);
    is.fixedUnknown.push_back(fixed);
    is.loc.push_back(loc);
    is.text.push_back(std::move(text));
  };
  for (size_t r = 0; r < st.residuals.size(); ++r)
    addRow(st.residuals[r], -1,
           r < sys.residualLocs.size() ? sys.residualLocs[r] : SourceLoc{},
           "", blt.reads.empty() ? nullptr : &blt.reads[0][r]);
  const int firstFixed = is.g.numRows();
  for (int u = 0; u < n; ++u)
    if (sys.unknowns[u].fixed) {
      rep.fixed.push_back(sys.unknowns[u].name);
      addRow(nullptr, u, sys.unknowns[u].loc,
             sys.unknowns[u].name + " = " +
                 ir::printNumber(sys.unknowns[u].start));
    } else if (sys.unknowns[u].key.order == 0 &&
               s.model.variables[sys.unknowns[u].key.var].hasStart) {
      rep.guesses.push_back(sys.unknowns[u].name);
    }
  const int firstInitial = is.g.numRows();
  for (size_t i = 0; i < sys.initialResiduals.size(); ++i) {
    const ir::Equation *eq = i < s.model.initialEquations.size()
                                 ? &s.model.initialEquations[i]
                                 : nullptr;
    addRow(sys.initialResiduals[i], -1, eq ? eq->loc : SourceLoc{},
           eq && !eq->text.empty()
               ? eq->text
               : ir::printLsd(sys.initialResiduals[i], &s.model) + " = 0");
  }
  rep.initialEquations = is.g.numRows() - firstInitial;
  rep.unknowns = is.g.numCols;
  rep.equations = is.g.numRows();
  rep.dof = rep.unknowns - rep.equations;

  auto textOf = [&](int r) {
    // Bounded: substituted expressions of a shared DAG grow exponentially
    // when written out (a heat grid's took minutes; issue 28).
    if (is.text[r].empty())
      is.text[r] = ir::printLsdBrief(is.expr[r], &s.model, 400) + " = 0";
    return is.text[r];
  };
  graph::Matching m = graph::maximumMatching(is.g);
  for (int r = firstFixed; r < firstInitial; ++r)
    if (m.rowMate[r] >= 0)
      rep.honoured.push_back(is.colName[is.fixedUnknown[r]]);
  if (m.size < is.g.numRows()) {
    graph::DmDecomposition dm = graph::dulmageMendelsohn(is.g, m);
    std::vector<int> fixedRows;
    for (int r : dm.over.rows)
      if (is.fixedUnknown[r] >= 0)
        fixedRows.push_back(r);
    if (fixedRows.empty()) {
      SingularityNames names;
      names.rowLoc = [&](int r) { return is.loc[r]; };
      names.rowText = textOf;
      names.colName = [&](int c) { return is.colName[c]; };
      names.colLoc = [&](int c) {
        return c < n ? sys.unknowns[c].loc : SourceLoc{};
      };
      diagnoseSingular(s, "initialization", is.g, m, names, {}, false);
      rep.consistent = false;
      return false;
    }
    // Which fixed values to keep: match everything else first, then add
    // the fixed values one by one in canonical order; those that no longer
    // fit are the ones to free.
    graph::BipartiteGraph partial(0, is.g.numCols);
    for (int r = 0; r < is.g.numRows(); ++r)
      partial.addRow(is.fixedUnknown[r] >= 0 ? std::vector<int>{}
                                             : is.g.rows[r]);
    graph::Matching pm = graph::maximumMatching(partial);
    std::vector<char> honoured(is.g.numRows(), 0);
    for (int r = firstFixed; r < firstInitial; ++r) {
      partial.rows[r] = is.g.rows[r];
      graph::Matching next = graph::maximumMatching(partial, {}, &pm);
      if (next.size > pm.size) {
        honoured[r] = 1;
        pm = std::move(next);
      } else {
        partial.rows[r].clear();
      }
    }
    rep.honoured.clear();
    for (int r = firstFixed; r < firstInitial; ++r)
      if (honoured[r])
        rep.honoured.push_back(is.colName[is.fixedUnknown[r]]);
    int canTake = 0;
    for (int r : fixedRows) {
      const std::string &name = is.colName[is.fixedUnknown[r]];
      rep.conflicting.push_back(name);
      if (honoured[r])
        ++canTake;
      else
        rep.toFree.push_back(name);
    }
    if (solvable(s, is, layout, dm.over.rows, dm.over.cols) &&
        static_cast<int>(dm.over.cols.size()) <= kDenseLimit) {
      s.diags.report(DiagId::WarnInitRedundant,
                     is.loc[fixedRows.front()],
                     {quotedList(rep.conflicting), std::to_string(canTake),
                      quotedList(rep.toFree)});
      rep.consistent = true;
    } else {
      Diagnostic &d = s.diags.report(
          DiagId::ErrInitOverSpecified, is.loc[fixedRows.front()],
          {quotedList(rep.conflicting), std::to_string(canTake),
           quotedList(rep.toFree)});
      for (int r : dm.over.rows)
        if (is.fixedUnknown[r] < 0)
          DiagnosticEngine::addNote(d, is.loc[r], DiagId::NoteEquationInvolved,
                                    {textOf(r)});
      rep.consistent = false;
      return false;
    }
    return true;
  }

  // Numeric rank at the start point: a fixed value the constraints already
  // pin there cannot be met by Newton steps.
  if (is.g.numCols <= kDenseLimit && firstInitial > firstFixed) {
    std::vector<int> rows(is.g.numRows()), cols(is.g.numCols);
    for (int r = 0; r < is.g.numRows(); ++r)
      rows[r] = r;
    for (int c = 0; c < is.g.numCols; ++c)
      cols[c] = c;
    numeric::ResidualFn f = rowsFunction(s, is, layout, rows, cols);
    Eigen::VectorXd x = startOf(is, cols), r0;
    Eigen::MatrixXd J;
    f(x, r0);
    // The exact Jacobian (symbolic partials at the start point) where
    // every entry evaluates: a zero is then a zero and a small entry the
    // model's own (a 1e-14 F capacitance's der(v) at 1e-14 after the rows
    // are equilibrated), so the columns can be equilibrated too. Forward
    // differences give z^2 at z = 0 a slope of 1e-7, above a real
    // inductance's L/R.
    bool exact = true;
    {
      Eigen::MatrixXd Je = Eigen::MatrixXd::Zero(r0.size(), x.size());
      ir::Differentiator diff(s.model.ctx());
      std::vector<double> xs(x.data(), x.data() + x.size());
      ir::EvalEnv env = envAt(s, is, layout, xs);
      for (int r = 0; exact && r < is.g.numRows(); ++r) {
        if (is.fixedUnknown[r] >= 0) {
          Je(r, is.fixedUnknown[r]) = 1;
          continue;
        }
        for (ir::VarKey k : variablesOf(is.expr[r])) {
          SlotRead sr = layout.read(k);
          if (sr.unknown < 0)
            continue;
          int c = sr.derivative ? is.colOfDerivative[sr.unknown] : sr.unknown;
          if (c < 0)
            continue;
          ir::ExprRef d = diff.partial(is.expr[r], k);
          if (d->isConstant(0))
            continue;
          auto v = ir::evaluate(d, env);
          if (!v || !std::isfinite(*v)) {
            exact = false;
            break;
          }
          Je(r, c) += *v;
        }
      }
      if (exact)
        J = std::move(Je);
    }
    if ((exact || numeric::finiteDifferenceJacobian(f, x, r0, J)) &&
        J.allFinite()) {
      // Each row equilibrated (the rank is the same): a row divided by an
      // inductance (1/L = 2e4) beside rows of an off diode's conductance
      // (1e-3) must not make those look like round-off of the rank
      // tolerance, relative to the largest entry (MSL's Rectifier).
      auto equilibrateRows = [&J] {
        for (Eigen::Index r = 0; r < J.rows(); ++r)
          if (double big = J.row(r).cwiseAbs().maxCoeff(); big > 0)
            J.row(r) /= big;
      };
      equilibrateRows();
      // Then each column to its largest entry in the model's constraints,
      // and the rows again (the fixed rows stay unit rows, the others keep
      // their largest entry 1): the rank of D1 J D2 is that of J. An
      // inductance (L = 2e-6 beside R = 10: der(i) at 2e-7) and an off
      // resistance (vAK/Roff at 1e-6) multiplied into a pivot of 2e-13,
      // below the tolerance though the fixed current is independent (MSL's
      // ThyristorBehaviourTest, SimpleTriacCircuit). Only the exact
      // Jacobian's columns: a difference quotient's error scaled up would
      // be taken for the model's.
      for (Eigen::Index c = 0; exact && firstFixed > 0 && c < J.cols(); ++c)
        if (double big = J.col(c).head(firstFixed).cwiseAbs().maxCoeff();
            big > 0)
          J.col(c) /= big;
      equilibrateRows();
      // Add the fixed rows one by one after the residuals.
      Eigen::MatrixXd base = J.topRows(firstFixed);
      auto rankOf = [](const Eigen::MatrixXd &A) {
        return numeric::numericRank(A, 1e-9);
      };
      int rank = rankOf(base);
      std::vector<std::string> dependent;
      for (int r = firstFixed; r < firstInitial; ++r) {
        Eigen::MatrixXd next(base.rows() + 1, base.cols());
        next << base, J.row(r);
        int nr = rankOf(next);
        if (nr == rank)
          dependent.push_back(is.colName[is.fixedUnknown[r]]);
        base = std::move(next);
        rank = nr;
      }
      if (!dependent.empty())
        s.diags.report(DiagId::WarnInitNumericallyRedundant, SourceLoc{},
                       {quotedList(dependent)});
    }
  }
  return true;
}

// The unreduced system of `--method raw` has no meaningful initialization
// structure when the index exceeds one: raw does not run this pass.
class InitializationPass
    : public TypedPass<InitializationPass, Reads<BltResult>,
                       Updates<ir::DaeSystem>, Produces<InitResult>> {
public:
  InitializationPass() : TypedPass(PassId::Init) {}

  bool runOn(PassContext &ctx, const BltResult &blt, ir::DaeSystem &sys,
             InitResult &out) {
    bool ok = analyzeInitialization(ctx, sys, blt, out.report);
    ctx.report.init = out.report;
    // Redundant fixed values that agree: the ones the model cannot take
    // become guesses. Holding them all would ask the runtime to meet the
    // same condition twice, which values consistent only to rounding (the
    // test set's 16 digits) cannot do to its tolerance.
    if (ok && out.report.consistent && !out.report.toFree.empty()) {
      std::unordered_set<std::string> free(out.report.toFree.begin(),
                                           out.report.toFree.end());
      for (ir::SystemUnknown &u : sys.unknowns)
        if (u.fixed && free.count(u.name))
          u.fixed = false;
    }
    return ok;
  }
};

} // namespace

std::unique_ptr<Pass> createInitializationPass() {
  return std::make_unique<InitializationPass>();
}

} // namespace ldae::passes
