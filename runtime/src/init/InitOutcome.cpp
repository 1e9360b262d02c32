// The conditions of the start and of the re-initialization after an event
// (see InitOutcome.h).
#include "init/InitOutcome.h"

namespace ldae::runtime {

InitConditions InitConditions::atStart(const ldae_model &m) {
  InitConditions c;
  c.held.assign(m.n, 0);
  if (m.fixed)
    for (int i = 0; i < m.n; ++i)
      c.held[i] = m.fixed[i] != 0;
  return c;
}

InitConditions InitConditions::afterEvent(const ldae_model &m,
                                          const std::vector<int> &held) {
  InitConditions c;
  c.held.assign(m.n, 0);
  for (int i : held)
    if (i >= 0 && i < m.n)
      c.held[i] = 1;
  c.initialEquations = false;
  return c;
}

} // namespace ldae::runtime
