// Pass "pantelides": finds which equations to differentiate, and how
// often, on the model as written: a variable's derivatives der(x),
// der(x, 2)... are columns chained by graph::Pantelides, so der(der(x))
// needs no first-order form. Equations are differentiated symbolically
// (ir::Differentiator::timeDerivative) as the algorithm asks, so the
// incidence of a derivative is what the symbolic layer finds.
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/Sga.h"
#include "passes/SystemStructure.h"

#include "graph/Pantelides.h"
#include "ir/Differentiate.h"
#include "ir/Print.h"
#include "ir/Query.h"
#include "ir/Substitute.h"

#include <algorithm>
#include <ostream>

namespace ldae::passes {

namespace {

/// Pantelides on the unknowns and equations `mr` names in `m`, filling
/// `s` (rows, highest orders, most differentiations); the status of the
/// run.
graph::Pantelides::Status reduce(ir::Model &m, const MatchingResult &mr,
                                 IndexReduction &s);

/// Pryce's structural index of what `s` found: the most differentiations,
/// plus one when an unknown stays algebraic (it needs one more to become
/// an ODE).
int structuralIndex(const IndexReduction &s) {
  bool anyAlgebraic = false;
  for (int h : s.highest)
    anyAlgebraic = anyAlgebraic || h == 0;
  return s.maxTimes + (anyAlgebraic ? 1 : 0);
}

class PantelidesPass
    : public TypedPass<PantelidesPass, Reads<MatchingResult>, Updates<>,
                       Produces<IndexReduction>> {
public:
  explicit PantelidesPass(const PantelidesOptions &opts)
      : TypedPass(PassId::Pantelides), opts_(opts) {}

  bool runOn(PassContext &pc, const MatchingResult &mr, IndexReduction &s);
  void print(PassContext &pc, ResultStore &results,
             std::ostream &out) const override;

private:
  PantelidesOptions opts_;
};

graph::Pantelides::Status reduce(ir::Model &m, const MatchingResult &mr,
                                 IndexReduction &s) {
  ir::ExprContext &ctx = m.ctx();
  const int nu = static_cast<int>(mr.unknowns.size());

  // Columns: every unknown at every order 0..its highest in the model.
  std::vector<std::vector<int>> colOf(nu);
  std::vector<std::pair<int, unsigned>> colKey; // (unknown, order)
  std::vector<int> varDiff;
  for (int j = 0; j < nu; ++j)
    for (int k = 0; k <= mr.originalOrder[j]; ++k) {
      int c = static_cast<int>(colKey.size());
      colKey.emplace_back(j, k);
      varDiff.push_back(-1);
      if (k > 0)
        varDiff[colOf[j].back()] = c;
      colOf[j].push_back(c);
    }
  graph::BipartiteGraph g(0, static_cast<int>(colKey.size()));
  s.rows.clear();
  auto incidence = [&](ir::ExprRef e, graph::Pantelides *p) {
    std::vector<int> cols;
    for (ir::VarKey k : variablesOf(e)) {
      if (k.var >= mr.unknownIndex.size() || mr.unknownIndex[k.var] < 0)
        continue;
      int j = mr.unknownIndex[k.var];
      while (static_cast<int>(colOf[j].size()) <= static_cast<int>(k.order)) {
        int c = p->derivativeColumn(colOf[j].back());
        colKey.emplace_back(j, colOf[j].size());
        colOf[j].push_back(c);
      }
      cols.push_back(colOf[j][k.order]);
    }
    return cols;
  };
  for (size_t r = 0; r < mr.equations.size(); ++r) {
    Row row;
    row.residual = m.equations[mr.equations[r]].residual;
    row.equation = static_cast<int>(r);
    s.rows.push_back(row);
    g.addRow(incidence(row.residual, nullptr));
  }

  // Discrete variables are constant between events: their derivatives are 0.
  ir::Substitution discrete(ctx);
  bool anyDiscrete = false;
  for (ir::VarId v = 0; v < m.variables.size(); ++v)
    if (m.variables[v].isDiscrete)
      for (unsigned k = 1; k <= 3; ++k) {
        discrete.set(ctx.var(v, k), ctx.zero());
        anyDiscrete = true;
      }

  graph::Pantelides p(std::move(g), std::move(varDiff));
  ir::Differentiator diff(ctx);
  auto hook = [&](int r) {
    ir::ExprRef d = diff.timeDerivative(s.rows[r].residual);
    if (anyDiscrete)
      d = discrete.apply(d);
    Row row;
    row.residual = d;
    row.equation = s.rows[r].equation;
    row.times = s.rows[r].times + 1;
    s.rows[r].next = static_cast<int>(s.rows.size());
    s.rows.push_back(row);
    return incidence(d, &p);
  };
  graph::Pantelides::Result res = p.run(hook);
  if (res.status != graph::Pantelides::Status::Ok)
    return res.status;

  s.highest.assign(nu, 0);
  for (int j = 0; j < nu; ++j) {
    int c = colOf[j][0], k = 0;
    while (p.varDiff()[c] >= 0) {
      c = p.varDiff()[c];
      ++k;
    }
    s.highest[j] = k;
  }
  s.maxTimes = 0;
  for (size_t r = 0; r < mr.equations.size(); ++r) {
    int times = 0;
    for (int x = s.rows[r].next; x >= 0; x = s.rows[x].next)
      ++times;
    s.maxTimes = std::max(s.maxTimes, times);
  }
  return graph::Pantelides::Status::Ok;
}

bool PantelidesPass::runOn(PassContext &pc, const MatchingResult &mr,
                           IndexReduction &s) {
  ir::Model &m = pc.model;
  graph::Pantelides::Status status = reduce(m, mr, s);
  if (status != graph::Pantelides::Status::Ok) {
    pc.diags.report(DiagId::ErrIndexReductionFailed, m.loc,
                   {status == graph::Pantelides::Status::NoProgress
                        ? "the differentiated equations lost unknowns the "
                          "structure needs (cancellation)"
                        : "the model is structurally singular"});
    return false;
  }
  for (size_t r = 0; r < mr.equations.size(); ++r) {
    int times = 0;
    for (int x = s.rows[r].next; x >= 0; x = s.rows[x].next)
      ++times;
    if (times > 0) {
      const ir::Equation &eq = m.equations[mr.equations[r]];
      pc.report.differentiated.push_back(
          {pc.equationText(mr.equations[r]), pc.where(eq.loc), times});
    }
  }
  pc.report.structuralIndex = structuralIndex(s);
  if (!opts_.reduce) {
    // Hand on the model as written: its equations only, every unknown
    // at its order in the model, so nothing becomes a dummy derivative.
    s.rows.resize(mr.equations.size());
    for (Row &row : s.rows)
      row.next = -1;
    s.highest = mr.originalOrder;
    s.maxTimes = 0;
    s.handedIndex = pc.report.structuralIndex.value_or(1);
  }
  return true;
}

void PantelidesPass::print(PassContext &pc, ResultStore &results,
                           std::ostream &out) const {
  const MatchingResult &mr = results.get<MatchingResult>();
  for (const DifferentiatedEquation &d : pc.report.differentiated)
    out << "// differentiated " << d.times << "x: " << d.equation << "  ("
        << d.location << ")\n";
  for (const Row &r : results.get<IndexReduction>().rows)
    out << "0 = " << ir::printLsd(r.residual, &pc.model) << ";  // "
        << pc.equationText(mr.equations[r.equation]) << " d/dt^" << r.times
        << "\n";
}

} // namespace

std::optional<int> structuralIndexAsWritten(ir::Model &m) {
  MatchingResult mr = sgaInput(m);
  IndexReduction s;
  if (reduce(m, mr, s) != graph::Pantelides::Status::Ok)
    return std::nullopt;
  return structuralIndex(s);
}

std::unique_ptr<Pass> createPantelidesPass(const PantelidesOptions &opts) {
  return std::make_unique<PantelidesPass>(opts);
}

} // namespace ldae::passes
