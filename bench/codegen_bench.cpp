// Code generation benchmark: residual evaluations per second of the JIT code,
// the interpreter and the emitted C against hand-written C of the same
// equations (all compiled with cc -O2 and called through the same function
// pointer type), for the pendulum and a 10,000-equation chain; and JIT
// compile time for chains of 10^3, 10^4, 10^5 equations. Prints a markdown
// section (bench/run_codegen.sh puts it into docs/benchmarks.md).
//
// Usage: codegen_bench [--quick]
#include "codegen/CodePlan.h"
#include "codegen/Codegen.h"
#include "codegen/LlvmEmitter.h"
#include "codegen/PlanLowering.h"
#include "SampleSystems.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dlfcn.h>
#include <filesystem>
#include <fstream>
#include <string>
#include <time.h>
#include <unistd.h>
#include <vector>

using namespace ldae;
using namespace ldae::codegen;
using Clock = std::chrono::steady_clock;

namespace {

double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

/// CPU seconds of this thread (LLJIT compiles on the calling thread), the
/// fair measure on a shared machine.
double threadCpu() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

const char *kHandWritten = R"C(
#include <math.h>
int pendulum_hand(double t, const double *restrict y, const double *restrict yp,
                  const double *restrict p, double *restrict r) {
  const double g = p[0], L = p[1];
  const double x = y[0], yy = y[1], vx = y[2], vy = y[3], lam = y[4],
               dy = y[5], dvy = y[6];
  r[0] = yp[0] - vx;
  r[1] = dy - vy;
  r[2] = yp[2] + lam * x;
  r[3] = dvy + lam * yy + g;
  r[4] = x * x + yy * yy - L * L;
  r[5] = x * vx + yy * vy;
  r[6] = vx * vx + vy * vy + x * yp[2] + yy * dvy;
  return 0;
}
int chain_hand(double t, const double *restrict y, const double *restrict yp,
               const double *restrict p, double *restrict r) {
  const double k = p[0], a = p[1];
  const int n = 10000;
  for (int i = 0; i < n; ++i) {
    double lap = -2 * y[i] + (i > 0 ? y[i - 1] : 0) + (i + 1 < n ? y[i + 1] : 0);
    r[i] = yp[i] - (k * lap - a * y[i] * y[i] * y[i]);
  }
  r[0] -= sin(t);
  return 0;
}
)C";

/// Compiles C source with cc -O2 into a shared object and loads it.
void *compileShared(const std::string &source, const std::string &stem) {
  std::string dir = (std::filesystem::temp_directory_path() /
                     ("ldae_bench_" + std::to_string(getpid())))
                        .string();
  std::filesystem::create_directories(dir);
  std::string c = dir + "/" + stem + ".c", so = dir + "/" + stem + ".so";
  std::ofstream(c) << source;
  std::string cmd = "cc -std=c99 -O2 -shared -fPIC -o " + so + " " + c + " -lm";
  if (std::system(cmd.c_str()) != 0) {
    std::fprintf(stderr, "cc failed for %s\n", stem.c_str());
    std::exit(1);
  }
  void *h = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    std::fprintf(stderr, "%s\n", dlerror());
    std::exit(1);
  }
  return h;
}

/// Residual calls per second of `f` at a fixed point (best of 3 runs).
double callsPerSecond(ldae_residual_fn f, int n, const std::vector<double> &p,
                      double minSeconds) {
  std::vector<double> y(n), yp(n), r(n);
  for (int i = 0; i < n; ++i) {
    y[i] = 0.3 + 0.001 * i;
    yp[i] = 0.1 - 0.002 * i;
  }
  double best = 0;
  for (int rep = 0; rep < 3; ++rep) {
    long calls = 0;
    auto start = Clock::now();
    double elapsed = 0;
    while (elapsed < minSeconds) {
      for (int k = 0; k < 16; ++k)
        f(0.5, y.data(), yp.data(), p.data(), r.data());
      calls += 16;
      elapsed = seconds(start, Clock::now());
    }
    best = std::max(best, calls / elapsed);
  }
  return best;
}

struct SpeedRow {
  std::string model;
  double hand, jit, c, interp;
};

SpeedRow measureSpeed(const std::string &name, const samples::SampleSystem &s,
                      ldae_residual_fn hand, double minSeconds) {
  auto jit = compile(s.sys, {});
  CodegenOptions io;
  io.jit = false;
  auto interp = compile(s.sys, io);
  auto text = emitC(s.sys, false);
  if (!jit || !interp || !text) {
    std::fprintf(stderr, "compile failed\n");
    std::exit(1);
  }
  void *h = compileShared(*text, name);
  auto get = reinterpret_cast<const ldae_model *(*)()>(dlsym(h, "ldae_get_model"));
  const ldae_model &m = (*jit)->model();
  std::vector<double> p(m.param_values, m.param_values + m.n_params);
  SpeedRow row{name, 0, 0, 0, 0};
  row.hand = callsPerSecond(hand, m.n, p, minSeconds);
  row.jit = callsPerSecond(m.state_sets[0].residual, m.n, p, minSeconds);
  row.c = callsPerSecond(get()->state_sets[0].residual, m.n, p, minSeconds);
  row.interp = callsPerSecond((*interp)->model().state_sets[0].residual, m.n,
                              p, minSeconds);
  return row;
}

struct CompileRow {
  unsigned n;
  double plan, jit, wall; // plan and jit in CPU seconds
  size_t nodes;
};

CompileRow measureCompile(unsigned n) {
  auto s = samples::chain(n);
  auto w0 = Clock::now();
  double t0 = threadCpu();
  auto plan = lowerToPlan(s.sys);
  double t1 = threadCpu();
  auto code = jitCompile(*plan);
  double t2 = threadCpu();
  double wall = seconds(w0, Clock::now());
  if (!plan || !code) {
    std::fprintf(stderr, "compile failed\n");
    std::exit(1);
  }
  size_t nodes = 0;
  for (const PlanFunction &f : plan->functions) {
    nodes += f.nodes.size();
    for (const PlanLoop &l : f.loops)
      nodes += l.body.nodes.size();
  }
  return {n, t1 - t0, t2 - t1, wall, nodes};
}

} // namespace

int main(int argc, char **argv) {
  bool quick = argc > 1 && !std::strcmp(argv[1], "--quick");
  double minSeconds = quick ? 0.05 : 0.3;

  void *hand = compileShared(kHandWritten, "hand");
  auto pendHand = reinterpret_cast<ldae_residual_fn>(dlsym(hand, "pendulum_hand"));
  auto chainHand = reinterpret_cast<ldae_residual_fn>(dlsym(hand, "chain_hand"));

  std::vector<SpeedRow> speed = {
      measureSpeed("pendulum", samples::pendulum(), pendHand, minSeconds),
      measureSpeed("chain10000", samples::chain(10000), chainHand, minSeconds)};

  std::vector<CompileRow> compileRows;
  for (unsigned n : {1000u, 10000u, 100000u})
    if (!quick || n <= 10000)
      compileRows.push_back(measureCompile(n));

  std::printf("Residual evaluations per second (best of 3; hand-written C, "
              "emitted C and the\nhand-written reference all built with "
              "`cc -O2`, called through the ABI pointer):\n\n");
  std::printf("| model | hand-written C | JIT | JIT / hand | emitted C | "
              "interpreter |\n|---|---|---|---|---|---|\n");
  for (const SpeedRow &r : speed)
    std::printf("| %s | %.3g | %.3g | %.2fx | %.3g | %.3g |\n", r.model.c_str(),
                r.hand, r.jit, r.jit / r.hand, r.c, r.interp);
  std::printf("\nJIT compile time of the chain (all functions of the model: "
              "residual, sparse\nJacobian, init, roots, outputs, drift; "
              "lowering includes symbolic differentiation):\n\n");
  std::printf("| equations | plan nodes | lowering [CPU s] | LLVM opt + codegen "
              "[CPU s] | total [CPU s] | growth per 10x | wall [s] |\n"
              "|---|---|---|---|---|---|---|\n");
  for (size_t i = 0; i < compileRows.size(); ++i) {
    const CompileRow &r = compileRows[i];
    double total = r.plan + r.jit;
    std::string growth = "";
    if (i > 0) {
      double prev = compileRows[i - 1].plan + compileRows[i - 1].jit;
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.1fx", total / prev);
      growth = buf;
    }
    std::printf("| %u | %zu | %.3f | %.3f | %.3f | %s | %.2f |\n", r.n,
                r.nodes, r.plan, r.jit, total, growth.c_str(), r.wall);
  }
  // Verdict on the targets of the codegen issue.
  std::printf("\nTargets: JIT >= 0.9x hand-written:");
  for (const SpeedRow &r : speed)
    std::printf(" %s %s;", r.model.c_str(), r.jit >= 0.9 * r.hand ? "pass" : "FAIL");
  bool linear = true;
  for (size_t i = 1; i < compileRows.size(); ++i)
    linear = linear && compileRows[i].plan + compileRows[i].jit <=
                           12 * (compileRows[i - 1].plan + compileRows[i - 1].jit);
  std::printf(" compile time <= 12x per 10x equations: %s;", linear ? "pass" : "FAIL");
  if (compileRows.size() == 3)
    std::printf(" 10^5 equations under 5 s: %s.",
                compileRows[2].plan + compileRows[2].jit < 5 ? "pass" : "FAIL");
  std::printf("\n");
  return 0;
}
