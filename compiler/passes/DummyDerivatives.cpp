// Pass "dummy-derivatives" (Mattsson & Söderlind 1993). After Pantelides,
// level l = 1..max(c) holds the equations differentiated at least l times
// (each at c_i - l differentiations) and the unknowns whose highest order
// d_j is at least l (each at order d_j - l). At each level as many of those
// unknowns as there are equations are selected, with a nonsingular
// Jacobian; the derivative of each selected one (order d_j - l + 1) becomes
// a dummy derivative, an algebraic unknown. Selections nest: one made at a
// higher level is forced at every lower one.
//
// We choose top-down (the smallest, most value-dependent level first) and
// complete each lower level by augmenting paths from the forced selection,
// which keeps it sparse. Candidates are ranked by stateSelect (never and
// avoid first), then by the size of their Jacobian entry at the start point
// (conditioning), then by derivative order, then by name. Where the top
// level has one-row blocks whose choice depends on values (the pendulum: x
// or y), every structurally possible choice becomes a candidate state set
// for dynamic state selection at run time. Larger value-dependent blocks
// (the pendulum chain: n link constraints over 2n coordinates) would need
// binomially many sets; they are chosen at run time instead (Mattsson,
// Olsson and Soderlind): every candidate's derivative is a dummy, the
// states are s = A c with a selection matrix A that the runtime sets from a
// column-pivoted factorization of the block's Jacobian (numeric/
// StatePivot.h), and the lower levels the block forces are chosen the same
// way where they have a value-dependent choice left.
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/SystemStructure.h"

#include "graph/DulmageMendelsohn.h"
#include "graph/Matching.h"
#include "ir/Differentiate.h"
#include "ir/Query.h"
#include "numeric/Rank.h"
#include "numeric/StatePivot.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>
#include <random>

namespace ldae::passes {

namespace {

// Blocks of one row are enumerated (a candidate set each); larger ones are
// chosen at run time.
constexpr int kMaxAmbiguousRows = 1;
constexpr int kMaxAmbiguousCols = 8;
constexpr size_t kMaxStateSets = 16;
constexpr int kDenseCheckLimit = 200;

struct Edge {
  int col;
  ir::ExprRef partial;
  double value;
};

struct Level {
  std::vector<int> rowEq;   // original equation (row of s.rows chain start)
  std::vector<int> row;     // row of s.rows at this level
  std::vector<int> colVar;  // unknown index
  std::vector<int> colOfVar; // unknown -> local column or -1
  std::vector<int> rowOfEq;  // original equation -> local row or -1
  graph::BipartiteGraph g;   // adjacency sorted by preference
  std::vector<std::vector<Edge>> edges; // per row, same order as g.rows
};

/// What the selection reads: the model and its start point (context), the
/// canonical unknowns (matching) and the augmented rows (pantelides).
struct SelectionInput {
  PassContext &ctx;
  ir::Model &model;
  const std::vector<ir::VarId> &unknowns;
  const std::vector<int> &unknownIndex;
  const std::vector<int> &equations;
  const std::vector<Row> &rows;
  const std::vector<int> &highest;
  int maxTimes;
  ir::EvalEnv startEnv() const { return ctx.startEnv(); }
};

class Selector {
public:
  explicit Selector(const SelectionInput &s) : s_(s), diff_(s.model.ctx()) {}

  void buildLevels();
  /// A full selection; `topOverride` forces top-level pairs (row, col).
  /// Returns the selected unknowns per level (index l-1), or empty on failure.
  /// With `atStart`, numerically singular blocks at the start point are
  /// re-chosen by pivoting; alternatives (meant for elsewhere in state
  /// space) keep the structural completion.
  std::vector<std::vector<int>>
  choose(const std::vector<std::pair<int, int>> &topOverride, bool atStart);
  /// The blocks the first choose() made dynamic, for the result.
  std::vector<DynamicBlock> dynamicBlocks() const;
  DummyChoice toChoice(const std::vector<std::vector<int>> &sel) const;
  void findAmbiguous();

  int levels() const { return static_cast<int>(levels_.size()); }
  const Level &level(int l) const { return levels_[l - 1]; }

  struct Ambiguous {
    std::vector<int> rows, cols;                // local, top level
    std::vector<std::vector<int>> alternatives; // column subsets
  };
  std::vector<Ambiguous> ambiguous;
  std::string failure;

  /// The pivot matrix (column-major) of the ambiguous blocks of `sel`'s top
  /// level.
  std::vector<ir::ExprRef> pivot(const std::vector<int> &topSel,
                                 unsigned &size) const;

private:
  /// How much selecting unknown j at `order` (making order + 1 a dummy)
  /// is wanted: it costs x its place among the states only at order 0, so
  /// stateSelect ranks those; higher orders (der(x) no longer a state) go
  /// first, keeping the user's own variables as states.
  int dummyRank(int j, int order) const {
    if (order > 0)
      return -1;
    return static_cast<int>(
        s_.model.variables[s_.unknowns[j]].stateSelect);
  }
  /// A maximum matching of `lv` extending `first`, taking columns in
  /// tiers of dummyRank: the most wanted dummies as many as they can, then
  /// the next tier only to fill the rows left.
  graph::Matching completeByRank(const Level &lv, int l,
                                 const graph::Matching &first) const;
  /// The symbolic Jacobian entry (row r, column c) of `lv`, or nullptr.
  ir::ExprRef entry(const Level &lv, int r, int c) const;
  bool hasEntry(const Level &lv, int r, int c) const;
  bool fixDense(Level &lv, int levelIndex, graph::Matching &m,
                const std::vector<char> &forcedCol,
                const std::vector<char> &skipRow);

  /// A piece of a level chosen at run time (local rows and columns).
  struct DynamicPiece {
    int level;
    std::vector<int> rows, forced, free;
  };
  bool valueDependent(const Level &lv, const std::vector<int> &rows) const;
  /// Decides which pieces of level l are dynamic (first choose() only).
  void findDynamic(int l, const std::vector<char> &forced,
                   const std::vector<char> &forcedByDynamic,
                   const graph::Matching &m);

  SelectionInput s_;
  mutable ir::Differentiator diff_;
  std::vector<Level> levels_;
  bool dynamicDecided_ = false;
  std::vector<DynamicPiece> dynamic_;
};

/// Larger entries first (better conditioned pivots); entries within 0.1%
/// of each other tie, so order and name decide deterministically.
double magnitudeClass(double v, double rowMax) {
  if (!std::isfinite(v) || v == 0 || rowMax == 0)
    return 2;
  return -std::round(1000 * std::fabs(v) / rowMax) / 1000;
}

void Selector::buildLevels() {
  const int L = s_.maxTimes;
  const int nu = static_cast<int>(s_.unknowns.size());
  const int ne = static_cast<int>(s_.equations.size());
  ir::EvalEnv env = s_.startEnv();
  levels_.resize(L);
  for (int l = 1; l <= L; ++l) {
    Level &lv = levels_[l - 1];
    lv.colOfVar.assign(nu, -1);
    lv.rowOfEq.assign(ne, -1);
    for (int j = 0; j < nu; ++j)
      if (s_.highest[j] >= l) {
        lv.colOfVar[j] = static_cast<int>(lv.colVar.size());
        lv.colVar.push_back(j);
      }
    for (int i = 0; i < ne; ++i) {
      std::vector<int> chain{i};
      while (s_.rows[chain.back()].next >= 0)
        chain.push_back(s_.rows[chain.back()].next);
      int c = static_cast<int>(chain.size()) - 1;
      if (c < l)
        continue;
      lv.rowOfEq[i] = static_cast<int>(lv.row.size());
      lv.rowEq.push_back(i);
      lv.row.push_back(chain[c - l]);
    }
    lv.g = graph::BipartiteGraph(static_cast<int>(lv.row.size()),
                                 static_cast<int>(lv.colVar.size()));
    lv.edges.resize(lv.row.size());
    // Entry values by finite differences at the start point: symbolic
    // partials are only needed for the small value-dependent blocks (the
    // differentiator's cache is per variable, so one partial per column
    // would cost the whole DAG each time).
    for (size_t r = 0; r < lv.row.size(); ++r) {
      ir::ExprRef e = s_.rows[lv.row[r]].residual;
      std::vector<std::pair<ir::VarKey, int>> keys;
      for (ir::VarKey k : variablesOf(e)) {
        if (k.var >= s_.unknownIndex.size() || s_.unknownIndex[k.var] < 0)
          continue;
        int j = s_.unknownIndex[k.var];
        int c = lv.colOfVar[j];
        if (c >= 0 && static_cast<int>(k.order) == s_.highest[j] - l)
          keys.emplace_back(k, c);
      }
      if (keys.empty())
        continue;
      ir::VarKey bumped{~0u, ~0u};
      double h = 0;
      ir::EvalEnv fd = env;
      fd.variable = [&](ir::VarKey k) {
        double v = env.variable(k);
        return k == bumped ? v + h : v;
      };
      auto base = ir::evaluate(e, fd);
      for (auto [k, c] : keys) {
        bumped = k;
        h = 1e-7 * std::max(1.0, std::fabs(env.variable(k)));
        auto up = ir::evaluate(e, fd);
        double v = base && up ? (*up - *base) / h
                              : std::numeric_limits<double>::quiet_NaN();
        lv.edges[r].push_back({c, nullptr, v});
      }
      bumped = {~0u, ~0u};
    }
    // Preference order inside each row: the candidate to make a dummy first.
    for (size_t r = 0; r < lv.row.size(); ++r) {
      std::vector<Edge> &es = lv.edges[r];
      double rowMax = 0;
      for (const Edge &e : es)
        if (std::isfinite(e.value))
          rowMax = std::max(rowMax, std::fabs(e.value));
      auto key = [&](const Edge &e) {
        int j = lv.colVar[e.col];
        return std::make_tuple(dummyRank(j, s_.highest[j] - l),
                               magnitudeClass(e.value, rowMax),
                               -s_.highest[j], s_.model.variables[s_.unknowns[j]].name);
      };
      std::stable_sort(es.begin(), es.end(), [&](const Edge &a, const Edge &b) {
        return key(a) < key(b);
      });
      for (const Edge &e : es)
        lv.g.rows[r].push_back(e.col);
    }
  }
}

ir::ExprRef Selector::entry(const Level &lv, int r, int c) const {
  for (const Edge &e : lv.edges[r])
    if (e.col == c) {
      int j = lv.colVar[c];
      int l = static_cast<int>(&lv - levels_.data()) + 1;
      ir::VarKey key{s_.unknowns[j], static_cast<unsigned>(s_.highest[j] - l)};
      return diff_.partial(s_.rows[lv.row[r]].residual, key);
    }
  return nullptr;
}

bool Selector::hasEntry(const Level &lv, int r, int c) const {
  for (const Edge &e : lv.edges[r])
    if (e.col == c)
      return true;
  return false;
}

// Dense column-pivoted elimination of the components of level `lv` whose
// selected submatrix is numerically singular at the start point: forced
// columns first, then the best-ranked column with a usable pivot.
bool Selector::fixDense(Level &lv, int levelIndex, graph::Matching &m,
                        const std::vector<char> &forcedCol,
                        const std::vector<char> &skipRow) {
  graph::DmPart all;
  for (int r = 0; r < lv.g.numRows(); ++r)
    all.rows.push_back(r);
  for (int c = 0; c < lv.g.numCols; ++c)
    all.cols.push_back(c);
  bool ok = true;
  for (const graph::DmPart &piece : graph::connectedPieces(lv.g, all)) {
    const int nr = static_cast<int>(piece.rows.size());
    if (nr == 0 || nr > kDenseCheckLimit || skipRow[piece.rows[0]])
      continue;
    std::vector<int> sel;
    for (int r : piece.rows)
      sel.push_back(m.rowMate[r]);
    std::map<int, int> colPos;
    for (size_t k = 0; k < piece.cols.size(); ++k)
      colPos[piece.cols[k]] = static_cast<int>(k);
    std::map<int, int> rowPos;
    for (size_t k = 0; k < piece.rows.size(); ++k)
      rowPos[piece.rows[k]] = static_cast<int>(k);
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(nr, piece.cols.size());
    std::vector<int> rank(piece.cols.size(), 0); // preference rank of column
    for (int r : piece.rows)
      for (size_t k = 0; k < lv.edges[r].size(); ++k) {
        const Edge &e = lv.edges[r][k];
        A(rowPos[r], colPos[e.col]) = std::isfinite(e.value) ? e.value : 0;
      }
    Eigen::MatrixXd S(nr, nr);
    for (int k = 0; k < nr; ++k)
      S.col(k) = A.col(colPos[sel[k]]);
    if (numeric::isNonsingular(S, numeric::kNonsingularThreshold))
      continue;
    // Rank columns by stateSelect then name (the magnitude is what pivoting
    // measures here).
    std::vector<int> order(piece.cols.size());
    for (size_t k = 0; k < order.size(); ++k)
      order[k] = static_cast<int>(k);
    auto prefKey = [&](int k) {
      int j = lv.colVar[piece.cols[k]];
      return std::make_tuple(forcedCol[piece.cols[k]] ? 0 : 1,
                             dummyRank(j, s_.highest[j] - levelIndex),
                             -s_.highest[j],
                             s_.model.variables[s_.unknowns[j]].name);
    };
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return prefKey(a) < prefKey(b); });
    std::vector<char> rowUsed(nr, 0);
    std::vector<std::pair<int, int>> chosen; // (row pos, col pos)
    double scale = A.cwiseAbs().maxCoeff();
    bool forcedLost = false;
    for (int k : order) {
      if (static_cast<int>(chosen.size()) == nr || forcedLost)
        break;
      int best = -1;
      double bestVal = 1e-10 * std::max(scale, 1.0);
      for (int r = 0; r < nr; ++r)
        if (!rowUsed[r] && std::fabs(A(r, k)) > bestVal) {
          bestVal = std::fabs(A(r, k));
          best = r;
        }
      if (best < 0) {
        // A forced column dependent at this point (an alternative state
        // set made for elsewhere in state space): keep the structural
        // choice.
        forcedLost = forcedLost || forcedCol[piece.cols[k]];
        continue;
      }
      rowUsed[best] = 1;
      chosen.emplace_back(best, k);
      // Eliminate the column's pivot from the other rows.
      for (int r = 0; r < nr; ++r)
        if (r != best && A(r, k) != 0)
          A.row(r) -= (A(r, k) / A(best, k)) * A.row(best);
    }
    if (forcedLost || static_cast<int>(chosen.size()) < nr) {
      ok = false;
      continue;
    }
    // The new selection must still be structurally matchable; re-match the
    // piece's rows to the chosen columns.
    graph::BipartiteGraph sub(nr, nr);
    std::vector<int> chosenCols;
    for (auto [r, k] : chosen)
      chosenCols.push_back(piece.cols[k]);
    for (int r = 0; r < nr; ++r)
      for (int k = 0; k < nr; ++k)
        if (hasEntry(lv, piece.rows[r], chosenCols[k]))
          sub.addEdge(r, k);
    graph::Matching sm = graph::maximumMatching(sub);
    if (sm.size < nr) {
      ok = false;
      continue;
    }
    for (int r : piece.rows)
      if (m.rowMate[r] >= 0)
        m.colMate[m.rowMate[r]] = -1;
    for (int r = 0; r < nr; ++r) {
      m.rowMate[piece.rows[r]] = chosenCols[sm.rowMate[r]];
      m.colMate[chosenCols[sm.rowMate[r]]] = piece.rows[r];
    }
  }
  return ok;
}

// A row's candidates are ordered by rank, but a matching completed row by
// row lets a row take its first choice from a row that had no other: a
// mass joined to a spring-damper with relative states (MSL's HeatLosses:
// s_rel prefer, the stop mass's s always, the other mass's s default, one
// position constraint through the flanges) gave the stop mass's s as the
// dummy, so its reinit had no state to act on. Augmenting paths never
// unmatch a column, so growing the allowed columns tier by tier keeps
// every column of a lower tier already taken: as many of the most wanted
// dummies as any matching has, then the next tier (the greedy algorithm of
// the transversal matroid, over tiers).
graph::Matching Selector::completeByRank(const Level &lv, int l,
                                         const graph::Matching &first) const {
  std::vector<int> rank(lv.g.numCols);
  for (int c = 0; c < lv.g.numCols; ++c) {
    int j = lv.colVar[c];
    rank[c] = dummyRank(j, s_.highest[j] - l);
  }
  std::vector<int> tiers(rank);
  std::sort(tiers.begin(), tiers.end());
  tiers.erase(std::unique(tiers.begin(), tiers.end()), tiers.end());
  graph::Matching m = first;
  std::vector<char> allowed(lv.g.numCols, 0);
  for (int c = 0; c < lv.g.numCols; ++c)
    allowed[c] = first.colMate[c] >= 0;
  for (int tier : tiers) {
    if (m.size == lv.g.numRows())
      break;
    for (int c = 0; c < lv.g.numCols; ++c)
      allowed[c] = allowed[c] || rank[c] == tier;
    m = graph::maximumMatching(lv.g, allowed, &m);
  }
  return m;
}

std::vector<std::vector<int>>
Selector::choose(const std::vector<std::pair<int, int>> &topOverride,
                 bool atStart) {
  const int L = levels();
  std::vector<std::vector<int>> selected(L);
  std::vector<std::pair<int, int>> prev; // (original equation, unknown)
  std::vector<int> prevDynamic;          // unknowns selected by a dynamic block
  for (int l = L; l >= 1; --l) {
    Level &lv = levels_[l - 1];
    graph::Matching init(lv.g.numRows(), lv.g.numCols);
    std::vector<char> forced(lv.g.numCols, 0);
    std::vector<char> forcedByDynamic(lv.g.numCols, 0);
    for (int j : prevDynamic) {
      int c = lv.colOfVar[j];
      if (c < 0) {
        failure = "the run-time state selection of level " +
                  std::to_string(l + 1) + " does not carry to level " +
                  std::to_string(l);
        return {};
      }
      forced[c] = forcedByDynamic[c] = 1;
    }
    auto hasEdge = [&](int r, int c) {
      const std::vector<int> &adj = lv.g.rows[r];
      return std::find(adj.begin(), adj.end(), c) != adj.end();
    };
    for (auto [i, j] : prev) {
      int r = lv.rowOfEq[i], c = lv.colOfVar[j];
      if (r < 0 || c < 0 || !hasEdge(r, c)) {
        failure = "the selection of level " + std::to_string(l + 1) +
                  " does not carry to level " + std::to_string(l);
        return {};
      }
      init.match(r, c);
      forced[c] = 1;
    }
    if (l == L)
      for (auto [r, c] : topOverride) {
        init.match(r, c);
        forced[c] = 1;
      }
    // The columns a dynamic block above forces have no row of their own:
    // match them first, so the completion keeps them.
    graph::Matching first = graph::maximumMatching(lv.g, forced, &init);
    for (int c = 0; c < lv.g.numCols; ++c)
      if (forced[c] && first.colMate[c] < 0) {
        failure = "the selection of level " + std::to_string(l + 1) +
                  " does not carry to level " + std::to_string(l);
        return {};
      }
    graph::Matching m = completeByRank(lv, l, first);
    if (m.size < lv.g.numRows()) {
      failure = "no nonsingular choice of dummy derivatives at level " +
                std::to_string(l);
      return {};
    }
    if (!dynamicDecided_)
      findDynamic(l, forced, forcedByDynamic, m);
    std::vector<char> dynamicRow(lv.g.numRows(), 0);
    std::vector<int> dynamicCols;
    for (const DynamicPiece &d : dynamic_)
      if (d.level == l) {
        for (int r : d.rows)
          dynamicRow[r] = 1;
        for (int c : d.free)
          if (m.colMate[c] < 0)
            dynamicCols.push_back(c);
      }
    if (atStart && !fixDense(lv, l, m, forced, dynamicRow)) {
      failure = "the Jacobian of the differentiated equations at level " +
                std::to_string(l) + " is singular at the start point";
      // Keep the structural choice: a singular start point is a warning.
    }
    // Selected per row in row order (pivot() reads them so), then the
    // dynamic blocks' candidates no row took.
    prev.clear();
    prevDynamic.clear();
    for (int r = 0; r < lv.g.numRows(); ++r) {
      int j = lv.colVar[m.rowMate[r]];
      if (dynamicRow[r] || forcedByDynamic[m.rowMate[r]])
        prevDynamic.push_back(j);
      else
        prev.emplace_back(lv.rowEq[r], j);
      selected[l - 1].push_back(j);
    }
    for (int c : dynamicCols) {
      prevDynamic.push_back(lv.colVar[c]);
      selected[l - 1].push_back(lv.colVar[c]);
    }
  }
  dynamicDecided_ = true;
  return selected;
}

bool Selector::valueDependent(const Level &lv,
                              const std::vector<int> &rows) const {
  for (int r : rows)
    for (const Edge &e : lv.edges[r])
      if (!entry(lv, r, e.col)->isConstant())
        return true;
  return false;
}

// A piece is chosen at run time when its choice depends on values and it
// is too large to enumerate (top level), or when a dynamic block above
// forces columns into it and a value-dependent choice is left (the chain's
// velocities below its positions).
void Selector::findDynamic(int l, const std::vector<char> &forced,
                           const std::vector<char> &forcedByDynamic,
                           const graph::Matching &m) {
  const Level &lv = levels_[l - 1];
  graph::DmPart all;
  for (int r = 0; r < lv.g.numRows(); ++r)
    all.rows.push_back(r);
  for (int c = 0; c < lv.g.numCols; ++c)
    all.cols.push_back(c);
  for (const graph::DmPart &piece : graph::connectedPieces(lv.g, all)) {
    DynamicPiece d{l, piece.rows, {}, {}};
    bool belowDynamic = false;
    for (int c : piece.cols) {
      (forced[c] ? d.forced : d.free).push_back(c);
      belowDynamic = belowDynamic || forcedByDynamic[c];
    }
    const int rows = static_cast<int>(piece.rows.size());
    const int choose = rows - static_cast<int>(d.forced.size());
    if (choose < 1 || static_cast<int>(d.free.size()) <= choose)
      continue;
    bool large = rows > kMaxAmbiguousRows ||
                 static_cast<int>(piece.cols.size()) > kMaxAmbiguousCols;
    if (!(l == levels() ? large : belowDynamic) ||
        !valueDependent(lv, piece.rows))
      continue;
    // Every row matched inside the piece (the matching covers all rows).
    for (int r : piece.rows)
      if (m.rowMate[r] < 0)
        return;
    dynamic_.push_back(std::move(d));
  }
}

std::vector<DynamicBlock> Selector::dynamicBlocks() const {
  std::vector<DynamicBlock> out;
  ir::ExprContext &ctx = s_.model.ctx();
  ir::EvalEnv env = s_.startEnv();
  for (const DynamicPiece &d : dynamic_) {
    const Level &lv = levels_[d.level - 1];
    DynamicBlock b;
    b.level = d.level;
    b.rows = static_cast<unsigned>(d.rows.size());
    auto key = [&](int c) {
      int j = lv.colVar[c];
      return ir::VarKey{s_.unknowns[j],
                        static_cast<unsigned>(s_.highest[j] - d.level)};
    };
    std::vector<int> cols = d.forced;
    cols.insert(cols.end(), d.free.begin(), d.free.end());
    for (int c : d.forced)
      b.forced.push_back(key(c));
    for (int c : d.free)
      b.candidates.push_back(key(c));
    Eigen::MatrixXd J(d.rows.size(), cols.size());
    for (size_t k = 0; k < cols.size(); ++k)
      for (size_t r = 0; r < d.rows.size(); ++r) {
        ir::ExprRef e = hasEntry(lv, d.rows[r], cols[k])
                            ? entry(lv, d.rows[r], cols[k])
                            : ctx.zero();
        b.jacobian.push_back(e);
        auto v = ir::evaluate(e, env);
        J(r, k) = v ? *v : std::numeric_limits<double>::quiet_NaN();
      }
    b.startDummies = numeric::pivotDummies(
        numeric::reduceForced(J, static_cast<int>(d.forced.size())));
    if (b.startDummies.empty()) // not finite at the start: the first ones
      for (size_t k = 0; k < d.rows.size() - d.forced.size(); ++k)
        b.startDummies.push_back(static_cast<int>(k));
    out.push_back(std::move(b));
  }
  return out;
}

DummyChoice
Selector::toChoice(const std::vector<std::vector<int>> &sel) const {
  DummyChoice lowest(s_.unknowns.size());
  for (size_t j = 0; j < lowest.size(); ++j)
    lowest[j] = s_.highest[j] + 1;
  // Selected at level l: der of order (d_j - l) is a dummy, i.e. order
  // d_j - l + 1 and above.
  for (int l = 1; l <= static_cast<int>(sel.size()); ++l)
    for (int j : sel[l - 1])
      lowest[j] = std::min(lowest[j], s_.highest[j] - l + 1);
  return lowest;
}

void Selector::findAmbiguous() {
  if (levels_.empty())
    return;
  const Level &top = levels_.back();
  graph::DmPart all;
  for (int r = 0; r < top.g.numRows(); ++r)
    all.rows.push_back(r);
  for (int c = 0; c < top.g.numCols; ++c)
    all.cols.push_back(c);
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> uni(0.5, 1.5);
  for (const graph::DmPart &piece : graph::connectedPieces(top.g, all)) {
    const int nr = static_cast<int>(piece.rows.size());
    const int nc = static_cast<int>(piece.cols.size());
    if (nr == 0 || nr > kMaxAmbiguousRows || nc > kMaxAmbiguousCols ||
        nc <= nr)
      continue;
    bool isDynamic = false;
    for (const DynamicPiece &d : dynamic_)
      isDynamic = isDynamic ||
                  (d.level == levels() && d.rows.front() == piece.rows.front());
    if (isDynamic)
      continue;
    bool valueDependent = false;
    for (int r : piece.rows)
      for (const Edge &e : top.edges[r])
        valueDependent =
            valueDependent || !entry(top, r, e.col)->isConstant();
    if (!valueDependent)
      continue;
    // Generic values: a random point, so only identically singular choices
    // are rejected.
    std::map<ir::VarKey, double> generic;
    ir::EvalEnv env = s_.startEnv();
    env.variable = [&](ir::VarKey k) {
      auto it = generic.find(k);
      if (it == generic.end())
        it = generic.emplace(k, uni(rng)).first;
      return it->second;
    };
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(nr, nc);
    for (int r = 0; r < nr; ++r)
      for (const Edge &e : top.edges[piece.rows[r]]) {
        int k = static_cast<int>(
            std::find(piece.cols.begin(), piece.cols.end(), e.col) -
            piece.cols.begin());
        auto v = ir::evaluate(entry(top, piece.rows[r], e.col), env);
        A(r, k) = v ? *v : 0;
      }
    // Columns by name so the alternatives come in a canonical order.
    std::vector<int> byName(nc);
    for (int k = 0; k < nc; ++k)
      byName[k] = k;
    auto nameOf = [&](int k) {
      return s_.model.variables[s_.unknowns[top.colVar[piece.cols[k]]]].name;
    };
    std::sort(byName.begin(), byName.end(),
              [&](int a, int b) { return nameOf(a) < nameOf(b); });
    Ambiguous amb{piece.rows, piece.cols, {}};
    std::vector<int> pick(nr);
    std::function<void(int, int)> rec = [&](int start, int depth) {
      if (depth == nr) {
        Eigen::MatrixXd S(nr, nr);
        std::vector<int> cols;
        for (int k = 0; k < nr; ++k) {
          S.col(k) = A.col(pick[k]);
          cols.push_back(piece.cols[pick[k]]);
        }
        if (numeric::isNonsingular(S))
          amb.alternatives.push_back(cols);
        return;
      }
      for (int k = start; k < nc; ++k) {
        pick[depth] = byName[k];
        rec(k + 1, depth + 1);
      }
    };
    rec(0, 0);
    if (amb.alternatives.size() < 2)
      continue;
    // Never let a stateSelect = always unknown be the dummy when another
    // choice exists.
    std::vector<std::vector<int>> allowed;
    for (const std::vector<int> &alt : amb.alternatives) {
      bool always = false;
      for (int c : alt)
        always = always ||
                 s_.model.variables[s_.unknowns[top.colVar[c]]].stateSelect ==
                     ir::StateSelect::Always;
      if (!always)
        allowed.push_back(alt);
    }
    if (allowed.size() >= 2)
      amb.alternatives = allowed;
    else if (allowed.size() == 1)
      continue;
    ambiguous.push_back(std::move(amb));
  }
}

std::vector<ir::ExprRef> Selector::pivot(const std::vector<int> &topSel,
                                         unsigned &size) const {
  // topSel: selected unknowns at the top level (one per top row, in row
  // order). The pivot is block diagonal over the ambiguous blocks.
  const Level &top = levels_.back();
  size = 0;
  for (const Ambiguous &a : ambiguous)
    size += static_cast<unsigned>(a.rows.size());
  ir::ExprContext &ctx = s_.model.ctx();
  std::vector<ir::ExprRef> M(size * size, ctx.zero());
  unsigned offset = 0;
  for (const Ambiguous &a : ambiguous) {
    std::vector<int> cols;
    for (int r : a.rows)
      cols.push_back(top.colOfVar[topSel[r]]);
    std::sort(cols.begin(), cols.end());
    for (size_t r = 0; r < a.rows.size(); ++r)
      for (size_t k = 0; k < cols.size(); ++k) {
        ir::ExprRef e = entry(top, a.rows[r], cols[k]);
        M[(offset + k) * size + offset + r] = e ? e : ctx.zero();
      }
    offset += static_cast<unsigned>(a.rows.size());
  }
  return M;
}

class DummyDerivativesPass
    : public TypedPass<DummyDerivativesPass,
                       Reads<MatchingResult, IndexReduction>, Updates<>,
                       Produces<DummyChoices>> {
public:
  DummyDerivativesPass() : TypedPass(PassId::DummyDerivatives) {}

  bool runOn(PassContext &ctx, const MatchingResult &mr,
             const IndexReduction &red, DummyChoices &out);
  void print(PassContext &ctx, ResultStore &results,
             std::ostream &out) const override;
};

bool DummyDerivativesPass::runOn(PassContext &ctx, const MatchingResult &mr,
                                 const IndexReduction &red,
                                 DummyChoices &out) {
  if (red.maxTimes == 0) {
    DummyChoice none(mr.unknowns.size());
    for (size_t j = 0; j < none.size(); ++j)
      none[j] = red.highest[j] + 1;
    out.choices.push_back(none);
    out.pivots.emplace_back();
    out.pivotSizes.push_back(0);
    return true;
  }

  Selector sel({ctx, ctx.model, mr.unknowns, mr.unknownIndex, mr.equations,
                red.rows, red.highest, red.maxTimes});
  sel.buildLevels();
  std::vector<std::vector<int>> first = sel.choose({}, true);
  if (first.empty()) {
    ctx.diags.report(DiagId::ErrIndexReductionFailed, ctx.model.loc,
                   {sel.failure});
    return false;
  }
  if (!sel.failure.empty())
    ctx.diags.report(DiagId::WarnDummySelectionAtStart, ctx.model.loc,
                   {sel.failure});
  out.dynamic = sel.dynamicBlocks();
  sel.findAmbiguous();
  std::vector<std::vector<std::vector<int>>> selections{first};
  // Alternatives: one ambiguous block switched at a time.
  const Level &top = sel.level(sel.levels());
  for (size_t a = 0; a < sel.ambiguous.size(); ++a) {
    const auto &amb = sel.ambiguous[a];
    for (const std::vector<int> &alt : amb.alternatives) {
      if (selections.size() >= kMaxStateSets)
        break;
      // Match the block's rows to the alternative's columns.
      graph::BipartiteGraph sub(static_cast<int>(amb.rows.size()),
                                static_cast<int>(alt.size()));
      for (size_t r = 0; r < amb.rows.size(); ++r)
        for (size_t k = 0; k < alt.size(); ++k) {
          const std::vector<int> &adj = top.g.rows[amb.rows[r]];
          if (std::find(adj.begin(), adj.end(), alt[k]) != adj.end())
            sub.addEdge(static_cast<int>(r), static_cast<int>(k));
        }
      graph::Matching sm = graph::maximumMatching(sub);
      std::vector<std::pair<int, int>> override;
      for (size_t r = 0; r < amb.rows.size(); ++r)
        override.emplace_back(amb.rows[r], alt[sm.rowMate[r]]);
      // Keep the other blocks as in the first choice.
      for (size_t b = 0; b < sel.ambiguous.size(); ++b)
        if (b != a)
          for (int r : sel.ambiguous[b].rows)
            override.emplace_back(r, top.colOfVar[first.back()[r]]);
      std::vector<std::vector<int>> choice = sel.choose(override, false);
      if (choice.empty())
        continue;
      bool duplicate = false;
      for (const auto &prev : selections)
        duplicate = duplicate || sel.toChoice(prev) == sel.toChoice(choice);
      if (!duplicate)
        selections.push_back(choice);
    }
  }
  for (const auto &choice : selections) {
    out.choices.push_back(sel.toChoice(choice));
    unsigned size = 0;
    if (sel.ambiguous.empty()) {
      out.pivots.emplace_back();
    } else {
      out.pivots.push_back(sel.pivot(choice.back(), size));
    }
    out.pivotSizes.push_back(size);
  }

  // The chosen set must be well conditioned at the start point.
  if (out.pivotSizes[0] > 0) {
    const unsigned m = out.pivotSizes[0];
    Eigen::MatrixXd P(m, m);
    ir::EvalEnv env = ctx.startEnv();
    for (unsigned k = 0; k < m * m; ++k) {
      auto v = ir::evaluate(out.pivots[0][k], env);
      P(k % m, k / m) = v ? *v : std::numeric_limits<double>::quiet_NaN();
    }
    double cond = numeric::conditionNumber(P);
    if (!(cond < 1e8)) {
      std::vector<std::string> states;
      for (size_t j = 0; j < mr.unknowns.size(); ++j)
        if (out.choices[0][j] > 1 && red.highest[j] > 0)
          states.push_back(ctx.model.variables[mr.unknowns[j]].name);
      ctx.diags.report(DiagId::WarnStateSelectIllConditioned, ctx.model.loc,
                     {quotedList(states), ir::printNumber(cond)});
    }
  }

  // The result must need as many dummies as there were differentiations.
  // (Every row after the equations is one differentiation.)
  // A dynamic block's states are new unknowns with two equations each,
  // one more dummy per state.
  int dummies = 0;
  int diffs = static_cast<int>(red.rows.size() - mr.equations.size());
  for (const DynamicBlock &b : out.dynamic)
    diffs += static_cast<int>(b.candidates.size() + b.forced.size()) -
             static_cast<int>(b.rows);
  for (size_t j = 0; j < mr.unknowns.size(); ++j)
    dummies += red.highest[j] + 1 - out.choices[0][j];
  if (dummies != diffs) {
    ctx.diags.report(DiagId::ErrIndexReductionFailed, ctx.model.loc,
                   {std::to_string(diffs) + " differentiations but " +
                    std::to_string(dummies) + " dummy derivatives"});
    return false;
  }
  for (size_t j = 0; j < mr.unknowns.size(); ++j) {
    const ir::Variable &v = ctx.model.variables[mr.unknowns[j]];
    // A run-time candidate may well be a state: what the user is told is
    // that its stateSelect does not take part in the choice.
    const DynamicBlock *dynamic = nullptr;
    for (const DynamicBlock &b : out.dynamic)
      for (const ir::VarKey &k : b.candidates)
        if (k.var == mr.unknowns[j])
          dynamic = &b;
    if (dynamic && (v.stateSelect == ir::StateSelect::Always ||
                    v.stateSelect == ir::StateSelect::Prefer ||
                    v.stateSelect == ir::StateSelect::Never))
      ctx.diags.report(DiagId::WarnStateSelectDynamic, v.loc,
                       {v.name, ir::stateSelectName(v.stateSelect),
                        std::to_string(dynamic->candidates.size())});
    else if (v.stateSelect == ir::StateSelect::Always && red.highest[j] > 0 &&
             out.choices[0][j] <= red.highest[j] && out.choices[0][j] <= 1)
      ctx.diags.report(DiagId::WarnStateSelectAlways, v.loc, {v.name});
  }
  return true;
}

// Before build-system names the slots: each candidate set's states and
// dummy derivatives in the model's own names.
void DummyDerivativesPass::print(PassContext &ctx, ResultStore &results,
                                 std::ostream &out) const {
  const MatchingResult &mr = results.get<MatchingResult>();
  const IndexReduction &red = results.get<IndexReduction>();
  const DummyChoices &dc = results.get<DummyChoices>();
  for (size_t set = 0; set < dc.choices.size(); ++set) {
    std::vector<std::string> states, dummies;
    for (size_t j = 0; j < mr.unknowns.size(); ++j) {
      const int d = red.highest[j], lowest = dc.choices[set][j];
      for (int k = 0; k <= d; ++k) {
        std::string name = ctx.model.variableName(
            ir::VarKey{mr.unknowns[j], static_cast<unsigned>(k)});
        if (k + 1 <= d && k + 1 < lowest)
          states.push_back(name);
        else if (k >= 1 && k >= lowest)
          dummies.push_back(name);
      }
    }
    out << "// state set " << set << ": states "
        << (states.empty() && !dc.dynamic.empty() ? "chosen at run time"
                                                  : quotedList(states))
        << "; dummy derivatives " << quotedList(dummies) << "\n";
  }
  for (size_t b = 0; b < dc.dynamic.size(); ++b) {
    const DynamicBlock &blk = dc.dynamic[b];
    std::vector<std::string> cands, start;
    for (size_t j = 0; j < blk.candidates.size(); ++j) {
      cands.push_back(ctx.model.variableName(blk.candidates[j]));
      if (!std::binary_search(blk.startDummies.begin(), blk.startDummies.end(),
                              static_cast<int>(j)))
        start.push_back(cands.back());
    }
    out << "// chosen at run time " << b + 1 << ": "
        << blk.candidates.size() + blk.forced.size() - blk.rows
        << " states among " << quotedList(cands)
        << " (start: " << quotedList(start) << ")\n";
  }
}

} // namespace

std::unique_ptr<Pass> createDummyDerivativesPass() {
  return std::make_unique<DummyDerivativesPass>();
}

} // namespace ldae::passes
