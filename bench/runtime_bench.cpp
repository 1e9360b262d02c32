// Runtime benchmark: Robertson (the hand-written ldae_model of the unit
// tests) through ldae::runtime::simulate with the settings of SUNDIALS'
// idaRoberts_dns.c (rtol 1e-4, atol 1e-8 / 1e-6 / 1e-6, outputs at
// 0.4 * 10^k up to 4e10, two root functions, every unknown error-tested).
// Prints one line: steps and microseconds per run (best of several batches).
// bench/run_runtime.sh compares it with the example itself.
#include "../tests/unit/runtime/HandModels.h"
#include "ldae/Simulation.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

using namespace ldae::runtime;

int main(int argc, char **argv) {
  int reps = argc > 1 ? std::atoi(argv[1]) : 200;
  ldae_model m = handmodels::robertson();
  SimOptions o;
  o.start = 0;
  o.stop = 4e10;
  o.rtol = 1e-4;
  o.atol = 1e-8;
  o.algebraicErrorTest = true;
  o.progress = false;
  for (int k = 0; k < 12; ++k)
    o.times.push_back(0.4 * std::pow(10.0, k));
  long steps = 0;
  double best = 1e300;
  for (int batch = 0; batch < 5; ++batch) {
    auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < reps; ++i) {
      auto r = simulate(m, o);
      if (!r || r->status != 0) {
        std::fprintf(stderr, "simulation failed\n");
        return 1;
      }
      steps = r->stats.steps;
    }
    double us = std::chrono::duration<double, std::micro>(
                    std::chrono::steady_clock::now() - t0)
                    .count() /
                reps;
    best = std::min(best, us);
  }
  std::printf("ldae steps=%ld us_per_run=%.1f\n", steps, best);
  return 0;
}
