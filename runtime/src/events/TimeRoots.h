// The zero crossings of a model with no unknowns (docs/events.md, "Models
// without unknowns"): its relations' root functions read time alone, and no
// integrator watches them, so the run looks for their changes of sign
// itself, on a sub-grid of each stretch it walks, and locates each by
// bisection to the first time just past the crossing.
#pragma once

#include "model/ModelEval.h"

#include <vector>

namespace ldae::runtime {

class TimeRoots {
public:
  explicit TimeRoots(const ModelEval &ev);

  /// The first time in (from, to] at which a root function has another
  /// sign (zero counting as a sign) than at `from`, located to a few ulps
  /// of the crossing on its far side; `to` when there is none.
  double first(double from, double to);

private:
  bool evaluate(double t, std::vector<double> &g) const;
  /// Whether some root function differs in sign between `a` and `g`.
  static bool signChanged(const std::vector<double> &a,
                          const std::vector<double> &g);

  const ModelEval &ev_;
  int nr_;
};

} // namespace ldae::runtime
