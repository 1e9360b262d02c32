// The jump rule's tables (see JumpPencil.h).
#include "passes/JumpPencil.h"

#include <string>
#include <unordered_map>

namespace ldae::passes {

namespace {

bool saysNothing(const ir::DaeSystem &sys) {
  for (const std::vector<int> &d : sys.dummyOf)
    for (int j : d)
      if (j >= 0)
        return false;
  for (const std::vector<bool> &o : sys.originalRow)
    for (bool b : o)
      if (!b)
        return false;
  return true;
}

} // namespace

void fillJumpPencil(const PassContext &pc, const MatchingResult &mr,
                    const IndexReduction &red, const DummyChoices &dc,
                    ir::DaeSystem &sys) {
  sys.dummyOf.clear();
  sys.originalRow.clear();
  if (!pc.jumpsMatter && (pc.opts.causalize || !pc.opts.outputs.empty()))
    return;
  const size_t n = sys.unknowns.size();
  // Slots by the name build-system gives them: der(x) for order 1 of x,
  // whether it holds Variable(x, 1) or a fresh variable.
  std::unordered_map<std::string, int> slot;
  for (size_t u = 0; u < n; ++u)
    slot.emplace(sys.unknowns[u].name, static_cast<int>(u));
  auto slotOf = [&](size_t j, unsigned k) {
    auto it = slot.find(
        pc.model.variableName(ir::VarKey{mr.unknowns[j], k}));
    return it == slot.end() ? -1 : it->second;
  };
  // The equations and their derivatives come first, in build-system's
  // order; then each set's link rows.
  std::vector<bool> common;
  for (size_t i = 0; i < mr.equations.size(); ++i)
    for (int r = static_cast<int>(i); r >= 0; r = red.rows[r].next)
      common.push_back(red.rows[r].times == 0);
  // A dynamic set's x - A c as written, der(x) - A der(c) its derivative.
  for (const ir::DynamicStateSet &ds : sys.dynamicSets)
    for (size_t k = 0; k < ds.states.size(); ++k) {
      common.push_back(true);
      common.push_back(false);
    }
  for (size_t set = 0; set < sys.stateSets.size(); ++set) {
    std::vector<int> dummy(n, -1);
    for (size_t j = 0; j < mr.unknowns.size(); ++j)
      for (int k = std::max(1, dc.choices[set][j]);
           k <= red.highest[j]; ++k) {
        int u = slotOf(j, k), below = slotOf(j, k - 1);
        if (u >= 0 && below >= 0)
          dummy[u] = below;
      }
    std::vector<bool> original = common;
    original.resize(sys.stateSets[set].residuals.size(), true);
    sys.dummyOf.push_back(std::move(dummy));
    sys.originalRow.push_back(std::move(original));
  }
  if (saysNothing(sys)) {
    sys.dummyOf.clear();
    sys.originalRow.clear();
  }
}

bool restrictJumpPencil(ir::DaeSystem &sys, const std::vector<int> &newIndex,
                        const std::vector<std::vector<int>> &keptRows) {
  if (sys.dummyOf.empty())
    return true;
  int kept = 0;
  for (int i : newIndex)
    kept += i >= 0;
  for (size_t set = 0; set < sys.dummyOf.size(); ++set) {
    std::vector<int> dummy(kept, -1);
    for (size_t u = 0; u < newIndex.size(); ++u) {
      int j = sys.dummyOf[set][u];
      if (newIndex[u] < 0 || j < 0)
        continue;
      if (newIndex[j] < 0) {
        sys.dummyOf.clear();
        sys.originalRow.clear();
        return false;
      }
      dummy[newIndex[u]] = newIndex[j];
    }
    std::vector<bool> original;
    for (int r : keptRows[set])
      original.push_back(sys.originalRow[set][r]);
    sys.dummyOf[set] = std::move(dummy);
    sys.originalRow[set] = std::move(original);
  }
  return true;
}

} // namespace ldae::passes
