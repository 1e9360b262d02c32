// SIGINT and SIGTERM during a run (docs/results.md, "When a run is
// interrupted"): while an InterruptGuard lives, either signal only asks
// the run to stop (SimOptions::interrupted); the run ends at its next step
// and its rows so far are written as a failed run's are. Outside a run the
// signals keep their default action: Ctrl-C during a long compilation
// still ends it at once.
#pragma once

namespace ldae::driver {

class InterruptGuard {
public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard &) = delete;
  InterruptGuard &operator=(const InterruptGuard &) = delete;

  /// The signal received since the guard was made (SIGINT, SIGTERM), or 0.
  static int received();
};

} // namespace ldae::driver
