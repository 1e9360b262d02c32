// Frontend benchmark: parse + flatten of generated models, in process.
//   chain:     Real x[N] with a for-loop of N scalar equations
//   instances: an RC ladder of N/2 sections from the standard library
//              (N component instances, each with pins and equations)
// Each size runs at N and 10 N; the time is the fastest of `reps` runs
// (CPU time of this thread). Prints a Markdown table for docs/benchmarks.md.
#include "frontend/Frontend.h"

#include <algorithm>
#include <iostream>
#include <cstdio>
#include <ctime>
#include <string>

using namespace ldae;

namespace {

double threadSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

std::string chainModel(long n) {
  return "model Chain\n"
         "  parameter Integer N = " + std::to_string(n) + ";\n"
         "  Real x[N](each start = 1);\n"
         "equation\n"
         "  der(x[1]) = -x[1];\n"
         "  for i in 2:N loop\n"
         "    der(x[i]) = x[i - 1] - x[i];\n"
         "  end for;\n"
         "end Chain;\n";
}

std::string ladderModel(long instances) {
  return "model Ladder\n"
         "  import Electrical.*;\n"
         "  parameter Integer N = " + std::to_string(instances / 2) + ";\n"
         "  StepVoltage source(V = 1);\n"
         "  Resistor r[N](each R = 1);\n"
         "  Capacitor c[N](each C = 1e-3);\n"
         "  Ground ground;\n"
         "equation\n"
         "  connect(source.p, r[1].p);\n"
         "  for i in 1:N loop\n"
         "    connect(r[i].n, c[i].p);\n"
         "    connect(c[i].n, ground.p);\n"
         "  end for;\n"
         "  for i in 1:N - 1 loop\n"
         "    connect(r[i].n, r[i + 1].p);\n"
         "  end for;\n"
         "  connect(source.n, ground.p);\n"
         "end Ladder;\n";
}

struct Result {
  double seconds = 1e300;
  size_t variables = 0, equations = 0;
};

Result run(const std::string &text, int reps) {
  Result r;
  for (int k = 0; k < reps; ++k) {
    SourceManager sources;
    DiagnosticEngine diags(sources);
    frontend::FrontendOptions opts;
    opts.libraryPaths = {LDAE_BENCH_STDLIB};
    double t0 = threadSeconds();
    auto model = frontend::compileSource("bench.lsd", text, opts, sources, diags);
    double t = threadSeconds() - t0;
    if (!model) {
      diags.flush(std::cerr);
      std::fprintf(stderr, "frontend_bench: the generated model failed\n");
      std::exit(1);
    }
    r.seconds = std::min(r.seconds, t);
    r.variables = model->variables.size();
    r.equations = model->equations.size();
  }
  return r;
}

} // namespace

int main(int argc, char **argv) {
  int reps = argc > 1 ? std::atoi(argv[1]) : 3;
  Result c1 = run(chainModel(100000), reps);
  Result c10 = run(chainModel(1000000), std::max(1, reps / 2));
  Result l1 = run(ladderModel(10000), reps);
  Result l10 = run(ladderModel(100000), std::max(1, reps / 2));
  std::printf("| model | size | variables | equations | time (s) |\n");
  std::printf("|---|---:|---:|---:|---:|\n");
  auto row = [](const char *name, const char *size, const Result &r) {
    std::printf("| %s | %s | %zu | %zu | %.3f |\n", name, size, r.variables,
                r.equations, r.seconds);
  };
  row("for-chain", "N = 100000", c1);
  row("for-chain", "N = 1000000", c10);
  row("RC ladder", "10000 instances", l1);
  row("RC ladder", "100000 instances", l10);
  std::printf("\nScaling 10x: chain %.1fx, ladder %.1fx (target <= 12x).\n",
              c10.seconds / c1.seconds, l10.seconds / l1.seconds);
  bool ok = c1.seconds < 1 && l1.seconds < 1 &&
            c10.seconds <= 12 * c1.seconds && l10.seconds <= 12 * l1.seconds;
  std::printf("Targets (< 1 s at the base size, <= 12x for 10x): %s\n",
              ok ? "met" : "NOT met");
  return 0;
}
