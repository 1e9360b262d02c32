#!/bin/sh
# Result writing: the CSV writer against the one-string-per-value writer it
# replaced, on the same rows in the same run (bench/results_bench.cpp).
# Prints the table; with --doc also writes it under `## Results` in
# docs/benchmarks.md.
# Usage: bench/run_results.sh [--doc] [build-dir]   (default: build)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
doc=no
if [ "${1:-}" = "--doc" ]; then doc=yes; shift; fi
build=${1:-$root/build}
ninja -C "$build" results_bench >/dev/null
rows=$("$build/bench/results_bench" "${REPS:-3}")
section=$(cat <<EOT
## Results

\`bench/run_results.sh\` ($(date +%Y-%m-%d), $(uname -m), load average $(cut -d' ' -f1 /proc/loadavg)): writing a CSV of 2 million smooth values of mixed magnitude to /dev/null, best of ${REPS:-3}. Reference: one \`fmt::format("{:.17g}")\` string per value (the writer before issue 13's change); ours: \`std::to_chars\` shortest round-trip text straight into a 1 MiB buffer (runtime/src/results/ResultWriter.cpp).

| rows x columns | reference MB | ours MB | reference MB/s | ours MB/s | speedup | smaller |
|---|---:|---:|---:|---:|---:|---:|
$rows
EOT
)
printf '%s\n' "$section"
if [ "$doc" = yes ]; then
  SECTION="$section" LDAE_BENCH_DOC=1 LDAE_BENCH_DIR="$root/bench" /usr/bin/python3 - "$root/docs/benchmarks.md" <<'PY'
import os, sys
sys.path.insert(0, os.environ["LDAE_BENCH_DIR"])
from benchdoc import write_section
write_section(sys.argv[1], "Results", os.environ["SECTION"])
PY
fi
