#!/bin/sh
# End-to-end benchmarks of the ldaec binary: Robertson vs SUNDIALS' example,
# pendulum parse-to-CSV time, RC-ladder compile time vs N (chart
# docs/e2e_compile_time.png), then the work-precision charts
# (bench/work_precision.py). Figures go under `## End to end` in
# docs/benchmarks.md.
# Usage: bench/run_e2e.sh [--doc] [build-dir]   (default: build)
set -eu
# --doc: write the figures and charts into docs/ (never by default; the
# charts then go to a temporary directory).
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$tmp
if [ "${1:-}" = "--doc" ]; then export LDAE_BENCH_DOC=1; shift; out="$(cd "$(dirname "$0")/.." && pwd)/docs"; fi
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
ninja -C "$build" ldaec >/dev/null
ldaec="$build/compiler/driver/ldaec"
/usr/bin/python3 "$root/bench/e2e_bench.py" "$ldaec"
if [ "${WORK_PRECISION:-1}" = 1 ]; then
  /usr/bin/python3 "$root/bench/work_precision.py" --ldaec "$ldaec" \
    --out "$out" --methods dd,raw  # the driver runs sga, ode as dd
fi
