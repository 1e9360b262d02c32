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
#include "codegen/CodePlan.h"

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

  /// The cone of `s`; `nodes` is empty if it exceeds kLoopMaxBody nodes.
  Cone walk(const PlanStore &s) {
    Cone c;
    if (!visit(s.node, c.nodes)) {
      reset(c.nodes);
      c.nodes.clear();
      return c;
    }
    c.shape.reserve(c.nodes.size() * 12 + 1);
    c.shape.push_back(char(s.array));
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

  void reset(const std::vector<uint32_t> &nodes) {
    for (uint32_t k : nodes)
      local_[k] = -1;
    for (auto &[k, next] : stack_)
      local_[k] = -1;
  }

  const PlanFunction &fn_;
  std::vector<int32_t> local_;
  std::vector<std::pair<uint32_t, unsigned>> stack_;

public:
  /// Local index of a node during `build` (the cone of the first instance).
  std::vector<int32_t> &local() { return local_; }
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

/// Builds the loop computing stores `members` of `fn`, all with the shape
/// of `cone` (the first member's cone).
PlanLoop buildLoop(const PlanFunction &fn, const std::vector<uint32_t> &members,
                   const std::vector<Cone> &cones) {
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
  bool needsRow = fn.nodes[fn.stores[members[0]].node].mayFail;
  unsigned indexCol = raw.size(), rowCol = needsRow ? indexCol + 1 : indexCol;
  raw.resize(rowCol + 1);
  for (std::vector<int64_t> &c : raw)
    c.reserve(members.size());
  for (uint32_t m : members) {
    const Cone &cone = cones[m];
    for (size_t j = 0; j < cone.nodes.size(); ++j)
      if (isLoad(fn.nodes[cone.nodes[j]].op))
        raw[loadColumn[j]].push_back(fn.nodes[cone.nodes[j]].index);
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
  const PlanStore &s = fn.stores[members[0]];
  uint32_t root = body.nodes.size() - 1;
  body.stores.push_back(
      {root, s.array, columnOf[indexCol], columnOf[rowCol], root});
  body.chunks.push_back({0, uint32_t(body.nodes.size()), 0, 1});
  body.spill.assign(body.nodes.size(), -1);
  return loop;
}

} // namespace

void rollLoops(PlanFunction &fn) {
  if (fn.stores.size() < kLoopMinStores)
    return;
  ConeWalker walker(fn);
  std::vector<Cone> cones(fn.stores.size());
  std::unordered_map<std::string, std::vector<uint32_t>> byShape;
  std::vector<const std::string *> order; // shapes in order of first store
  for (uint32_t i = 0; i < fn.stores.size(); ++i) {
    cones[i] = walker.walk(fn.stores[i]);
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
    fn.loops.push_back(buildLoop(fn, members, cones));
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
