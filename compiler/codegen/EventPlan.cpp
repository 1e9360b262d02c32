// The events block of the code plan; see EventPlan.h. The checks here are
// the ones a runtime could not survive: an index it would read out of
// bounds, a function it would call with a missing expression.
#include "codegen/EventPlan.h"

#include "codegen/CodePlan.h"
#include "ldae/model.h"

namespace ldae::codegen {

namespace {

int abiKind(ir::DiscreteKind k) {
  switch (k) {
  case ir::DiscreteKind::Variable: return LDAE_DISCRETE_VARIABLE;
  case ir::DiscreteKind::Relation: return LDAE_DISCRETE_RELATION;
  case ir::DiscreteKind::When: return LDAE_DISCRETE_WHEN;
  case ir::DiscreteKind::Sample: return LDAE_DISCRETE_SAMPLE;
  case ir::DiscreteKind::Initial: return LDAE_DISCRETE_INITIAL;
  case ir::DiscreteKind::Terminal: return LDAE_DISCRETE_TERMINAL;
  case ir::DiscreteKind::Delay: return LDAE_DISCRETE_DELAY;
  }
  return LDAE_DISCRETE_VARIABLE;
}

/// Collects the first failed check's message.
class Checker {
public:
  bool ok() const { return error_.empty(); }
  const std::string &error() const { return error_; }

  void require(bool holds, const std::string &what) {
    if (!holds && error_.empty())
      error_ = "events: " + what;
  }
  void count(size_t got, size_t want, const std::string &what) {
    require(got == want, what + " has " + std::to_string(got) +
                             " entries for " + std::to_string(want));
  }
  /// Copies `indices` into `out`, each in [lo, bound).
  template <typename T>
  void indices(const std::vector<T> &in, long lo, size_t bound,
               const std::string &what, std::vector<int> &out) {
    for (T i : in) {
      require(long(i) >= lo && long(i) < long(bound),
              what + " " + std::to_string(long(i)) + " is out of range (" +
                  std::to_string(bound) + ")");
      out.push_back(int(i));
    }
  }
  void present(ir::ExprRef e, const std::string &what) {
    require(e != nullptr, what + " has no expression");
  }

private:
  std::string error_;
};

/// Per state set tables of n entries (dummy_of, original_row), each entry
/// in [lo, bound): empty, or one row per state set.
template <typename T>
void perSetTable(Checker &c, const std::vector<std::vector<T>> &in,
                 size_t sets, size_t n, long lo, size_t bound,
                 const std::string &what, std::vector<std::vector<int>> &out) {
  if (in.empty())
    return;
  c.count(in.size(), sets, what);
  for (const std::vector<T> &row : in) {
    c.count(row.size(), n, what + " row");
    out.emplace_back();
    c.indices(row, lo, bound, what, out.back());
  }
}

} // namespace

Expected<bool> planEventTables(const ir::DaeSystem &sys, EventPlan &plan,
                               const SourceManager *sources) {
  const ir::EventSystem &ev = sys.events;
  const size_t n = sys.unknowns.size(), nd = ev.discrete.size();
  Checker c;
  for (const ir::DiscreteValue &d : ev.discrete) {
    plan.discreteNames.push_back(d.name);
    plan.discreteStart.push_back(d.start);
    plan.discreteKind.push_back(abiKind(d.kind));
  }
  c.count(ev.update.size(), nd, "the update");
  for (ir::ExprRef e : ev.update)
    c.present(e, "an update");
  // A system without discrete values may still have plain roots.
  if (nd > 0 || !ev.rootRelation.empty()) {
    c.count(ev.rootRelation.size(), sys.roots.size(), "root_relation");
    c.indices(ev.rootRelation, 0, nd, "root_relation", plan.rootRelation);
  }
  for (const ir::ReinitUpdate &r : ev.reinits) {
    c.require(r.unknown < n, "reinit target " + std::to_string(r.unknown) +
                                 " is out of range (" + std::to_string(n) +
                                 ")");
    c.present(r.value, "a reinit value");
    c.present(r.fired, "a reinit");
    plan.reinitTarget.push_back(int(r.unknown));
  }
  for (const ir::TerminateUpdate &t : ev.terminates) {
    c.present(t.fired, "a terminate");
    plan.terminateMessage.push_back(t.message);
  }
  c.count(ev.thresholdRelation.size(), ev.timeThresholds.size(),
          "threshold_relation");
  c.indices(ev.thresholdRelation, 0, nd, "threshold_relation",
            plan.thresholdRelation);
  for (ir::ExprRef e : ev.timeThresholds)
    c.present(e, "a time threshold");
  c.count(ev.sampleDiscrete.size(), ev.samples.size(), "sample_discrete");
  c.indices(ev.sampleDiscrete, 0, nd, "sample_discrete", plan.sampleDiscrete);
  for (const auto &[start, interval] : ev.samples) {
    c.present(start, "a sample start");
    c.present(interval, "a sample interval");
  }
  // The runtime finds the delays by their kind, in discrete order.
  std::vector<uint32_t> delayed;
  for (size_t k = 0; k < nd; ++k)
    if (ev.discrete[k].kind == ir::DiscreteKind::Delay)
      delayed.push_back(uint32_t(k));
  c.count(ev.delays.size(), delayed.size(), "the delays");
  for (size_t j = 0; j < ev.delays.size() && j < delayed.size(); ++j) {
    c.require(ev.delays[j].discrete == delayed[j],
              "delay " + std::to_string(j) + " is not the discrete value " +
                  std::to_string(delayed[j]));
    c.present(ev.delays[j].source, "a delayed expression");
    c.present(ev.delays[j].time, "a delay time");
    c.present(ev.delays[j].max, "a maximum delay");
  }
  if (!ev.asserts.empty())
    plan.assertValueBegin.assign(1, 0);
  for (const ir::AssertCheck &a : ev.asserts) {
    c.present(a.condition, "an assert");
    for (ir::ExprRef v : a.messageValues)
      c.present(v, "a value of an assert's message");
    plan.assertValueBegin.push_back(plan.assertValueBegin.back() +
                                    int(a.messageValues.size()));
    plan.assertMessage.push_back(a.message);
    plan.assertLevel.push_back(a.level);
    plan.assertOrigin.push_back(sourceOrigin(sources, a.loc, ""));
  }
  c.count(ev.modeValues.size(), ev.modeDiscrete.size(), "mode_values");
  c.indices(ev.modeDiscrete, 0, nd, "mode_discrete", plan.modeDiscrete);
  plan.modeValues = ev.modeValues;
  const size_t sets = sys.stateSets.size();
  perSetTable(c, sys.dummyOf, sets, n, -1, n, "dummy_of", plan.dummyOf);
  perSetTable(c, sys.originalRow, sets, n, 0, 2, "original_row",
              plan.originalRow);
  if (!c.ok())
    return Error{c.error()};
  return true;
}

EventFunctionValues eventFunctionValues(const ir::EventSystem &ev) {
  EventFunctionValues v;
  v.update = ev.update;
  for (const ir::ReinitUpdate &r : ev.reinits)
    v.update.push_back(r.value);
  for (const ir::ReinitUpdate &r : ev.reinits)
    v.update.push_back(r.fired);
  for (const ir::TerminateUpdate &t : ev.terminates)
    v.update.push_back(t.fired);
  v.timeEvents = ev.timeThresholds;
  for (const auto &[start, interval] : ev.samples) {
    v.timeEvents.push_back(start);
    v.timeEvents.push_back(interval);
  }
  for (const ir::DelayInput &d : ev.delays) {
    v.timeEvents.push_back(d.source);
    v.timeEvents.push_back(d.time);
    v.timeEvents.push_back(d.max);
  }
  // The conditions, then every assert's message values in order.
  for (const ir::AssertCheck &a : ev.asserts)
    v.asserts.push_back(a.condition);
  for (const ir::AssertCheck &a : ev.asserts)
    v.asserts.insert(v.asserts.end(), a.messageValues.begin(),
                     a.messageValues.end());
  return v;
}

} // namespace ldae::codegen
