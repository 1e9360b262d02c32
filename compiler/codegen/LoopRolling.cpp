// Loop rolling over a straight-line plan function: stores whose expression
// cones have the same shape (same operations, constants and operand
// structure; only the y/y'/p slots, the output index and the row differ)
// are moved into one PlanLoop that reads its slots from index columns. A
// model built from `for` loops or component arrays then compiles in time
// proportional to its number of distinct equation shapes, and LLVM sees a
// few small loops instead of 10^5 straight-line statements.
//
// The shape of a store is its cone in depth-first post-order from the
// stored node, following operands a, b, c: canonical by structure, so it
// does not depend on the order in which nodes were created. Each distinct
// load leaf of the cone becomes a column (a leaf used twice in the cone is
// one column; two leaves with the same slot are two columns with equal
// contents, merged when the columns are deduplicated).
#include "codegen/LoopRolling.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <unordered_map>

namespace ldae::codegen {

namespace {

bool isLoad(OpCode op) {
  return op == OpCode::LoadY || op == OpCode::LoadYp || op == OpCode::LoadP;
}

/// One store's cone, canonically ordered, or empty when it is too large.
struct Cone {
  std::vector<uint32_t> nodes; // plan node indices, post-order
  std::string shape;           // equal for stores a loop may share
};

class ConeWalker {
public:
  explicit ConeWalker(const PlanFunction &fn)
      : fn_(fn), local_(fn.nodes.size(), -1) {}

  /// The cone of `root`; `nodes` is empty if it exceeds kLoopMaxBody nodes
  /// or holds a Reduce (loops do not nest). `tag` starts the shape (the
  /// store's output array, a term's sign).
  Cone walk(uint32_t root, char tag) {
    Cone c;
    if (!visit(root, c.nodes)) {
      reset(c.nodes);
      c.nodes.clear();
      return c;
    }
    c.shape.reserve(c.nodes.size() * 12 + 1);
    c.shape.push_back(tag);
    uint32_t loads = 0;
    for (uint32_t k : c.nodes) {
      const PlanNode &n = fn_.nodes[k];
      put(c.shape, uint8_t(n.op));
      put(c.shape, n.sub);
      if (n.op == OpCode::Const)
        put(c.shape, n.value);
      else if (isLoad(n.op))
        put(c.shape, loads++);
      else if (n.op == OpCode::PowInt)
        put(c.shape, n.index);
      for (unsigned i = 0; i < numOperands(n.op); ++i)
        put(c.shape, uint32_t(local_[n.operand(i)]));
    }
    reset(c.nodes);
    return c;
  }

private:
  template <typename T> static void put(std::string &s, T v) {
    char buf[sizeof(T)];
    std::memcpy(buf, &v, sizeof(T));
    s.append(buf, sizeof(T));
  }

  /// Post-order DFS from `root`; false once more than kLoopMaxBody nodes.
  bool visit(uint32_t root, std::vector<uint32_t> &out) {
    stack_.clear();
    stack_.push_back({root, 0});
    while (!stack_.empty()) {
      auto &[k, next] = stack_.back();
      if (local_[k] >= 0) {
        stack_.pop_back();
        continue;
      }
      const PlanNode &n = fn_.nodes[k];
      if (n.op == OpCode::Reduce || n.op == OpCode::ExtCall)
        return false; // an external call keeps its own node (impure ones)
      if (next < numOperands(n.op)) {
        uint32_t child = n.operand(next++);
        if (local_[child] < 0)
          stack_.push_back({child, 0});
        continue;
      }
      local_[k] = int32_t(out.size());
      out.push_back(k);
      stack_.pop_back();
      if (out.size() > kLoopMaxBody)
        return false;
    }
    return true;
  }

  /// Only finished nodes get a local index, so clearing `nodes` suffices.
  void reset(const std::vector<uint32_t> &nodes) {
    for (uint32_t k : nodes)
      local_[k] = -1;
  }

  const PlanFunction &fn_;
  std::vector<int32_t> local_;
  std::vector<std::pair<uint32_t, unsigned>> stack_;

};

/// An index column from its values: affine when evenly spaced.
IndexColumn makeColumn(const std::vector<int64_t> &values) {
  IndexColumn c;
  c.base = values[0];
  c.stride = values.size() > 1 ? values[1] - values[0] : 0;
  for (size_t i = 2; i < values.size(); ++i)
    if (values[i] != c.base + int64_t(i) * c.stride) {
      c.table.assign(values.begin(), values.end());
      c.base = c.stride = 0;
      break;
    }
  return c;
}

/// Builds the loop whose iteration i evaluates the cone `cones[members[i]]`
/// (all of one shape) and, unless it is a reduction, performs the store
/// `fn.stores[members[i]]`.
PlanLoop buildLoop(const PlanFunction &fn, const std::vector<uint32_t> &members,
                   const std::vector<Cone> &cones, bool reduction) {
  const Cone &first = cones[members[0]];
  PlanLoop loop;
  loop.count = members.size();
  PlanFunction &body = loop.body;
  body.name = fn.name;
  body.sig = fn.sig;

  // Raw columns: one per load leaf (in cone order), then index and row.
  std::vector<std::vector<int64_t>> raw;
  std::vector<unsigned> loadColumn(first.nodes.size(), 0);
  for (size_t j = 0; j < first.nodes.size(); ++j)
    if (isLoad(fn.nodes[first.nodes[j]].op)) {
      loadColumn[j] = raw.size();
      raw.emplace_back();
    }
  // The row is read only to report a domain error.
  bool needsRow =
      !reduction && fn.nodes[fn.stores[members[0]].node].mayFail;
  unsigned indexCol = raw.size(), rowCol = needsRow ? indexCol + 1 : indexCol;
  if (!reduction)
    raw.resize(rowCol + 1);
  for (std::vector<int64_t> &c : raw)
    c.reserve(members.size());
  for (uint32_t m : members) {
    const Cone &cone = cones[m];
    for (size_t j = 0; j < cone.nodes.size(); ++j)
      if (isLoad(fn.nodes[cone.nodes[j]].op))
        raw[loadColumn[j]].push_back(fn.nodes[cone.nodes[j]].index);
    if (reduction)
      continue;
    raw[indexCol].push_back(fn.stores[m].index);
    if (needsRow)
      raw[rowCol].push_back(fn.stores[m].row);
  }
  // Equal columns (the residual's index and row; a slot read by two leaves)
  // are kept once.
  std::vector<unsigned> columnOf(raw.size());
  for (size_t c = 0; c < raw.size(); ++c) {
    size_t same = 0;
    while (same < c && raw[same] != raw[c])
      ++same;
    if (same < c) {
      columnOf[c] = columnOf[same];
      continue;
    }
    columnOf[c] = loop.columns.size();
    loop.columns.push_back(makeColumn(raw[c]));
  }

  // The body: the first member's cone with operands renumbered locally.
  std::unordered_map<uint32_t, uint32_t> localOf;
  for (size_t j = 0; j < first.nodes.size(); ++j)
    localOf.emplace(first.nodes[j], j);
  for (size_t j = 0; j < first.nodes.size(); ++j) {
    PlanNode n = fn.nodes[first.nodes[j]];
    for (unsigned i = 0; i < numOperands(n.op); ++i) {
      uint32_t &operand = i == 0 ? n.a : i == 1 ? n.b : n.c;
      operand = localOf.at(operand);
    }
    if (isLoad(n.op))
      n.index = int32_t(columnOf[loadColumn[j]]);
    body.nodes.push_back(n);
  }
  uint32_t root = body.nodes.size() - 1;
  if (!reduction) {
    const PlanStore &s = fn.stores[members[0]];
    body.stores.push_back(
        {root, s.array, columnOf[indexCol], columnOf[rowCol], root});
  }
  body.chunks.push_back({0, uint32_t(body.nodes.size()), 0,
                         uint32_t(body.stores.size())});
  body.spill.assign(body.nodes.size(), -1);
  return loop;
}

/// Finds sums of at least kReductionMinTerms terms (chains a + t1 - t2 ...
/// whose inner links have no other use) and replaces each run of at least
/// kLoopMinCount consecutive terms of one sign and shape by a Reduce node:
/// the same additions in the same order, run by a loop.
void rollReductions(PlanFunction &fn) {
  auto isSum = [&](uint32_t k) {
    return fn.nodes[k].op == OpCode::Add || fn.nodes[k].op == OpCode::Sub;
  };
  // The user of each node that has exactly one use, when that user
  // continues its chain (reads it as operand a).
  std::vector<uint32_t> uses(fn.nodes.size(), 0), user(fn.nodes.size(), 0);
  for (uint32_t k = 0; k < fn.nodes.size(); ++k)
    for (unsigned i = 0; i < numOperands(fn.nodes[k].op); ++i) {
      ++uses[fn.nodes[k].operand(i)];
      user[fn.nodes[k].operand(i)] = k;
    }
  for (const PlanStore &s : fn.stores)
    uses[s.node] += 2; // a stored value ends its chain
  auto continues = [&](uint32_t k) {
    return uses[k] == 1 && isSum(user[k]) && fn.nodes[user[k]].a == k &&
           fn.nodes[user[k]].b != k;
  };
  ConeWalker walker(fn);
  std::vector<uint32_t> chain;
  std::vector<Cone> cones;
  for (uint32_t top = 0; top < fn.nodes.size(); ++top) {
    if (!isSum(top) || continues(top))
      continue;
    chain.clear();
    for (uint32_t c = top;; c = fn.nodes[c].a) {
      chain.push_back(c);
      uint32_t below = fn.nodes[c].a;
      if (!isSum(below) || !continues(below))
        break;
    }
    if (chain.size() < kReductionMinTerms)
      continue;
    std::reverse(chain.begin(), chain.end()); // first addition first
    cones.clear();
    for (uint32_t c : chain)
      cones.push_back(walker.walk(fn.nodes[c].b, char(fn.nodes[c].op)));
    for (size_t s = 0; s < chain.size();) {
      size_t e = s + 1;
      while (e < chain.size() && !cones[s].nodes.empty() &&
             cones[e].shape == cones[s].shape)
        ++e;
      if (cones[s].nodes.empty() || e - s < kLoopMinCount) {
        s = e;
        continue;
      }
      std::vector<uint32_t> members;
      for (size_t j = s; j < e; ++j)
        members.push_back(j);
      PlanLoop loop = buildLoop(fn, members, cones, true);
      loop.subtract = fn.nodes[chain[s]].op == OpCode::Sub;
      PlanNode &last = fn.nodes[chain[e - 1]];
      last.op = OpCode::Reduce;
      last.a = fn.nodes[chain[s]].a;
      last.b = last.c = 0;
      last.index = int32_t(fn.reductions.size());
      last.checks = false;
      last.mayFail =
          fn.nodes[last.a].mayFail || loop.body.nodes.back().mayFail;
      fn.reductions.push_back(std::move(loop));
      s = e;
    }
  }
}

} // namespace

void rollLoops(PlanFunction &fn) {
  rollReductions(fn);
  if (!fn.reductions.empty())
    removeDeadNodes(fn);
  if (fn.stores.size() < kLoopMinStores)
    return;
  ConeWalker walker(fn);
  std::vector<Cone> cones(fn.stores.size());
  std::unordered_map<std::string, std::vector<uint32_t>> byShape;
  std::vector<const std::string *> order; // shapes in order of first store
  for (uint32_t i = 0; i < fn.stores.size(); ++i) {
    cones[i] = walker.walk(fn.stores[i].node, char(fn.stores[i].array));
    if (cones[i].nodes.empty())
      continue;
    auto [it, fresh] = byShape.try_emplace(cones[i].shape);
    if (fresh)
      order.push_back(&it->first);
    it->second.push_back(i);
  }
  std::vector<char> rolled(fn.stores.size(), 0);
  for (const std::string *shape : order) {
    const std::vector<uint32_t> &members = byShape.at(*shape);
    if (members.size() < kLoopMinCount)
      continue;
    fn.loops.push_back(buildLoop(fn, members, cones, false));
    for (uint32_t m : members)
      rolled[m] = 1;
  }
  if (fn.loops.empty())
    return;
  std::vector<PlanStore> kept;
  for (uint32_t i = 0; i < fn.stores.size(); ++i)
    if (!rolled[i])
      kept.push_back(fn.stores[i]);
  fn.stores = std::move(kept);
  removeDeadNodes(fn);
}

} // namespace ldae::codegen
