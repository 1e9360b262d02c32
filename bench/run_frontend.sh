#!/bin/sh
# Runs the frontend benchmark (parse + flatten of a 100000-equation for-chain
# and of a 10000-instance RC ladder, and of both at 10x) and writes the
# table into docs/benchmarks.md under "## Frontend".
# Usage: bench/run_frontend.sh [--doc] [build-dir] [repetitions]   (default: build, 3)
set -eu
# --doc: write the figures into docs/benchmarks.md (never by default).
if [ "${1:-}" = "--doc" ]; then export LDAE_BENCH_DOC=1; shift; fi
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
reps=${2:-3}
bin=$build/bench/frontend_bench
[ -x "$bin" ] || { echo "run_frontend.sh: $bin not built (ninja -C $build frontend_bench)" >&2; exit 2; }
table=$("$bin" "$reps")
echo "$table"
load=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo "?")

LDAE_BENCH_DIR="$root/bench" python3 - "$root/docs/benchmarks.md" "$table" "$load" <<'PY'
import datetime, platform, re, sys
path, table, load = sys.argv[1], sys.argv[2], sys.argv[3]
section = f"""## Frontend

`bench/frontend_bench.cpp`, run by `bench/run_frontend.sh` ({datetime.date.today()}, {platform.machine()}).
Parse and flatten, in process, of generated models: a `for`-chain
`der(x[i]) = x[i - 1] - x[i]` over `Real x[N]`, and an RC ladder of
`Resistor r[N/2]` and `Capacitor c[N/2]` from `stdlib/Electrical.lsd`
connected in `for`-loops (N component instances, each with its pins,
extends, modifiers and connection sets). CPU time of the benchmark thread,
fastest of several runs; load average {load} on a shared 2-core machine.
Targets: under 1 s for 100000 equations and for 10000 instances; 10x the
model in at most 12x the time.

{table.strip()}
"""
import os as _os, sys as _sys
_sys.path.insert(0, _os.environ["LDAE_BENCH_DIR"])
from benchdoc import write_section
write_section(path, "Frontend", section)
PY
