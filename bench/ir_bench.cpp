// IR benchmark: builds an expression DAG of N nodes (a chain mixing sin, *
// and + in which every step reuses the two previous results, so the tree it
// unfolds to is exponentially large), then takes its total time derivative
// and a partial derivative. Prints one line of `key=value` figures; run by
// bench/run_ir.sh for N = 1e5 and 1e6 in separate processes.
#include "ir/Differentiate.h"
#include "ir/Query.h"

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sys/resource.h>

using namespace ldae::ir;

namespace {

/// CPU time of this thread: the machine is shared, so wall time would
/// measure the neighbours as much as the IR.
double cpuNow() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

long maxRssKiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

} // namespace

int main(int argc, char **argv) {
  size_t target = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 100000;
  ExprContext ctx;
  const unsigned numVars = 10;

  double t0 = cpuNow();
  // e[k+1] = e[k] * sin(e[k-1]) + x[k mod 10]
  ExprRef prev = ctx.var(0), cur = ctx.var(1);
  for (unsigned k = 0; ctx.size() < target; ++k) {
    ExprRef next = ctx.add(ctx.mul(cur, ctx.call(FuncKind::Sin, prev)),
                           ctx.var(k % numVars));
    prev = cur;
    cur = next;
  }
  double buildTime = cpuNow() - t0;
  size_t dagNodes = dagSize(cur);
  size_t built = ctx.size();

  Differentiator diff(ctx);
  double t1 = cpuNow();
  ExprRef dt = diff.timeDerivative(cur);
  double timeDerivTime = cpuNow() - t1;
  size_t afterTime = ctx.size();

  double t2 = cpuNow();
  ExprRef dx = diff.partial(cur, {3, 0});
  double partialTime = cpuNow() - t2;
  size_t afterPartial = ctx.size();

  std::printf("nodes=%zu dag=%zu build_s=%.4f ddt_s=%.4f ddt_nodes=%zu "
              "ddt_dag=%zu partial_s=%.4f partial_nodes=%zu partial_dag=%zu "
              "arena_MiB=%.1f maxrss_MiB=%.1f\n",
              built, dagNodes, buildTime, timeDerivTime, afterTime - built,
              dagSize(dt), partialTime, afterPartial - afterTime, dagSize(dx),
              ctx.memoryBytes() / 1048576.0, maxRssKiB() / 1024.0);
  return 0;
}
