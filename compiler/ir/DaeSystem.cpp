// The differential flags of the layout rule (see DaeSystem.h).
#include "ir/DaeSystem.h"

namespace ldae::ir {

std::vector<bool> setDifferential(const DaeSystem &sys, size_t set) {
  const StateSet &st = sys.stateSets[set];
  if (!st.differential.empty())
    return st.differential;
  std::vector<bool> flags(sys.unknowns.size());
  for (size_t i = 0; i < flags.size(); ++i)
    flags[i] = sys.unknowns[i].differential;
  return flags;
}

std::vector<bool> anyDifferential(const DaeSystem &sys) {
  std::vector<bool> flags(sys.unknowns.size(), false);
  for (size_t set = 0; set < sys.stateSets.size(); ++set) {
    std::vector<bool> f = setDifferential(sys, set);
    for (size_t i = 0; i < flags.size(); ++i)
      flags[i] = flags[i] || f[i];
  }
  return flags;
}

} // namespace ldae::ir
