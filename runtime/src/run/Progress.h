// A progress bar on stderr for long runs: shown only when stderr is a
// terminal and the run has taken more than a second, redrawn at most ten
// times a second, erased at the end.
#pragma once

#include <chrono>

namespace ldae::runtime {

class Progress {
public:
  Progress(bool enabled, double start, double stop);
  ~Progress() { finish(); }
  /// Reports that the integration reached time t.
  void update(double t);
  /// Erases the bar (idempotent).
  void finish();

private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  bool shown_ = false;
  double start_, stop_;
  Clock::time_point begin_, last_;
};

} // namespace ldae::runtime
