#!/usr/bin/python3
"""The JIT's object cache (issue 16, "Compile once, run many"): the code
generation time of an RC ladder (examples/rc_ladder.lsd, N sections) with
an empty cache (LLVM optimizes and compiles the model, then stores the
object) against a run that finds the model in the cache (the object is
loaded: no optimization, no code generation), and the whole process.

For each N: --runs cold runs (each with a fresh cache directory) and
--runs cached runs (the directory of a cold run), the medians of the
"compile time" --stats prints (code generation, cache lookup included) and
of the process's wall time; the ratio cold / cached is the gain. Both
kinds run in this script on this machine, one after the other.
Usage: bench/run_cache.py --ldaec PATH [--sizes 100,400,1600] [--runs 3]
                          [--write]
  --write  puts the table into docs/benchmarks.md ("Object cache");
           without it the table is printed only.
Standard library only.
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DOC = os.path.join(ROOT, "docs", "benchmarks.md")
LADDER = os.path.join(ROOT, "examples", "rc_ladder.lsd")
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402


def run_once(ldaec, n, cache):
    """(compile seconds, wall seconds, 'hit'|'miss') of one run."""
    env = dict(os.environ, LDAEC_CACHE_DIR=cache)
    cmd = [ldaec, LADDER, "--simulate", "--jit", "on", "--stats",
           "--param", "N=%d" % n, "--stop", "1e-3", "-o", os.devnull]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit("ldaec failed (%d): %s" % (p.returncode, p.stderr))
    compile_s = float(re.search(r"^compile time: (\S+) s", p.stderr, re.M).group(1))
    use = re.search(r"^object cache: (\w+)", p.stderr, re.M)
    return compile_s, wall, use.group(1) if use else "off"


def measure(ldaec, n, runs, scratch):
    cold, cold_wall, hot, hot_wall = [], [], [], []
    for r in range(runs):
        cache = os.path.join(scratch, "n%d-%d" % (n, r))
        shutil.rmtree(cache, ignore_errors=True)
        c, w, use = run_once(ldaec, n, cache)
        assert use == "miss", use
        cold.append(c)
        cold_wall.append(w)
        c, w, use = run_once(ldaec, n, cache)
        assert use == "hit", use
        hot.append(c)
        hot_wall.append(w)
    size = sum(os.path.getsize(os.path.join(cache, f)) for f in os.listdir(cache))
    med = statistics.median
    return med(cold), med(hot), med(cold_wall), med(hot_wall), size


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ldaec", required=True)
    ap.add_argument("--sizes", default="100,400,1600")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--write", "--doc", action="store_true",
                    help="write the table into docs/benchmarks.md")
    a = ap.parse_args()
    if a.write:
        os.environ["LDAE_BENCH_DOC"] = "1"
    rows = []
    with tempfile.TemporaryDirectory(prefix="ldaec-cache-bench-") as scratch:
        for n in [int(s) for s in a.sizes.split(",")]:
            cold, hot, cold_wall, hot_wall, size = measure(a.ldaec, n, a.runs, scratch)
            rows.append("| %d | %.3f | %.3f | %.1fx | %.3f | %.3f | %.1fx | %d |"
                        % (n, cold, hot, cold / hot, cold_wall, hot_wall,
                           cold_wall / hot_wall, size // 1024))
            print(rows[-1], flush=True)
    section = """## Object cache

`bench/run_cache.py --ldaec build/compiler/driver/ldaec --runs %d` (the
RC ladder of `examples/rc_ladder.lsd` with N sections, `--jit on`, a run
of 1 ms): the medians of `--stats`' compile time (code generation) and of
the whole process, with an empty cache (LLVM optimizes and compiles, then
stores the object) and with the object in the cache (loaded: the module is
still emitted and hashed, no optimization or code generation). Both in
the same script on this machine (2 cores shared with other work).

| N | codegen cold (s) | codegen cached (s) | gain | process cold (s) | process cached (s) | gain | entry (KiB) |
|---|---|---|---|---|---|---|---|
%s
""" % (a.runs, "\n".join(rows))
    write_section(DOC, "Object cache", section)


if __name__ == "__main__":
    main()
