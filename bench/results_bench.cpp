// Result writing speed: ldae's CSV writer (runtime/src/results/ResultWriter.cpp)
// against the reference it replaced, one fmt::format("{:.17g}") string per
// value, on the same rows, both written to /dev/null in the same run.
// Prints one markdown table row per size (see bench/run_results.sh).
#include "ldae/ResultWriter.h"
#include "ldae/Simulation.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fmt/format.h>
#include <fstream>
#include <sstream>
#include <string>

using namespace ldae::runtime;

namespace {

double seconds(auto f) {
  auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
      .count();
}

void referenceCsv(const SimResult &r, std::ostream &out) {
  std::string line;
  for (const auto &row : r.rows) {
    line.clear();
    for (size_t c = 0; c < row.size(); ++c)
      line += (c ? "," : "") + fmt::format("{:.17g}", row[c]);
    out << line << '\n';
  }
  out.flush();
}

} // namespace

int main(int argc, char **argv) {
  int reps = argc > 1 ? std::atoi(argv[1]) : 3;
  for (int cols : {10, 1000}) {
    // Trajectory-like values: smooth, of mixed magnitudes.
    SimResult r;
    r.columns.push_back("time");
    for (int c = 1; c < cols; ++c)
      r.columns.push_back("x" + std::to_string(c));
    int rows = 2000000 / cols;
    for (int i = 0; i < rows; ++i) {
      std::vector<double> row{i * 1e-3};
      for (int c = 1; c < cols; ++c)
        row.push_back(std::sin(i * 1e-3 * c) * std::pow(10.0, c % 7 - 3));
      r.rows.push_back(std::move(row));
    }
    std::ostringstream ours, ref;
    writeCsv(r, ours);
    referenceCsv(r, ref);
    double oursBytes = ours.str().size(), refBytes = ref.str().size();
    double tOurs = 1e30, tRef = 1e30;
    for (int k = 0; k < reps; ++k) {
      std::ofstream a("/dev/null"), b("/dev/null");
      tOurs = std::min(tOurs, seconds([&] { writeCsv(r, a); }));
      tRef = std::min(tRef, seconds([&] { referenceCsv(r, b); }));
    }
    std::printf("| %d x %d | %.1f | %.1f | %.0f | %.0f | %.2fx | %.0f%% |\n",
                rows, cols, refBytes / 1e6, oursBytes / 1e6,
                refBytes / tRef / 1e6, oursBytes / tOurs / 1e6, tRef / tOurs,
                100.0 * (1 - oursBytes / refBytes));
  }
  return 0;
}
