// The consistent combination of coupled relations (see RelationSearch.h).
#include "events/RelationSearch.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace ldae::runtime {

namespace {

bool differs(double a, double b) {
  return a != b && !(std::isnan(a) && std::isnan(b));
}

/// The residual rows of state set `set` at (t, y, y') that change when
/// relation k is flipped.
class FlipProbe {
public:
  FlipProbe(ModelEval &ev, int set, double t, const std::vector<double> &y,
            const std::vector<double> &yp)
      : ev_(ev), set_(set), t_(t), y_(y), yp_(yp), base_(ev.n()),
        flipped_(ev.n()) {
    ok_ = ev.residual(set, t, y.data(), yp.data(), base_.data()) == 0;
  }
  bool ok() const { return ok_; }
  std::vector<char> rowsOf(int k) {
    double *d = ev_.discrete();
    const double was = d[k];
    d[k] = was != 0 ? 0.0 : 1.0;
    std::vector<char> rows(base_.size(), 0);
    if (ev_.residual(set_, t_, y_.data(), yp_.data(), flipped_.data()) == 0)
      for (size_t i = 0; i < rows.size(); ++i)
        rows[i] = differs(flipped_[i], base_[i]);
    d[k] = was;
    return rows;
  }

private:
  ModelEval &ev_;
  int set_;
  double t_;
  const std::vector<double> &y_, &yp_;
  std::vector<double> base_, flipped_;
  bool ok_ = false;
};

/// The cycling relations and every relation that changes a residual row
/// one of them changes: the relations of the same if-expressions, or of
/// the same algebraic loop through them.
std::vector<int> coupledRelations(ModelEval &ev, int set, double t,
                                  const std::vector<double> &y,
                                  const std::vector<double> &yp,
                                  const std::vector<int> &cycling) {
  const ldae_model &m = ev.model();
  // Probed at the values held and with the cycling relations flipped (the
  // other state of the cycle): a relation of an if-expression's later
  // branch changes nothing while an earlier one holds.
  std::vector<char> coupled(m.n_discrete, 0);
  for (int k : cycling)
    coupled[k] = 1;
  double *d = ev.discrete();
  for (int state = 0; state < 2; ++state) {
    for (int k : cycling)
      if (state == 1)
        d[k] = d[k] != 0 ? 0.0 : 1.0;
    FlipProbe probe(ev, set, t, y, yp);
    if (probe.ok()) {
      std::vector<char> cycleRows(ev.n(), 0);
      for (int k : cycling) {
        std::vector<char> rows = probe.rowsOf(k);
        for (size_t i = 0; i < rows.size(); ++i)
          cycleRows[i] |= rows[i];
      }
      for (int k = 0; k < m.n_discrete; ++k) {
        if (coupled[k] || m.discrete_kind[k] != LDAE_DISCRETE_RELATION)
          continue;
        std::vector<char> rows = probe.rowsOf(k);
        for (size_t i = 0; i < rows.size() && !coupled[k]; ++i)
          coupled[k] = rows[i] && cycleRows[i];
      }
    }
    for (int k : cycling)
      if (state == 1)
        d[k] = d[k] != 0 ? 0.0 : 1.0;
  }
  std::vector<int> which;
  for (int k = 0; k < m.n_discrete; ++k)
    if (coupled[k])
      which.push_back(k);
  return which;
}

/// Whether discrete value k can be an unknown of a search: a relation, or
/// a variable at 0 or 1 (a Boolean; an Integer there is tried at 0 and 1
/// only, and a combination stands only if the update gives it back).
bool zeroOrOne(const ldae_model &m, const double *d, int k) {
  return m.discrete_kind[k] == LDAE_DISCRETE_RELATION ||
         (m.discrete_kind[k] == LDAE_DISCRETE_VARIABLE &&
          (d[k] == 0 || d[k] == 1));
}

/// A cycle through other discrete values too: the 0/1 values among the
/// cycling ones that change a residual row, and every 0/1 value that
/// changes one of those rows, probed at both states of the cycle (the
/// current values and `other`), as coupledRelations does. A cycling value
/// that no residual reads (a friction element's `mode`) is no unknown:
/// the update gives it from the others.
std::vector<int> coupledValues(ModelEval &ev, int set, double t,
                               const std::vector<double> &y,
                               const std::vector<double> &yp,
                               const std::vector<int> &cycling,
                               const std::vector<double> &other) {
  const ldae_model &m = ev.model();
  double *d = ev.discrete();
  const std::vector<double> now(d, d + m.n_discrete);
  std::vector<char> coupled(m.n_discrete, 0);
  for (const std::vector<double> *state : {&now, &other}) {
    std::copy(state->begin(), state->end(), d);
    FlipProbe probe(ev, set, t, y, yp);
    if (!probe.ok())
      continue;
    std::vector<char> cycleRows(ev.n(), 0);
    for (int k : cycling) {
      if (!zeroOrOne(m, d, k))
        continue;
      std::vector<char> rows = probe.rowsOf(k);
      for (size_t i = 0; i < rows.size(); ++i) {
        cycleRows[i] |= rows[i];
        coupled[k] |= rows[i];
      }
    }
    for (int k = 0; k < m.n_discrete; ++k) {
      if (coupled[k] || !zeroOrOne(m, d, k))
        continue;
      std::vector<char> rows = probe.rowsOf(k);
      for (size_t i = 0; i < rows.size() && !coupled[k]; ++i)
        coupled[k] = rows[i] && cycleRows[i];
    }
  }
  std::copy(now.begin(), now.end(), d);
  std::vector<int> which;
  for (int k = 0; k < m.n_discrete; ++k)
    if (coupled[k])
      which.push_back(k);
  return which;
}

std::string quotedNames(const ModelEval &ev, const std::vector<int> &which) {
  std::string names;
  for (size_t j = 0; j < which.size(); ++j)
    names += fmt::format("{}{}", j ? ", " : "", ev.quotedDiscreteName(which[j]));
  return names;
}

/// "'a' true, 'b' false" for the combination `mask` of `which`.
std::string combination(const ModelEval &ev, const std::vector<int> &which,
                        unsigned mask) {
  std::string text;
  for (size_t j = 0; j < which.size(); ++j)
    text += fmt::format("{}{} {}", j ? ", " : "", ev.quotedDiscreteName(which[j]),
                        (mask >> j) & 1 ? "true" : "false");
  return text;
}

} // namespace

namespace {

/// Solves the point for each combination of 0/1 values of `coupled` and
/// keeps the one whose point gives them back (see RelationSearch.h).
bool searchCombinations(ModelEval &ev, double t, std::vector<double> &y,
                        std::vector<double> &yp,
                        const std::vector<int> &coupled,
                        const std::string &cycle, const char *what,
                        const Reinitialize &reinit, std::string &failure) {
  const ldae_model &m = ev.model();
  const int nd = m.n_discrete;
  if (coupled.size() > kMaxCoupledRelations) {
    failure = fmt::format("{}; {} {} are coupled to them, more than "
                          "the {} whose combinations ldaec tries",
                          cycle, coupled.size(), what, kMaxCoupledRelations);
    return false;
  }
  double *d = ev.discrete();
  const std::vector<double> held(d, d + nd);
  std::vector<double> out(nd + 2 * std::max(m.n_reinit, 0) +
                          std::max(m.n_terminate, 0));
  auto setCombination = [&](unsigned mask) {
    std::copy(held.begin(), held.end(), d);
    for (size_t j = 0; j < coupled.size(); ++j)
      d[coupled[j]] = (mask >> j) & 1 ? 1.0 : 0.0;
  };
  std::vector<unsigned> consistent;
  for (unsigned mask = 0; mask < (1u << coupled.size()); ++mask) {
    setCombination(mask);
    std::vector<double> ty = y, typ = yp;
    std::string why;
    if (!reinit(t, ty, typ, {}, why) ||
        !m.event_update ||
        m.event_update(t, ty.data(), typ.data(), ev.params(), out.data()) != 0)
      continue;
    bool same = true;
    for (int k : coupled)
      same = same && !differs(out[k], d[k]);
    if (same)
      consistent.push_back(mask);
  }
  if (consistent.size() != 1) {
    std::copy(held.begin(), held.end(), d);
    if (consistent.empty()) {
      failure = fmt::format("{}; no combination of {} gives a point that "
                            "keeps them",
                            cycle, quotedNames(ev, coupled));
    } else {
      std::string list;
      for (size_t i = 0; i < consistent.size(); ++i)
        list += fmt::format("{}({})", i ? ", " : "",
                            combination(ev, coupled, consistent[i]));
      failure = fmt::format("{}; {} combinations of them are consistent: {}; "
                            "ldaec does not choose between them",
                            cycle, consistent.size(), list);
    }
    // The integrator is left at the last combination tried: back to the
    // values held.
    std::vector<double> ty = y, typ = yp;
    std::string why;
    reinit(t, ty, typ, {}, why);
    return false;
  }
  setCombination(consistent[0]);
  return reinit(t, y, yp, {}, failure);
}

} // namespace

bool chooseConsistentRelations(ModelEval &ev, int set, double t,
                               std::vector<double> &y, std::vector<double> &yp,
                               const std::vector<int> &cycling,
                               const Reinitialize &reinit,
                               std::string &failure) {
  const std::string cycle = fmt::format(
      "the event iteration at t = {:.10g} keeps coming back to the values of "
      "{}, each point solved contradicting the relations it was solved with",
      t, quotedNames(ev, cycling));
  return searchCombinations(ev, t, y, yp,
                            coupledRelations(ev, set, t, y, yp, cycling), cycle,
                            "relations", reinit, failure);
}

bool chooseConsistentValues(ModelEval &ev, int set, double t,
                            std::vector<double> &y, std::vector<double> &yp,
                            const std::vector<int> &cycling,
                            const std::vector<double> &other,
                            const Reinitialize &reinit, std::string &failure) {
  const std::string cycle = fmt::format(
      "the event iteration at t = {:.10g} keeps coming back to the values of "
      "{}, each point solved contradicting the values it was solved with",
      t, quotedNames(ev, cycling));
  std::vector<int> coupled = coupledValues(ev, set, t, y, yp, cycling, other);
  if (coupled.empty()) {
    failure = fmt::format("{}; none of them is a Boolean that an equation of "
                          "the point reads",
                          cycle);
    return false;
  }
  return searchCombinations(ev, t, y, yp, coupled, cycle, "Boolean values",
                            reinit, failure);
}

} // namespace ldae::runtime
