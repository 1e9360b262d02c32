// Pass "alias": removes equations `a = b`, `a = -b` and `a = c` (c free of
// variables and time) before structural analysis. Connections create many;
// eliminating them shrinks every later graph. Each class of aliases keeps
// one representative, chosen by what the user is likely to want to see:
// a fixed start value, then any start value, then stateSelect, then a
// variable whose derivative appears, then the shortest and alphabetically
// first name (never the declaration order, so shuffling changes nothing).
// The removed variables become outputs of the system.
//
// Cost: linear in the model per round (a round is needed when substituting
// makes new aliases; connector models take two or three). Names are compared
// once, by ranking them; a round rewrites only the equations that read an
// eliminated variable, through a substitution memoized by node id.
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/SystemStructure.h"

#include "graph/Matching.h"
#include "ir/Print.h"
#include "ir/Substitute.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <optional>
#include <span>

namespace ldae::passes {

namespace {

/// A linear alias equation: `s1*a + s2*b = 0` or `s1*a + c = 0`.
struct AliasEquation {
  int equation;
  ir::VarId a;
  double sa;
  std::optional<ir::VarId> b;
  double sb = 0;
  ir::ExprRef constant = nullptr; // the `c` (over parameters only)
  /// Canonical order: the two names' ranks, smaller first; (-1, a) for
  /// `a = c`. Ordering by rank is ordering by the names themselves.
  std::pair<int, int> key;
};

/// `±1 * Variable(v, 0)` as (v, ±1).
std::optional<std::pair<ir::VarId, double>> unitVariable(ir::ExprRef e) {
  if (e->kind() == ir::ExprKind::Variable && e->order() == 0)
    return std::make_pair(e->var(), 1.0);
  if (e->kind() == ir::ExprKind::Mul && e->numOperands() == 2 &&
      e->operand(0)->isConstant() &&
      std::fabs(e->operand(0)->constant()) == 1.0 &&
      e->operand(1)->kind() == ir::ExprKind::Variable &&
      e->operand(1)->order() == 0)
    return std::make_pair(e->operand(1)->var(), e->operand(0)->constant());
  return std::nullopt;
}

/// True if `e` reads no variable, `pre` or time: parameters and constants.
bool isConstantTerm(ir::ExprRef e) {
  std::vector<ir::ExprRef> stack{e};
  while (!stack.empty()) {
    ir::ExprRef n = stack.back();
    stack.pop_back();
    switch (n->kind()) {
    case ir::ExprKind::Variable:
    case ir::ExprKind::Time:
    case ir::ExprKind::Pre:
      return false;
    default:
      for (ir::ExprRef op : n->operands())
        stack.push_back(op);
    }
  }
  return true;
}

std::optional<AliasEquation> matchAlias(ir::ExprContext &ctx,
                                        ir::ExprRef residual, int eq) {
  std::span<const ir::ExprRef> terms(&residual, 1);
  if (residual->kind() == ir::ExprKind::Add) {
    // At most one term may be something other than +-variable, and at most
    // two may be variables: more than three terms never match (a quick
    // exit for the long sums of flow sets).
    terms = residual->operands();
    if (terms.size() > 3)
      return std::nullopt;
    int others = 0;
    for (ir::ExprRef t : terms)
      others += unitVariable(t) ? 0 : 1;
    if (others > 1 || residual->numOperands() - others > 2)
      return std::nullopt;
  }
  // Fixed capacity (at most three terms): this runs on every equation of
  // every round.
  std::array<std::pair<ir::VarId, double>, 3> vars;
  std::array<ir::ExprRef, 3> consts;
  size_t numVars = 0, numConsts = 0;
  for (ir::ExprRef t : terms) {
    if (auto v = unitVariable(t))
      vars[numVars++] = *v;
    else if (isConstantTerm(t))
      consts[numConsts++] = t;
    else
      return std::nullopt;
  }
  AliasEquation ae{eq, 0, 0, std::nullopt, 0, nullptr, {-1, -1}};
  if (numVars == 2 && numConsts == 0 && vars[0].first != vars[1].first) {
    ae.a = vars[0].first;
    ae.sa = vars[0].second;
    ae.b = vars[1].first;
    ae.sb = vars[1].second;
    return ae;
  }
  if (numVars == 1) {
    ae.a = vars[0].first;
    ae.sa = vars[0].second;
    ae.constant =
        numConsts == 0
            ? ctx.zero()
            : ctx.add(std::span<const ir::ExprRef>(consts.data(), numConsts));
    return ae;
  }
  return std::nullopt;
}

int stateSelectRank(ir::StateSelect s) { return static_cast<int>(s); }

/// Union-find with a sign: value(v) = sign[v] * value(parent[v]).
struct SignedUnionFind {
  std::vector<int> parent;
  std::vector<double> sign;
  explicit SignedUnionFind(size_t n) : parent(n), sign(n, 1.0) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  std::pair<int, double> find(int v) {
    double s = 1.0;
    int r = v;
    while (parent[r] != r) {
      s *= sign[r];
      r = parent[r];
    }
    // Path compression keeping signs.
    double acc = s;
    int x = v;
    while (parent[x] != x) {
      int next = parent[x];
      double sx = sign[x];
      parent[x] = r;
      sign[x] = acc;
      acc /= sx;
      x = next;
    }
    return {r, s};
  }
};

/// ir::Substitution for the replacement of leaves (variables, `pre`) over
/// a whole model: the replacements seed the memo, which is a table by node
/// id instead of a hash map. The traversal is ir::postOrder's (operands
/// left to right), so new nodes are made in the same order.
class LeafSubstitution {
public:
  explicit LeafSubstitution(ir::ExprContext &ctx) : ctx_(ctx) {}
  /// Every occurrence of leaf `from` is replaced by `to`.
  void set(ir::ExprRef from, ir::ExprRef to) { slot(from) = to; }
  ir::ExprRef apply(ir::ExprRef e) {
    if (ir::ExprRef r = known(e))
      return r;
    stack_.assign(1, {e, 0u});
    while (!stack_.empty()) {
      auto &[n, next] = stack_.back();
      if (next < n->numOperands()) {
        ir::ExprRef op = n->operand(next++);
        if (!known(op))
          stack_.push_back({op, 0u}); // `n` and `next` are stale from here
        continue;
      }
      ir::ExprRef node = n;
      stack_.pop_back();
      ir::ExprRef result = node;
      if (node->numOperands() != 0) {
        ops_.clear();
        bool changed = false;
        for (ir::ExprRef op : node->operands()) {
          ops_.push_back(known(op));
          changed = changed || ops_.back() != op;
        }
        if (changed)
          result = ir::rebuild(ctx_, node, ops_);
      }
      slot(node) = result;
    }
    return known(e);
  }

private:
  ir::ExprRef known(ir::ExprRef n) const {
    return n->id() < memo_.size() ? memo_[n->id()] : nullptr;
  }
  ir::ExprRef &slot(ir::ExprRef n) {
    if (n->id() >= memo_.size())
      memo_.resize(std::max<size_t>(n->id() + 1, 2 * memo_.size()), nullptr);
    return memo_[n->id()];
  }
  ir::ExprContext &ctx_;
  std::vector<ir::ExprRef> memo_; // by node id
  std::vector<std::pair<ir::ExprRef, unsigned>> stack_;
  std::vector<ir::ExprRef> ops_;
};

/// The state kept across rounds: name ranks and each equation's variables,
/// rescanned only when a round rewrites the equation.
struct AliasEliminator {
  PassContext &pc;
  AliasResult &s;
  ir::Model &m;
  const std::vector<int> &nameRank;           // by VarId: order of the names
  std::vector<std::vector<ir::VarKey>> reads; // by equation
  std::vector<char> readsPre;                 // by equation

  AliasEliminator(PassContext &pc, AliasResult &s)
      : pc(pc), s(s), m(pc.model), nameRank(pc.nameRanks()) {
    reads.resize(m.equations.size());
    readsPre.resize(m.equations.size());
    for (size_t i = 0; i < m.equations.size(); ++i)
      scan(i);
  }

  void scan(size_t eq) {
    bool pre = false;
    reads[eq] = variablesOf(m.equations[eq].residual, &pre);
    readsPre[eq] = pre;
  }

  bool completeMatching() const;
  int eliminateOnce();
};

/// Whether the equations can be matched to the continuous unknowns (orders
/// merged). The size of a maximum matching does not depend on the order of
/// rows and columns, so this skips the "matching" pass's canonical order,
/// which only a singular model's diagnosis needs.
bool AliasEliminator::completeMatching() const {
  const size_t nv = m.variables.size();
  std::vector<int> col(nv, -1);
  int cols = 0;
  for (ir::VarId v = 0; v < nv; ++v)
    if (!s.eliminated[v] && !m.variables[v].isDiscrete)
      col[v] = cols++;
  graph::BipartiteGraph g(static_cast<int>(reads.size()), cols);
  for (size_t r = 0; r < reads.size(); ++r) {
    std::vector<int> &row = g.rows[r];
    for (ir::VarKey k : reads[r]) // sorted by variable: repeats are adjacent
      if (col[k.var] >= 0 && (row.empty() || row.back() != col[k.var]))
        row.push_back(col[k.var]);
  }
  graph::Matching mm = graph::maximumMatching(g);
  return mm.size == g.numRows() && mm.size == g.numCols;
}

/// One round: finds the alias equations of the current model and removes
/// them. Returns how many variables it eliminated, or -1 after an error.
int AliasEliminator::eliminateOnce() {
  ir::ExprContext &ctx = m.ctx();
  const size_t nv = m.variables.size();
  const size_t before = s.aliases.size();

  // Variables a reinit writes must survive (or be the representative).
  std::vector<char> reinitTarget(nv, 0);
  for (const ir::WhenClause &w : m.whenClauses)
    for (const ir::Reinit &r : w.reinits)
      reinitTarget[r.var] = 1;
  std::vector<int> maxOrder(nv, 0);
  for (const std::vector<ir::VarKey> &eqReads : reads)
    for (ir::VarKey k : eqReads)
      maxOrder[k.var] = std::max<int>(maxOrder[k.var], k.order);

  std::vector<AliasEquation> found;
  for (size_t i = 0; i < m.equations.size(); ++i) {
    auto ae = matchAlias(ctx, m.equations[i].residual, static_cast<int>(i));
    if (!ae)
      continue;
    const ir::Variable &va = m.variables[ae->a];
    if (va.isDiscrete || (ae->b && m.variables[*ae->b].isDiscrete))
      continue;
    if (!ae->b && reinitTarget[ae->a])
      continue;
    int ra = nameRank[ae->a], rb = ae->b ? nameRank[*ae->b] : -1;
    ae->key = {std::min(ra, rb), std::max(ra, rb)};
    found.push_back(*ae);
  }
  // Canonical order: which of several redundant equations stays must not
  // depend on where they were written.
  std::sort(found.begin(), found.end(),
            [](const AliasEquation &x, const AliasEquation &y) {
              return x.key < y.key;
            });

  SignedUnionFind uf(nv);
  std::vector<ir::ExprRef> classConst(nv, nullptr); // by root: root = const
  std::vector<char> classReinit(nv, 0);
  for (size_t v = 0; v < nv; ++v)
    classReinit[v] = reinitTarget[v];
  // Two differentiated variables tied by `a = ±b` (capacitors in parallel,
  // rigidly joined inertias) stay apart where their values may differ
  // before the start or a mode change: the start must then jump by the
  // rule of LANGUAGE.md ("Initial values"), along T(E, F) of the model as
  // written, which weighs both (charge, momentum conserved). Merged, one
  // start value would win. Index reduction handles the tie instead.
  std::vector<char> classDiff(nv, 0);
  std::vector<std::optional<double>> classStart(nv); // in the root's sign
  for (size_t v = 0; v < nv; ++v) {
    classDiff[v] = maxOrder[v] > 0;
    if (m.variables[v].hasStart)
      classStart[v] = m.variables[v].start;
  }
  auto mayDiffer = [&](ir::VarId ra, ir::VarId rb, double sign) {
    if (!classDiff[ra] || !classDiff[rb])
      return false;
    if (pc.opts.keepStateAliases)
      return true;
    return classStart[ra] && classStart[rb] &&
           std::fabs(*classStart[ra] - sign * *classStart[rb]) >
               1e-12 * (1 + std::fabs(*classStart[ra]));
  };
  std::vector<char> removeEq(m.equations.size(), 0);
  for (const AliasEquation &ae : found) {
    auto [ra, sa] = uf.find(ae.a);
    if (ae.b) {
      auto [rb, sb] = uf.find(*ae.b);
      if (ra == rb)
        continue; // a cycle: the equation is redundant; structure reports it
      if (classReinit[ra] && classReinit[rb])
        continue;
      if ((classConst[ra] && (classConst[rb] || classReinit[rb])) ||
          (classConst[rb] && classReinit[ra]))
        continue;
      // sa_eq*a + sb_eq*b = 0 with a = sa*ra, b = sb*rb:
      // ra = -(sb_eq*sb)/(sa_eq*sa) * rb.
      double sign = -(ae.sb * sb) / (ae.sa * sa);
      if (mayDiffer(ra, rb, sign)) {
        pc.jumpsMatter = true;
        continue;
      }
      uf.parent[ra] = rb;
      uf.sign[ra] = sign;
      classDiff[rb] = classDiff[rb] || classDiff[ra];
      if (!classStart[rb] && classStart[ra])
        classStart[rb] = *classStart[ra] / sign;
      if (classConst[ra])
        classConst[rb] = ctx.mul(ctx.constant(uf.sign[ra]), classConst[ra]);
      classReinit[rb] = classReinit[rb] || classReinit[ra];
    } else {
      if (classConst[ra] || classReinit[ra])
        continue;
      // sa_eq*sa*ra + c = 0.
      classConst[ra] = ctx.div(ctx.neg(ae.constant), ctx.constant(ae.sa * sa));
    }
    removeEq[ae.equation] = 1;
  }

  // Representatives: the best member of each class.
  auto better = [&](ir::VarId x, ir::VarId y) {
    const ir::Variable &a = m.variables[x], &b = m.variables[y];
    auto key = [&](const ir::Variable &v, ir::VarId id) {
      return std::make_tuple(reinitTarget[id] ? 1 : 0,
                             v.fixed && v.hasStart ? 1 : 0, v.hasStart ? 1 : 0,
                             stateSelectRank(v.stateSelect),
                             maxOrder[id] > 0 ? 1 : 0);
    };
    auto kx = key(a, x), ky = key(b, y);
    if (kx != ky)
      return kx > ky;
    auto depth = [](const std::string &n) {
      return std::count(n.begin(), n.end(), '.');
    };
    if (depth(a.name) != depth(b.name))
      return depth(a.name) < depth(b.name);
    if (a.name.size() != b.name.size())
      return a.name.size() < b.name.size();
    return a.name < b.name;
  };
  // Members of each class in increasing VarId, in one array (offsets by
  // root): a vector per variable would be an allocation per variable.
  std::vector<double> toRoot(nv, 1.0);
  std::vector<ir::VarId> rootOf(nv);
  std::vector<size_t> start(nv + 1, 0);
  for (ir::VarId v = 0; v < nv; ++v) {
    auto [r, sg] = uf.find(v);
    toRoot[v] = sg;
    rootOf[v] = r;
    ++start[r + 1];
  }
  for (size_t r = 0; r < nv; ++r)
    start[r + 1] += start[r];
  std::vector<ir::VarId> memberList(nv);
  {
    std::vector<size_t> fill(start.begin(), start.end() - 1);
    for (ir::VarId v = 0; v < nv; ++v)
      memberList[fill[rootOf[v]]++] = v;
  }

  LeafSubstitution subst(ctx);
  std::vector<char> replaced(nv, 0); // eliminated in this round
  auto setAll = [&](ir::VarId v, unsigned top, auto valueAtOrder) {
    for (unsigned k = 0; k <= top; ++k)
      subst.set(ctx.var(v, k), valueAtOrder(k));
  };
  for (ir::VarId root = 0; root < nv; ++root) {
    std::span<const ir::VarId> cls(memberList.data() + start[root],
                                   start[root + 1] - start[root]);
    if (cls.size() < 2 && !classConst[root])
      continue;
    if (classConst[root]) {
      // Every member is a constant: value(v) = toRoot[v] * const.
      for (ir::VarId v : cls) {
        ir::ExprRef value = ctx.mul(ctx.constant(toRoot[v]), classConst[root]);
        s.eliminated[v] = 1;
        replaced[v] = 1;
        s.aliases.push_back({v, value});
        setAll(v, maxOrder[v], [&](unsigned k) {
          return k == 0 ? value : ctx.zero();
        });
        subst.set(ctx.pre(v), value);
      }
      continue;
    }
    ir::VarId rep = cls[0];
    for (ir::VarId v : cls)
      if (better(v, rep))
        rep = v;
    ir::Variable &rv = m.variables[rep];
    for (ir::VarId v : cls) {
      if (v == rep)
        continue;
      // value(v) = toRoot[v] * root = toRoot[v] / toRoot[rep] * rep.
      double sg = toRoot[v] / toRoot[rep];
      ir::Variable &av = m.variables[v];
      // Merge attributes into the representative (in its sign).
      if (av.hasStart) {
        double st = sg * av.start;
        if (av.fixed && rv.fixed && rv.hasStart &&
            std::fabs(rv.start - st) > 1e-12 * (1 + std::fabs(st))) {
          pc.diags.report(DiagId::ErrAliasFixedConflict, av.loc,
                         {av.name, ir::printNumber(av.start), rv.name,
                          ir::printNumber(rv.start)});
        } else if (!rv.hasStart || (av.fixed && !rv.fixed)) {
          rv.start = st;
          rv.startBinding =
              !av.startBinding || sg == 1
                  ? av.startBinding
                  : ctx.mul(ctx.constant(sg), av.startBinding);
          rv.hasStart = true;
          rv.fixed = rv.fixed || av.fixed;
        }
      }
      if (rv.nominal == 1 && av.nominal != 1)
        rv.nominal = av.nominal;
      double lo = sg > 0 ? av.min : -av.max, hi = sg > 0 ? av.max : -av.min;
      rv.min = std::max(rv.min, lo);
      rv.max = std::min(rv.max, hi);
      if (stateSelectRank(av.stateSelect) > stateSelectRank(rv.stateSelect))
        rv.stateSelect = av.stateSelect;
      s.eliminated[v] = 1;
      replaced[v] = 1;
      ir::ExprRef value = ctx.mul(ctx.constant(sg), ctx.var(rep));
      s.aliases.push_back({v, value});
      setAll(v, maxOrder[v], [&](unsigned k) {
        return ctx.mul(ctx.constant(sg), ctx.var(rep, k));
      });
      subst.set(ctx.pre(v), ctx.mul(ctx.constant(sg), ctx.pre(rep)));
    }
  }
  if (pc.diags.hasErrors())
    return -1;

  if (s.aliases.size() == before)
    return 0;
  // Apply: drop the alias equations, rewrite the equations that read an
  // eliminated variable (rewriting the others would change nothing and
  // make no node), in place.
  size_t out = 0;
  for (size_t i = 0; i < m.equations.size(); ++i) {
    if (removeEq[i])
      continue;
    if (out != i) {
      m.equations[out] = std::move(m.equations[i]);
      reads[out] = std::move(reads[i]);
      readsPre[out] = readsPre[i];
    }
    bool touched = readsPre[out] != 0;
    for (ir::VarKey k : reads[out])
      touched = touched || replaced[k.var];
    if (touched) {
      ir::Equation &e = m.equations[out];
      e.residual = subst.apply(e.residual);
      scan(out);
    }
    ++out;
  }
  m.equations.resize(out);
  reads.resize(out);
  readsPre.resize(out);
  for (ir::Equation &e : m.initialEquations)
    e.residual = subst.apply(e.residual);
  for (ir::WhenClause &w : m.whenClauses) {
    w.condition = subst.apply(w.condition);
    for (ir::ExprRef &c : w.elements)
      c = subst.apply(c);
    for (ir::Reinit &r : w.reinits) {
      r.value = subst.apply(r.value);
      if (s.eliminated[r.var]) {
        // The representative takes the reinit, in its own sign.
        ir::ExprRef alias = subst.apply(ctx.var(r.var));
        if (alias->kind() == ir::ExprKind::Mul) {
          r.value = ctx.mul(alias->operand(0), r.value);
          r.var = alias->operand(1)->var();
        } else if (alias->kind() == ir::ExprKind::Variable) {
          r.var = alias->var();
        }
      }
    }
    for (ir::Equation &e : w.equations)
      e.residual = subst.apply(e.residual);
  }
  // Aliases found earlier now stand for the new representatives too.
  for (size_t i = 0; i < before; ++i)
    s.aliases[i].value = subst.apply(s.aliases[i].value);
  return static_cast<int>(s.aliases.size() - before);
}

class AliasEliminationPass
    : public TypedPass<AliasEliminationPass, Reads<>, Updates<>,
                       Produces<AliasResult>> {
public:
  AliasEliminationPass() : TypedPass(PassId::Alias) {}

  bool runOn(PassContext &ctx, AliasResult &out) {
    ir::Model &m = ctx.model;
    out.eliminated.assign(m.variables.size(), 0);
    AliasEliminator elim(ctx, out);
    // A structurally singular model is diagnosed as the user wrote it:
    // eliminating `x = 1` would leave `2*x = 3` with no unknown at all.
    if (!elim.completeMatching())
      return true;
    // Substituting aliases makes new ones (`v = p.v - n.v` with n.v = 0):
    // repeat until a round finds none.
    for (int found = 1; found > 0;) {
      found = elim.eliminateOnce();
      if (found < 0)
        return false;
    }
    std::sort(out.aliases.begin(), out.aliases.end(),
              [&](const Alias &x, const Alias &y) {
                return elim.nameRank[x.var] < elim.nameRank[y.var];
              });
    ctx.report.aliasesRemoved = static_cast<int>(out.aliases.size());
    for (const Alias &a : out.aliases)
      ctx.report.aliases.push_back(m.variables[a.var].name + " = " +
                                   ir::printLsd(a.value, &m));
    return true;
  }
};

} // namespace

std::unique_ptr<Pass> createAliasEliminationPass() {
  return std::make_unique<AliasEliminationPass>();
}

} // namespace ldae::passes
