#!/usr/bin/env python3
"""SUNDIALS' idaRoberts_dns problem, whole process: `ldaec
tests/models/robertson_sundials.lsd --simulate -o out.csv` with default
options at the example's tolerances (--rtol 1e-4 --atol 1e-6, nominal
1e-2 on y1 giving its 1e-8) and output times (0.4, 4, ..., 4e10) against
the same problem written by hand in C (bench/robertson_ida.c: dense IDA,
analytic Jacobian, -O2, the SUNDIALS libraries ldaec links) writing the
same CSV. Median of --repeat interleaved runs; the target is ldaec within
3x of the C program.

Usage: run_robertson.py [--build DIR] [--repeat 20] [--doc]
  --build  the build directory holding compiler/driver/ldaec and
           bench/robertson_ida (default: build)
  --doc    writes the table into docs/benchmarks.md ("Robertson").
Standard library only.
"""
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MODEL = os.path.join(ROOT, "tests", "models", "robertson_sundials.lsd")
DOC = os.path.join(ROOT, "docs", "benchmarks.md")
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402
from benchrun import parse_args, machine, median, run, stat, word  # noqa: E402

TIMES = ",".join("%ge%d" % (4, k) for k in range(-1, 11))  # 0.4 ... 4e10


def main():
    args = parse_args(__doc__, ROOT, repeat=20)
    build, ldaec = args.build, args.ldaec
    program = os.path.join(build, "bench", "robertson_ida")
    times = {"ldaec": [], "C": []}
    with tempfile.TemporaryDirectory() as tmp:
        csv = os.path.join(tmp, "out.csv")
        for _ in range(args.repeat):
            _, err, seconds = run([
                ldaec, "--no-progress", MODEL, "--simulate", "--rtol", "1e-4",
                "--atol", "1e-6", "--output-times", TIMES, "--stats", "-o",
                csv])
            times["ldaec"].append(seconds)
            ldaec_steps = int(stat(err, "steps"))
            integrator = word(err, "integrator") or "IDA"
            backend = (word(err, "backend:") or "").split(" (")[0]
            _, err, seconds = run([program, "-o", csv])
            times["C"].append(seconds)
            c_steps = int(stat(err, "steps"))
    ours, theirs = median(times["ldaec"]), median(times["C"])
    table = "\n".join([
        "| program | integrator | steps | process ms (median) | min ms |",
        "|---|---|---:|---:|---:|",
        "| ldaec | %s | %d | %.1f | %.1f |" % (
            integrator, ldaec_steps, 1e3 * ours, 1e3 * min(times["ldaec"])),
        "| robertson_ida.c | IDA, dense | %d | %.1f | %.1f |" % (
            c_steps, 1e3 * theirs, 1e3 * min(times["C"])),
        "",
        "ldaec / C: **%.2fx** of the medians, %.2fx of the fastest runs "
        "(target 3x)." % (ours / theirs, min(times["ldaec"]) /
                          min(times["C"]))])
    text = "\n".join([
        "## Robertson",
        "",
        "`bench/run_robertson.py --doc` (%s). SUNDIALS' idaRoberts_dns "
        "problem, the whole process writing its 13-row CSV: `ldaec "
        "tests/models/robertson_sundials.lsd --simulate --rtol 1e-4 --atol "
        "1e-6 --output-times 0.4,...,4e10 -o out.csv` (default options%s) "
        "against `bench/robertson_ida.c`, the problem written by hand "
        "(dense IDA, analytic Jacobian, every unknown error-tested, -O2, the "
        "SUNDIALS ldaec links), median of %d interleaved runs. Accuracy "
        "against the example's printed output: ctest "
        "`model.robertson_default`." % (
            machine(), "; %s" % backend if backend else "", args.repeat),
        "",
        table])
    write_section(DOC, "Robertson", text)


if __name__ == "__main__":
    main()
