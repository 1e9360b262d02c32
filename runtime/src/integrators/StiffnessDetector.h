// When Adams under `--integrator auto` moves to BDF (CVODE on a linearly
// implicit model, `--method sga|ode`): every kStiffnessCheckEvery Adams
// steps the run looks at df/dy's spectrum, and a decaying mode that holds
// Adams' step at its stability bound for much of the rest of the run makes
// the field stiff (docs/runtime.md). The same look feeds the SGA's Adams
// stabilization its spectral radius (SgaProjectionPolicy.h).
#pragma once

#include <Eigen/Dense>

namespace ldae::runtime {

class StiffnessDetector {
public:
  /// Whether the spectrum of a model of `n` unknowns is worth computing:
  /// above this size it costs more than it can save (`auto` is BDF then).
  static bool affordable(int n) { return n <= kMaxUnknowns; }

  /// Counts an Adams step; true on every kCheckEvery-th (the counter then
  /// starts again).
  bool due() {
    if (++stepsSinceCheck_ < kCheckEvery)
      return false;
    stepsSinceCheck_ = 0;
    return true;
  }

  /// Whether the spectrum `lambda` of df/dy, with the last step `h` and the
  /// time `rest` to the stop time, says Adams' step is held by a decaying
  /// mode for many of its time constants.
  static bool looksStiff(const Eigen::VectorXcd &lambda, double h, double rest);

private:
  /// How often Adams looks at df/dy's spectrum (for stiffness under
  /// `--integrator auto`, and for the stabilization's radius), and the
  /// largest model whose spectrum it computes.
  static constexpr long kCheckEvery = 25;
  static constexpr int kMaxUnknowns = 200;

  long stepsSinceCheck_ = 0;
};

} // namespace ldae::runtime
