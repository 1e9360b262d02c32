// The progress bar (see Progress.h).
#include "run/Progress.h"

#include <cstdio>
#include <unistd.h>

namespace ldae::runtime {

Progress::Progress(bool enabled, double start, double stop)
    : enabled_(enabled && isatty(STDERR_FILENO)), start_(start), stop_(stop),
      begin_(Clock::now()), last_(begin_) {}

void Progress::update(double t) {
  if (!enabled_)
    return;
  auto now = Clock::now();
  if (now - begin_ < std::chrono::seconds(1) ||
      now - last_ < std::chrono::milliseconds(100))
    return;
  last_ = now;
  double f = stop_ > start_ ? (t - start_) / (stop_ - start_) : 1.0;
  f = f < 0 ? 0 : (f > 1 ? 1 : f);
  const int width = 40;
  int filled = int(f * width);
  char bar[width + 1];
  for (int i = 0; i < width; ++i)
    bar[i] = i < filled ? '#' : ' ';
  bar[width] = 0;
  std::fprintf(stderr, "\r[%s] %3d%%  t = %-12.6g", bar, int(f * 100), t);
  std::fflush(stderr);
  shown_ = true;
}

void Progress::finish() {
  if (!shown_)
    return;
  std::fprintf(stderr, "\r%*s\r", 70, "");
  std::fflush(stderr);
  shown_ = false;
}

} // namespace ldae::runtime
