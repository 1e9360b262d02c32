// Benchmark of the analysis stage (alias elimination, matching, Pantelides,
// dummy derivatives, BLT, initialization) on two model families built with
// the IR API:
//   chain N : der(x[i]) = -x[i] + z[i], z[i] = 0.5*x[i-1] (z[1] = sin(time)),
//             2N equations, index 1;
//   bodies N: N point masses joined by rods in a chain hanging from the
//             origin, 5N equations, index 3 (N rod constraints).
// Usage: analysis_bench [family N]...; prints `family,N,equations,seconds,
// index,states` lines (CSV) for bench/run_analysis.sh.
#include "ir/Model.h"
#include "passes/Pipeline.h"
#include "support/Diagnostics.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

using namespace ldae;

namespace {

ir::ExprRef addVar(ir::Model &m, const std::string &name, double start) {
  ir::Variable v;
  v.name = name;
  v.start = start;
  v.hasStart = start != 0;
  return m.ctx().var(m.addVariable(v));
}

void addEq(ir::Model &m, ir::ExprRef lhs, ir::ExprRef rhs) {
  ir::Equation e;
  e.residual = m.ctx().sub(lhs, rhs);
  m.equations.push_back(e);
}

void buildChain(ir::Model &m, int n) {
  auto &c = m.ctx();
  m.name = "Chain";
  ir::ExprRef prev = nullptr;
  for (int i = 1; i <= n; ++i) {
    std::string idx = "[" + std::to_string(i) + "]";
    ir::ExprRef x = addVar(m, "x" + idx, 1), z = addVar(m, "z" + idx, 0);
    addEq(m, c.var(x->var(), 1), c.add(c.neg(x), z));
    addEq(m, z,
          prev ? c.mul(c.constant(0.5), prev)
               : c.call(ir::FuncKind::Sin, c.time()));
    prev = x;
  }
}

void buildBodies(ir::Model &m, int n) {
  auto &c = m.ctx();
  m.name = "Bodies";
  ir::Parameter pl;
  pl.name = "L";
  pl.value = 1;
  ir::ExprRef L = c.param(m.addParameter(pl));
  ir::Parameter pg;
  pg.name = "g";
  pg.value = 9.81;
  ir::ExprRef g = c.param(m.addParameter(pg));
  std::vector<ir::ExprRef> x, y, vx, vy, lam;
  for (int i = 1; i <= n; ++i) {
    std::string idx = "[" + std::to_string(i) + "]";
    x.push_back(addVar(m, "b" + idx + ".x", i));
    y.push_back(addVar(m, "b" + idx + ".y", 0));
    vx.push_back(addVar(m, "b" + idx + ".vx", 0));
    vy.push_back(addVar(m, "b" + idx + ".vy", 0));
    lam.push_back(addVar(m, "rod" + idx + ".f", 0));
  }
  auto dx = [&](int i) { // x[i] - x[i-1], body 0 at the origin
    return i == 0 ? x[0] : c.sub(x[i], x[i - 1]);
  };
  auto dy = [&](int i) { return i == 0 ? y[0] : c.sub(y[i], y[i - 1]); };
  for (int i = 0; i < n; ++i) {
    addEq(m, c.var(x[i]->var(), 1), vx[i]);
    addEq(m, c.var(y[i]->var(), 1), vy[i]);
    ir::ExprRef fx = c.neg(c.mul(lam[i], dx(i)));
    ir::ExprRef fy = c.neg(c.mul(lam[i], dy(i)));
    if (i + 1 < n) {
      fx = c.add(fx, c.mul(lam[i + 1], dx(i + 1)));
      fy = c.add(fy, c.mul(lam[i + 1], dy(i + 1)));
    }
    addEq(m, c.var(vx[i]->var(), 1), fx);
    addEq(m, c.var(vy[i]->var(), 1), c.sub(fy, g));
    addEq(m,
          c.add(c.pow(dx(i), c.constant(2)), c.pow(dy(i), c.constant(2))),
          c.pow(L, c.constant(2)));
  }
}

} // namespace

int main(int argc, char **argv) {
  if (argc < 3 || argc % 2 == 0) {
    std::fprintf(stderr, "usage: analysis_bench chain|bodies N [...]\n");
    return 2;
  }
  std::printf("family,n,equations,seconds,index,states\n");
  for (int a = 1; a + 1 < argc; a += 2) {
    std::string family = argv[a];
    int n = std::atoi(argv[a + 1]);
    ir::Model m;
    if (family == "chain")
      buildChain(m, n);
    else
      buildBodies(m, n);
    SourceManager sm;
    DiagnosticEngine diags(sm);
    passes::PipelineOptions opts;
    if (std::getenv("LDAE_TIME_PASSES")) {
      opts.timePasses = true;
      opts.log = &std::cerr;
    }
    passes::AnalysisResult result;
    auto t0 = std::chrono::steady_clock::now();
    bool ok = passes::runPipeline(m, opts, diags, result);
    double secs = std::chrono::duration<double>(
                      std::chrono::steady_clock::now() - t0)
                      .count();
    if (!ok) {
      for (const Diagnostic &d : diags.diagnostics())
        std::fprintf(stderr, "%s\n", d.message.c_str());
      return 1;
    }
    std::printf("%s,%d,%zu,%.4f,%d,%zu\n", family.c_str(), n,
                m.equations.size(), secs, result.structuralIndex.value_or(-1),
                result.states.size());
    std::fflush(stdout);
  }
  return 0;
}
