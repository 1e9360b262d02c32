#!/usr/bin/python3
"""Wong sequences of a 2,000-state linear model (issue 14: under 5 s).

Writes an RC ladder in flat equations: N capacitors in a chain fed by a
sine source through resistors, the resistor currents as algebraic
unknowns, and at its end two capacitors in parallel (a capacitor loop:
index 2). States: N - 1 + 2 - 1 = N. The pencil has about 2N + 4 columns.
ldaec --analyze --time-passes reports the "linear" pass's time; the result
is checked (dim V = N, index 2, regular), and the time is given as a ratio
to a reference run in the same script: one dense SVD (singular values
only) of an N x N matrix with numpy, what a single step of the dense Wong
sequences would cost at the model's state count.

Usage: /usr/bin/python3 bench/run_wong.py [--ldaec build/compiler/driver/ldaec]
       [--states 2000] [--repeat 3] [--doc]
--doc writes the figures into docs/benchmarks.md (section "Wong sequences").
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import benchdoc  # noqa: E402


def ladder(n):
    """The lsd text of the ladder with n states."""
    caps = n - 1  # chain capacitors; the loop adds two with one state
    lines = ["model WongLadder", "  parameter Real R = 10;",
             "  parameter Real C = 1e-6;"]
    for k in range(1, caps + 1):
        lines.append("  Real v%d(start = 0);" % k)
        lines.append("  Real i%d;" % k)
    lines += ["  Real va(start = 0);", "  Real vb(start = 0);",
              "  Real ia;", "  Real ib;", "  Real iend;", "equation"]
    for k in range(1, caps + 1):
        prev = "sin(100 * time)" if k == 1 else "v%d" % (k - 1)
        out = "i%d" % (k + 1) if k < caps else "iend"
        lines.append("  R * i%d = %s - v%d;" % (k, prev, k))
        lines.append("  C * der(v%d) = i%d - %s;" % (k, k, out))
    lines += ["  R * iend = v%d - va;" % caps,
              "  C * der(va) = ia;", "  2 * C * der(vb) = ib;",
              "  va = vb;", "  ia + ib = iend;", "end WongLadder;"]
    return "\n".join(lines) + "\n"


def linear_seconds(ldaec, path):
    out = subprocess.run([ldaec, path, "--analyze", "--json", "--time-passes"],
                         capture_output=True, text=True, timeout=3600)
    m = re.search(r"^\s*([0-9.]+) s\s+linear$", out.stderr, re.M)
    if not m:
        raise RuntimeError("no 'linear' pass time:\n" + out.stderr[-2000:])
    return float(m.group(1)), json.loads(out.stdout)["linear"]


def reference_seconds(n):
    a = np.random.default_rng(2).random((n, n))
    t0 = time.perf_counter()
    np.linalg.svd(a, compute_uv=False)
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ldaec", default=os.path.join(
        HERE, "..", "build", "compiler", "driver", "ldaec"))
    ap.add_argument("--states", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--doc", action="store_true")
    args = ap.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "wong_ladder.lsd")
        with open(path, "w") as f:
            f.write(ladder(args.states))
        runs = [linear_seconds(args.ldaec, path) for _ in range(args.repeat)]
    report = runs[0][1]
    n = args.states
    ok = (report is not None and report["regular"] and report["index"] == 2
          and report["dim_V"] == n)
    if not ok:
        sys.exit("wrong Wong result for the ladder: %r" % (report,))
    wong = statistics.median(r[0] for r in runs)
    ref = reference_seconds(n)
    cols = report["dim_V"] + report["dim_W"]
    rows = [
        "| model | pencil n | dim V | dim W | index | linear pass (median of %d) "
        "| numpy SVD %d x %d | ratio |" % (args.repeat, n, n),
        "|---|---|---|---|---|---|---|---|",
        "| RC ladder, capacitor loop at its end | %d | %d | %d | %d | %.3f s "
        "| %.2f s | %.2g |" % (cols, report["dim_V"], report["dim_W"],
                               report["index"], wong, ref, wong / ref),
    ]
    text = "\n".join(rows)
    print(text)
    print("target: linear pass under 5 s: %s" % ("met" if wong < 5 else
                                                   "NOT met"))
    if args.doc:
        os.environ["LDAE_BENCH_DOC"] = "1"
    benchdoc.write_section(
        os.path.join(HERE, "..", "docs", "benchmarks.md"),
        "Wong sequences",
        "## Wong sequences\n\n"
        "bench/run_wong.py: the \"linear\" pass (Wong sequences by "
        "reduction, docs/analysis.md) on a linear model with %d states, "
        "against one dense SVD of the state count's size with numpy "
        "(singular values only) in the same run. Target: under 5 s. The "
        "dense Wong sequences need several SVDs of the pencil's size per "
        "step (n = 2N + 3 here), hence the reduction: index-1 pairs split "
        "off, then a few sparse solves per step on what is left."
        "\n\n%s\n" % (n, text))

if __name__ == "__main__":
    main()
