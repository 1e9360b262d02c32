#!/bin/sh
# Runtime benchmark: Robertson through ldae's runtime (bench/runtime_bench.cpp)
# vs SUNDIALS' own idaRoberts_dns.c, compiled here with -O2 from the
# installed examples (copied to a temporary directory, never committed).
# Same tolerances; compares step counts (target: within 10%) and time per
# run (target: ours <= 1.2x). Writes the figures under `## Runtime` in
# docs/benchmarks.md.
# Usage: bench/run_runtime.sh [--doc] [build-dir]   (default: build)
set -eu
# --doc: write the figures into docs/benchmarks.md (never by default).
if [ "${1:-}" = "--doc" ]; then export LDAE_BENCH_DOC=1; shift; fi
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
reps=${REPS:-300}
example=/usr/share/doc/libsundials-dev/examples/ida/serial/idaRoberts_dns.c
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The -O2 SUNDIALS ldaec links (docs/sundials.md), not Debian's -O0 one.
prefix=${LDAEC_SUNDIALS_PREFIX:-/opt/ldaec/sundials-6.4.1}
libs="-I$prefix/include -L$prefix/lib -lsundials_ida -lsundials_nvecserial -lsundials_sunlinsoldense -lsundials_sunmatrixdense"

# Ours: the benchmark as the build makes it (against the same SUNDIALS).
ninja -C "$build" runtime_bench >/dev/null 2>&1
ours=$("$build/bench/runtime_bench" "$reps")

# Theirs: the example's main renamed and called in a timed loop, its
# printing sent to /dev/null.
cp "$example" "$tmp/roberts.c"
cat > "$tmp/harness.c" <<'HARNESS'
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
int example_main(void);
static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
int main(int argc, char **argv) {
  int reps = argc > 1 ? atoi(argv[1]) : 200;
  double best = 1e300;
  fflush(stdout);
  if (!freopen("/dev/null", "w", stdout)) return 1;
  for (int b = 0; b < 5; ++b) {
    double t0 = now();
    for (int i = 0; i < reps; ++i) example_main();
    double us = (now() - t0) * 1e6 / reps;
    if (us < best) best = us;
  }
  fprintf(stderr, "sundials us_per_run=%.1f\n", best);
  return 0;
}
HARNESS
cc -O2 -Dmain=example_main -c "$tmp/roberts.c" -o "$tmp/roberts.o"
cc -O2 "$tmp/harness.c" "$tmp/roberts.o" $libs -lm -o "$tmp/theirs"
cc -O2 "$tmp/roberts.c" $libs -lm -o "$tmp/example"
their_steps=$("$tmp/example" | awk -F= '/^Steps/ {gsub(/ /, "", $2); print $2}')
theirs=$("$tmp/theirs" "$reps" 2>&1 >/dev/null)

our_steps=$(echo "$ours" | sed 's/.*steps=\([0-9]*\).*/\1/')
our_us=$(echo "$ours" | sed 's/.*us_per_run=\([0-9.]*\).*/\1/')
their_us=$(echo "$theirs" | sed 's/.*us_per_run=\([0-9.]*\).*/\1/')
ratio=$(awk -v a="$our_us" -v b="$their_us" 'BEGIN { printf "%.2f", a / b }')
stepdiff=$(awk -v a="$our_steps" -v b="$their_steps" 'BEGIN { printf "%.1f", 100 * (a - b) / b }')
echo "ours: $our_steps steps, $our_us us/run; SUNDIALS example: $their_steps steps, $their_us us/run; ratio $ratio; steps $stepdiff%"

section=$(cat <<EOT
## Runtime

Robertson kinetics (\`idaRoberts_dns.c\` settings: rtol 1e-4, atol 1e-8/1e-6/1e-6,
outputs at 0.4·10^k up to 4e10, two root functions), hand-written \`ldae_model\`
through \`ldae::runtime::simulate\` vs SUNDIALS' own example compiled with -O2
(\`bench/run_runtime.sh\`, best of 5 batches of $reps runs, $(date -u +%Y-%m-%d)).

| | steps | time per run | |
|---|---:|---:|---|
| ldae runtime | $our_steps | $our_us µs | |
| idaRoberts_dns.c | $their_steps | $their_us µs | |
| ratio | $stepdiff % | ${ratio}x | targets: steps within 10 %, time ≤ 1.2x |

Both step freely and interpolate the output times (the example with
IDA_NORMAL, ours one step at a time), both against the same -O2 SUNDIALS;
ours includes consistent initialization and result recording;
the example's time includes its own printing (sent to /dev/null) and its
final statistics.
EOT
)
doc="$root/docs/benchmarks.md"
[ -f "$doc" ] || printf '# Benchmarks\n' > "$doc"
SECTION="$section" LDAE_BENCH_DIR="$root/bench" /usr/bin/python3 - "$doc" <<'PY'
import os, re, sys
path = sys.argv[1]
sys.path.insert(0, os.environ["LDAE_BENCH_DIR"])
from benchdoc import write_section
write_section(path, "Runtime", os.environ["SECTION"])
PY
