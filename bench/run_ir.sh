#!/bin/sh
# Runs the IR benchmark at 1e5 and 1e6 nodes, checks that differentiation
# time grows linearly (10x the nodes may take at most 12x the time) and
# writes the figures into docs/benchmarks.md under "## IR".
# Usage: bench/run_ir.sh [--doc] [build-dir]   (default: build)
set -eu
# --doc: write the figures into docs/benchmarks.md (never by default).
if [ "${1:-}" = "--doc" ]; then export LDAE_BENCH_DOC=1; shift; fi
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
bin=$build/bench/ir_bench
[ -x "$bin" ] || { echo "run_ir.sh: $bin not built (ninja -C $build ir_bench)" >&2; exit 2; }

# Seven runs per size, interleaved so both sizes see the same machine; the
# figures keep the fastest (the machine is shared with other jobs).
small=""
large=""
for i in 1 2 3 4 5 6 7; do
  small="$small$("$bin" 100000)
"
  large="$large$("$bin" 1000000)
"
done
echo "1e5:"; echo "$small"
echo "1e6:"; echo "$large"

LDAE_BENCH_DIR="$root/bench" python3 - "$root/docs/benchmarks.md" "$small" "$large" <<'PY'
import os, re, sys, platform, datetime
path, small, large = sys.argv[1], sys.argv[2], sys.argv[3]
def parse(lines):
    runs = [{k: float(v) for k, v in (kv.split("=") for kv in line.split())}
            for line in lines.strip().splitlines()]
    return {k: min(r[k] for r in runs) for k in runs[0]}
s, l = parse(small), parse(large)
rows = []
for name, key in [("build", "build_s"), ("d/dt", "ddt_s"), ("partial", "partial_s")]:
    rows.append((name, s[key], l[key], l[key] / max(s[key], 1e-9)))
node_ratio = l["nodes"] / s["nodes"]
ok = all(r[3] <= 12 * node_ratio / 10 for r in rows[1:])
section = f"""## IR

`bench/ir_bench.cpp`, run by `bench/run_ir.sh` ({datetime.date.today()}, {platform.machine()}).
A chain `e[k+1] = e[k] * sin(e[k-1]) + x[k mod 10]` built through the simplifying
builders until the context holds N nodes (each step shares the two previous
results, so the unfolded tree is exponential), then its total time
derivative and the partial derivative by `x[3]` (memoized, iterative).
Times are CPU seconds of the benchmark thread, the fastest of seven interleaved runs.
Load average during the run: {open('/proc/loadavg').read().split()[0]} on {os.cpu_count()} cores (a shared
machine: single runs vary by up to ±50%, the fastest of seven by about ±15%).

| | N = {int(s['nodes'])} | N = {int(l['nodes'])} | ratio |
|---|---:|---:|---:|
""" + "".join(f"| {n} time (s) | {a:.3f} | {b:.3f} | {r:.1f}x |\n" for n, a, b, r in rows) + \
f"""| nodes made by d/dt | {int(s['ddt_nodes'])} | {int(l['ddt_nodes'])} | {l['ddt_nodes']/s['ddt_nodes']:.1f}x |
| nodes made by partial | {int(s['partial_nodes'])} | {int(l['partial_nodes'])} | {l['partial_nodes']/s['partial_nodes']:.1f}x |
| context memory (MiB) | {s['arena_MiB']:.1f} | {l['arena_MiB']:.1f} | {l['arena_MiB']/s['arena_MiB']:.1f}x |
| max RSS (MiB) | {s['maxrss_MiB']:.1f} | {l['maxrss_MiB']:.1f} | {l['maxrss_MiB']/s['maxrss_MiB']:.1f}x |

Linearity ({node_ratio:.1f}x the nodes may take at most {12*node_ratio/10:.1f}x the time): **{"pass" if ok else "FAIL"}**.
"""
import os as _os, sys as _sys
_sys.path.insert(0, _os.environ["LDAE_BENCH_DIR"])
from benchdoc import write_section
write_section(path, "IR", section)
print(section)
sys.exit(0 if ok else 1)
PY
