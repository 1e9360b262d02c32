#!/usr/bin/env python3
"""The SciMLBenchmarks RC circuit (tests/models/rc_circuit_sciml.lsd):
integration time to t = 10 and the number of unknowns IDA gets, for
N = 10, 100, 1000 sections, ldaec with causalization ("after") against
ldaec without it ("before": --causalize off, or another binary given with
--before) and against the same circuit written by hand with its N states
only (bench/rc_circuit_states.lsd, the reference).

Time is the simulator's own wall time (--stats "wall time": consistent
initialization, integration, output at the model's 1001 output times),
the best of --repeat runs; compile time is not included. All variables
are output (no --outputs pruning).

Usage: rc_circuit.py --ldaec PATH [--before PATH] [--sizes 10,100,1000]
                     [--repeat 3] [--doc]
  --doc   writes the table into docs/benchmarks.md ("RC circuit").
Standard library only.
"""
import argparse
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MODEL = os.path.join(ROOT, "tests", "models", "rc_circuit_sciml.lsd")
STATES = os.path.join(HERE, "rc_circuit_states.lsd")
DOC = os.path.join(ROOT, "docs", "benchmarks.md")
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402
from benchrun import stat  # noqa: E402


def simulate(ldaec, model, n, extra, repeat):
    """(unknowns, best wall time, steps) of ldaec --simulate --stats."""
    best, unknowns, steps = None, None, None
    for _ in range(repeat):
        proc = subprocess.run(
            [ldaec, "--no-progress", model, "--simulate", "--stats",
             "--param", "N=%d" % n, "-o", os.devnull] + extra,
            capture_output=True, text=True, timeout=3600)
        if proc.returncode != 0:
            raise RuntimeError("%s N=%d %s failed:\n%s" % (
                os.path.basename(model), n, " ".join(extra),
                proc.stderr[-3000:]))
        wall = stat(proc.stderr, "wall time")
        best = wall if best is None else min(best, wall)
        unknowns = int(stat(proc.stderr, "unknowns"))
        steps = int(stat(proc.stderr, "steps"))
    return unknowns, best, steps


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ldaec", required=True)
    ap.add_argument("--before", help="binary without causalization "
                    "(default: --ldaec with --causalize off)")
    ap.add_argument("--sizes", default="10,100,1000")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--doc", action="store_true")
    args = ap.parse_args()
    before = ([args.before, []] if args.before
              else [args.ldaec, ["--causalize", "off"]])
    rows = []
    for n in (int(s) for s in args.sizes.split(",")):
        after = simulate(args.ldaec, MODEL, n, [], args.repeat)
        prior = simulate(before[0], MODEL, n, before[1], args.repeat)
        ref = simulate(args.ldaec, STATES, n, [], args.repeat)
        rows.append((n, prior, after, ref))
        print("N=%d before %s after %s hand-written %s" % (n, prior, after,
                                                         ref), flush=True)
    lines = [
        "| N | unknowns before | unknowns after | hand-written | "
        "time before (s) | time after (s) | hand-written (s) | "
        "before / after | after / hand-written |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for n, prior, after, ref in rows:
        lines.append("| %d | %d | %d | %d | %.4f | %.4f | %.4f | %.2fx | "
                     "%.2fx |" % (n, prior[0], after[0], ref[0], prior[1],
                                  after[1], ref[1], prior[1] / after[1],
                                  after[1] / ref[1]))
    table = "\n".join(lines)
    print(table)
    if args.doc:
        os.environ["LDAE_BENCH_DOC"] = "1"
        before_text = ("`%s`" % os.path.relpath(args.before, ROOT)
                       if args.before else "`--causalize off`")
        write_section(DOC, "RC circuit", "\n".join([
            "## RC circuit",
            "",
            "`bench/rc_circuit.py --doc` (%s, x86_64, load average %.2f on "
            "a shared 2-core machine). The SciMLBenchmarks RC circuit "
            "(`tests/models/rc_circuit_sciml.lsd`: sine source, ladder of N "
            "MSL-style resistors and capacitors) integrated to t = 10 at "
            "rtol 1e-6, 1001 output times; unknowns are those IDA gets "
            "(`--stats`), time the simulator's wall time (initialization, "
            "integration, output; compile time excluded), best of %d. "
            "Before: %s; after: causalized (default); hand-written: "
            "`bench/rc_circuit_states.lsd`, the N states alone." % (
                time.strftime("%Y-%m-%d"), os.getloadavg()[0], args.repeat,
                before_text),
            "",
            table]))


if __name__ == "__main__":
    main()
