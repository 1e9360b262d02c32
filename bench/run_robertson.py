#!/usr/bin/env python3
"""SUNDIALS' idaRoberts_dns problem, whole process: `ldaec
tests/models/robertson_sundials.lsd --simulate -o out.csv` with default
options at the example's tolerances (--rtol 1e-4 --atol 1e-6, nominal
1e-2 on y1 giving its 1e-8) and output times (0.4, 4, ..., 4e10) against
the same problem written by hand in C (bench/robertson_ida.c: dense IDA,
analytic Jacobian, -O2, the SUNDIALS libraries ldaec links) writing the
same CSV. Median of --repeat interleaved runs; the target is ldaec within
3x of the C program. With valgrind, each process's instructions too
(callgrind, one run: exact whatever the machine's load), and those of
`ldaec --version`, the start-up alone.

Usage: run_robertson.py [--build DIR] [--repeat 20] [--before LDAEC] [--doc]
  --build   the build directory holding compiler/driver/ldaec and
            bench/robertson_ida (default: build)
  --before  another ldaec binary (one built before a change) run the same
            way, as rows of its own
  --doc     writes the table into docs/benchmarks.md ("Robertson").
Standard library only.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MODEL = os.path.join(ROOT, "tests", "models", "robertson_sundials.lsd")
DOC = os.path.join(ROOT, "docs", "benchmarks.md")
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402
from benchrun import (machine, median, parse_args, run_cpu, stat,  # noqa: E402
                      word)

TIMES = ",".join("%ge%d" % (4, k) for k in range(-1, 11))  # 0.4 ... 4e10


# The command lines compared: ldaec as a user runs it, ldaec as the
# accuracy test runs it (every unknown to IDA, as in the example), the C
# program.
VARIANTS = {"ldaec": [], "ldaec --causalize off": ["--causalize", "off"]}


def instructions(cmd):
    """Millions of instructions the process executes (callgrind), or None
    without valgrind."""
    if not shutil.which("valgrind"):
        return None
    proc = subprocess.run(["valgrind", "--tool=callgrind",
                           "--callgrind-out-file=/dev/null"] + cmd,
                          capture_output=True, text=True)
    m = re.search(r"Collected : (\d+)", proc.stderr)
    return int(m.group(1)) / 1e6 if m else None


def ldaec_command(ldaec, extra, csv):
    return [ldaec, "--no-progress", MODEL, "--simulate", "--rtol", "1e-4",
            "--atol", "1e-6", "--output-times", TIMES, "--stats", "-o",
            csv] + extra


def ldaec_run(ldaec, extra, csv):
    """(process seconds, CPU seconds, steps, "integrator, backend")."""
    _, err, seconds, cpu = run_cpu(ldaec_command(ldaec, extra, csv))
    backend = (word(err, "backend:") or "").split(" (")[0]
    return (seconds, cpu, int(stat(err, "steps")),
            (word(err, "integrator") or "IDA") + ", " + backend)


def main():
    args = parse_args(__doc__, ROOT, repeat=20, extra=lambda ap: ap.add_argument(
        "--before", help="an ldaec built before a change, run alike"))
    program = os.path.join(args.build, "bench", "robertson_ida")
    binaries = {"": args.ldaec}
    if args.before:
        binaries[" (before)"] = os.path.abspath(args.before)
    runs = {name + tag: (ldaec, extra) for tag, ldaec in binaries.items()
            for name, extra in VARIANTS.items()}
    times = {k: [] for k in list(runs) + ["robertson_ida.c"]}
    cpu = {k: [] for k in times}
    what = {"robertson_ida.c": "IDA, dense, -O2"}
    steps = {}
    with tempfile.TemporaryDirectory() as tmp:
        csv = os.path.join(tmp, "out.csv")
        for _ in range(args.repeat):
            for key, (ldaec, extra) in runs.items():
                seconds, used, steps[key], what[key] = ldaec_run(
                    ldaec, extra, csv)
                times[key].append(seconds)
                cpu[key].append(used)
            _, err, seconds, used = run_cpu([program, "-o", csv])
            times["robertson_ida.c"].append(seconds)
            cpu["robertson_ida.c"].append(used)
            steps["robertson_ida.c"] = int(stat(err, "steps"))
        counts = {key: instructions(ldaec_command(ldaec, extra, csv))
                  for key, (ldaec, extra) in runs.items()}
        counts["robertson_ida.c"] = instructions([program, "-o", csv])
        for tag, ldaec in binaries.items():
            counts["ldaec --version" + tag] = instructions(
                [ldaec, "--version"])
    ref, ref_cpu = times["robertson_ida.c"], cpu["robertson_ida.c"]
    ref_ins = counts["robertson_ida.c"]

    def ins(key):
        if counts.get(key) is None or ref_ins is None:
            return "| | "
        return "| %.1f | %.2fx " % (counts[key], counts[key] / ref_ins)

    lines = ["| program | integrator, backend | steps | wall ms (median) | "
             "/ C | wall ms (fastest) | / C | CPU ms (median) | / C | "
             "instructions (M) | / C |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for key, t in times.items():
        c = cpu[key]
        lines.append("| %s | %s | %d | %.1f | **%.2fx** | %.1f | %.2fx | "
                     "%.1f | %.2fx %s|" % (
                         key, what[key], steps[key], 1e3 * median(t),
                         median(t) / median(ref), 1e3 * min(t),
                         min(t) / min(ref), 1e3 * median(c),
                         median(c) / median(ref_cpu), ins(key)))
    for tag in binaries:
        key = "ldaec --version" + tag
        lines.append("| %s | start-up alone | | | | | | | %s|" % (
            key, ins(key)))
    text = "\n".join([
        "## Robertson",
        "",
        "`bench/run_robertson.py --doc` (%s). SUNDIALS' idaRoberts_dns "
        "problem, the whole process writing its 13-row CSV: `ldaec "
        "tests/models/robertson_sundials.lsd --simulate --rtol 1e-4 --atol "
        "1e-6 --output-times 0.4,...,4e10 -o out.csv` (default options, and "
        "with `--causalize off`, as ctest `model.robertson_default_uncausal` "
        "checks it against the example's printed output) against "
        "`bench/robertson_ida.c`, the problem written by hand (dense IDA, "
        "analytic Jacobian, every unknown error-tested, no root functions, "
        "-O2, the SUNDIALS ldaec links), %d interleaved runs: the wall time "
        "of each process as this script sees it (median and fastest) and "
        "its CPU time (user + system, median), and the instructions of one "
        "run (callgrind). Target: ldaec within 3x of the C program." % (
            machine(), args.repeat),
        "",
        "\n".join(lines)])
    write_section(DOC, "Robertson", text)


if __name__ == "__main__":
    main()
