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

void forEachEventExpr(EventSystem &ev,
                      const std::function<void(ExprRef &)> &f) {
  for (ExprRef &e : ev.update)
    f(e);
  for (ReinitUpdate &r : ev.reinits) {
    f(r.value);
    f(r.fired);
  }
  for (TerminateUpdate &t : ev.terminates)
    f(t.fired);
  for (ExprRef &e : ev.timeThresholds)
    f(e);
  for (auto &[start, interval] : ev.samples) {
    f(start);
    f(interval);
  }
  for (DelayInput &d : ev.delays) {
    f(d.source);
    f(d.time);
    f(d.max);
  }
  for (AssertCheck &a : ev.asserts) {
    f(a.condition);
    for (ExprRef &v : a.messageValues)
      f(v);
  }
}

std::vector<ExprRef> eventExprs(const EventSystem &ev) {
  std::vector<ExprRef> all;
  forEachEventExpr(const_cast<EventSystem &>(ev),
                   [&](ExprRef &e) { all.push_back(e); });
  return all;
}

bool renumberReinits(EventSystem &ev, const std::vector<int> &newIndex) {
  for (ReinitUpdate &r : ev.reinits) {
    if (r.unknown >= newIndex.size() || newIndex[r.unknown] < 0)
      return false;
    r.unknown = static_cast<uint32_t>(newIndex[r.unknown]);
  }
  return true;
}

} // namespace ldae::ir
