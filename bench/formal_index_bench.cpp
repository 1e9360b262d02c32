// Cost of the formal index (passes/FormalIndex.h) against model size, with
// the size limit lifted: an index-1 chain of N/2 stages,
//   der(x[i]) = -x[i] + z[i],  z[i] = 0.5 * x[i-1]  (z[1] = sin(time)),
// N unknowns, 2N jet coordinates in J_1. Its formal index is 1 at every
// size. Usage: formal_index_bench [N]...  (default 100 200 400 1000);
// prints `N,coordinates,wall_seconds,cpu_seconds,index` lines (CSV; the CPU
// time is the figure to compare on a loaded machine).
#include "frontend/Frontend.h"
#include "passes/FormalIndex.h"

#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

using namespace ldae;

namespace {

std::string chainModel(long unknowns) {
  return "model Chain\n"
         "  parameter Integer N = " + std::to_string(unknowns / 2) + ";\n"
         "  Real x[N](each start = 1);\n"
         "  Real z[N];\n"
         "equation\n"
         "  z[1] = sin(time);\n"
         "  for i in 2:N loop\n"
         "    z[i] = 0.5 * x[i - 1];\n"
         "  end for;\n"
         "  for i in 1:N loop\n"
         "    der(x[i]) = -x[i] + z[i];\n"
         "  end for;\n"
         "end Chain;\n";
}

} // namespace

int main(int argc, char **argv) {
  std::vector<long> sizes;
  for (int i = 1; i < argc; ++i)
    sizes.push_back(std::atol(argv[i]));
  if (sizes.empty())
    sizes = {100, 200, 400, 1000};
  std::printf("N,coordinates,wall_seconds,cpu_seconds,index\n");
  for (long n : sizes) {
    SourceManager sources;
    DiagnosticEngine diags(sources);
    frontend::FrontendOptions opts;
    auto model = frontend::compileSource("chain.lsd", chainModel(n), opts,
                                         sources, diags);
    if (!model) {
      diags.flush(std::cerr);
      return 1;
    }
    auto t0 = std::chrono::steady_clock::now();
    std::clock_t c0 = std::clock();
    passes::FormalIndexResult r =
        passes::formalIndex(*model, std::numeric_limits<size_t>::max());
    double secs = std::chrono::duration<double>(
                      std::chrono::steady_clock::now() - t0)
                      .count();
    double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    std::printf("%ld,%ld,%.3f,%.3f,%s\n", n, 2 * n, secs, cpu,
                r.index ? std::to_string(*r.index).c_str()
                        : ("null (" + r.reason + ")").c_str());
    std::fflush(stdout);
  }
  return 0;
}
