#!/bin/sh
# Runs the codegen benchmark (residual evaluations per second of the JIT,
# the emitted C and the interpreter against hand-written C; JIT compile time
# for 10^3, 10^4, 10^5 equations) and writes the figures into
# docs/benchmarks.md under "## Codegen".
# Usage: bench/run_codegen.sh [--doc] [build-dir]   (default: build; or set
# CODEGEN_BENCH to the benchmark binary)
set -eu
# --doc: write the figures into docs/benchmarks.md (never by default).
if [ "${1:-}" = "--doc" ]; then export LDAE_BENCH_DOC=1; shift; fi
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
bin=${CODEGEN_BENCH:-$build/bench/codegen_bench}
[ -x "$bin" ] || { echo "run_codegen.sh: $bin not built (ninja -C $build codegen_bench)" >&2; exit 2; }
body=$("$bin")
echo "$body"
LDAE_BENCH_DIR="$root/bench" python3 - "$root/docs/benchmarks.md" "$body" <<'PY'
import datetime, os, platform, re, sys
path, body = sys.argv[1], sys.argv[2]
section = (f"## Codegen\n\n`bench/codegen_bench.cpp`, run by `bench/run_codegen.sh` "
           f"({datetime.date.today()}, {platform.machine()}, load average "
           f"{open('/proc/loadavg').read().split()[0]} on {os.cpu_count()} cores: "
           f"a shared machine: evaluation rates are best of 3, compile times are CPU seconds of the compiling thread).\n\n{body}\n")
import os as _os, sys as _sys
_sys.path.insert(0, _os.environ["LDAE_BENCH_DIR"])
from benchdoc import write_section
write_section(path, "Codegen", section)
PY
