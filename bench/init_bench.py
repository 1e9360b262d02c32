#!/usr/bin/env python3
"""Initialization at scale (docs/runtime.md, "Sparse initialization").

Runs the real ldaec with `--simulate --stop 0 --stats` and reads its
`initialization time` (the time simulate() spends finding the initial
point; compilation not included) on
  - tests/models/heat2d.lsd, SUNDIALS' idaHeat2D form, at N = 101 (about
    10^4 unknowns once alias elimination drops the boundary): target < 1 s;
  - bench/init_oscillators.lsd, an index-1 chain with initial equations, at
    about 10^3, 10^4 and 10^5 unknowns: time per unknown roughly constant
    (the ratio to the smallest size's, measured in the same run, is
    printed; linear means about 1);
  - bench/init_tied.lsd, the same chain with the masses tied in pairs by
    initial equations: N/2 minimum-norm blocks (the sparse KKT step).
Each figure is the best of REPS runs. With --write the table goes into
docs/benchmarks.md under "## Initialization".

Usage: bench/init_bench.py [--build DIR] [--reps N] [--write]
"""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
from benchdoc import write_section  # noqa: E402


def stats(ldaec, model, n):
    """(unknowns, initialization time, the log's initialization line)."""
    proc = subprocess.run(
        [ldaec, "--no-progress", model, "--simulate", "--stop", "0",
         "--param", "N=%d" % n, "--stats", "-o", os.devnull],
        capture_output=True, text=True, timeout=3600)
    if proc.returncode != 0:
        sys.exit("ldaec failed on %s N=%d:\n%s" % (model, n, proc.stderr[-2000:]))
    unknowns = int(re.search(r"^unknowns\s+(\d+)", proc.stderr, re.M).group(1))
    t = float(re.search(r"^initialization time\s+([0-9.e+-]+)", proc.stderr,
                        re.M).group(1))
    path = re.search(r"^initialization: (.*)$", proc.stderr, re.M)
    return unknowns, t, path.group(1) if path else ""


def best(ldaec, model, n, reps):
    runs = [stats(ldaec, model, n) for _ in range(reps)]
    return runs[0][0], min(r[1] for r in runs), runs[0][2]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--write", action="store_true",
                    help="write the table into docs/benchmarks.md")
    a = ap.parse_args()
    ldaec = os.path.join(a.build, "compiler", "driver", "ldaec")
    heat = os.path.join(ROOT, "tests", "models", "heat2d.lsd")
    chain = os.path.join(ROOT, "bench", "init_oscillators.lsd")

    lines = []
    nh, th, how = best(ldaec, heat, 101, a.reps)
    lines.append("| heat2d (idaHeat2D form), N = 101 | %d | %.4f | %.2f | %s |"
                 % (nh, th, 1e6 * th / nh,
                    "yes" if th < 1 else "**no**"))
    rows = []
    tied = os.path.join(ROOT, "bench", "init_tied.lsd")
    for name, model in (("oscillator chain", chain), ("tied pairs", tied)):
        base = None
        for n in (500, 5000, 50000):
            u, t, how = best(ldaec, model, n, a.reps)
            per = t / u
            base = base or per
            rows.append("| %s, N = %d | %d | %.4f | %.2f | %.2f |"
                        % (name, n, u, t, 1e6 * per, per / base))
    section = "\n".join([
        "## Initialization",
        "",
        "`bench/init_bench.py` (ldaec `--simulate --stop 0 --stats`, the "
        "`initialization time` line: finding the consistent initial point, "
        "compilation not included; best of %d runs; shared 2-core machine). "
        "All these models have initial equations, so before the sparse path "
        "(docs/runtime.md) they took the dense one: O(n^3), 39 s for a "
        "900-unknown heat equation, refused above 10^4 unknowns." % a.reps,
        "",
        "| model | unknowns | init time (s) | µs per unknown | under 1 s |",
        "|---|---|---|---|---|",
        lines[0],
        "",
        "Index-1 chain with initial equations (`bench/init_oscillators.lsd`: "
        "x[i] = sin(0.01 i), der(x[i]) = 0), and the same chain with the "
        "masses tied in pairs (`bench/init_tied.lsd`: x[2i-1] + x[2i] = c_i, "
        "N/2 minimum-norm blocks); the last column is the time per unknown "
        "relative to the smallest size of the same model, 1 = linear:",
        "",
        "| model | unknowns | init time (s) | µs per unknown | per unknown vs smallest |",
        "|---|---|---|---|---|",
    ] + rows)
    print(section)
    if a.write:
        os.environ["LDAE_BENCH_DOC"] = "1"
        write_section(os.path.join(ROOT, "docs", "benchmarks.md"),
                      "Initialization", section)


if __name__ == "__main__":
    main()
