#!/usr/bin/env python3
"""The SciMLBenchmarks RC circuit (tests/models/rc_circuit_sciml.lsd) as a
user runs it: the whole `ldaec model.lsd --simulate -o out.csv` process
(parse, reduce, compile, integrate to StopTime 10, write every variable at
the 1001 output times), N = 1000 and 9000 sections, against Dymola's
translate + simulate times published by SciMLBenchmarks (6.826 s and
57.187 s, their machine), as ratios; median of --repeat runs.

The CSV throughput, two ways: the written file's size over the time ldaec
spends writing it (from opening the file to closing it, read from
`strace --seccomp-bpf -e trace=openat,close` in separate runs: strace
stops the process only at those calls), and the writer alone on
synthetic rows (bench/results_bench.cpp, the "ours MB/s" column).

Usage: run_rc_sciml.py [--build DIR] [--sizes 1000,9000] [--repeat 3]
                       [--doc]
  --build  the build directory holding compiler/driver/ldaec and
           bench/results_bench (default: build)
  --doc    writes the tables into docs/benchmarks.md
           ("RC circuit (SciMLBenchmarks)").
The CSVs go to a temporary directory (2.6 GB at N = 9000), removed after
each run. Standard library only.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MODEL = os.path.join(ROOT, "tests", "models", "rc_circuit_sciml.lsd")
DOC = os.path.join(ROOT, "docs", "benchmarks.md")
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402
from benchrun import parse_args, machine, median, run, stat  # noqa: E402

# SciMLBenchmarks "RC Circuit": Dymola's translate + simulate seconds.
DYMOLA = {1000: 6.826, 9000: 57.187}


def ldaec_cmd(ldaec, n, csv):
    return [ldaec, "--no-progress", MODEL, "--simulate", "--stats",
            "--param", "N=%d" % n, "-o", csv]


def whole_process(ldaec, n, tmp):
    """(process seconds, compile seconds, simulator wall seconds, CSV
    bytes) of one plain run."""
    csv = os.path.join(tmp, "out.csv")
    _, err, seconds = run(ldaec_cmd(ldaec, n, csv))
    size = os.path.getsize(csv)
    os.remove(csv)
    compile_s = float(re.search(r"^compile time: ([0-9.eE+-]+)", err,
                                re.M).group(1))
    return seconds, compile_s, stat(err, "wall time"), size


def write_window(ldaec, n, tmp):
    """(bytes, seconds between opening and closing the CSV) under strace."""
    csv = os.path.join(tmp, "out.csv")
    trace = os.path.join(tmp, "trace.txt")
    run(["strace", "-f", "--seccomp-bpf", "-ttt", "-e", "trace=openat,close",
         "-o", trace] + ldaec_cmd(ldaec, n, csv))
    size = os.path.getsize(csv)
    os.remove(csv)
    with open(trace) as f:
        text = f.read()
    opened = re.search(r"^\d+\s+([0-9.]+) openat\([^\n]*\"%s\"[^\n]*= (\d+)$"
                       % re.escape(csv), text, re.M)
    if not opened:
        raise RuntimeError("no openat of %s in the trace" % csv)
    closed = re.search(r"^\d+\s+([0-9.]+) close\(%s\)" % opened.group(2),
                       text[opened.end():], re.M)
    return size, float(closed.group(1)) - float(opened.group(1))


def writer_alone(build):
    """The "ours MB/s" column of results_bench, one value per size."""
    program = os.path.join(build, "bench", "results_bench")
    if not os.path.exists(program):
        return []
    out, _, _ = run([program, "3"])
    rows = []
    for line in out.splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) >= 5:
            rows.append((cells[0], float(cells[4])))
    return rows


def main():
    args = parse_args(__doc__, ROOT, sizes="1000,9000", repeat=3)
    build, ldaec = args.build, args.ldaec
    if not shutil.which("strace"):
        sys.exit("run_rc_sciml.py: needs strace (apt-get install strace)")
    process = ["| N | process s (median) | compile s | simulation s | "
               "CSV MB | Dymola s | ldaec / Dymola |",
               "|---:|---:|---:|---:|---:|---:|---:|"]
    write = ["| N | CSV MB | write s | MB/s |", "|---:|---:|---:|---:|"]
    with tempfile.TemporaryDirectory() as tmp:
        for n in (int(s) for s in args.sizes.split(",")):
            runs = [whole_process(ldaec, n, tmp) for _ in range(args.repeat)]
            seconds = median([r[0] for r in runs])
            size = runs[0][3]
            dymola = DYMOLA.get(n)
            process.append("| %d | %.3f | %.3f | %.3f | %.1f | %s | %s |" % (
                n, seconds, median([r[1] for r in runs]),
                median([r[2] for r in runs]), size / 1e6,
                dymola or "-", "%.2fx" % (seconds / dymola) if dymola
                else "-"))
            windows = [write_window(ldaec, n, tmp)
                       for _ in range(args.repeat)]
            secs = median([w[1] for w in windows])
            write.append("| %d | %.1f | %.3f | %.0f |" % (
                n, windows[0][0] / 1e6, secs, windows[0][0] / 1e6 / secs))
            print(process[-1] + "\n" + write[-1], flush=True)
    alone = writer_alone(build)
    text = "\n".join([
        "## RC circuit (SciMLBenchmarks)",
        "",
        "`bench/run_rc_sciml.py --doc` (%s). The whole process `ldaec "
        "tests/models/rc_circuit_sciml.lsd --simulate --param N=... -o "
        "out.csv` (StopTime 10, 1001 rows, every variable written; median of "
        "%d) against Dymola's translate + simulate time published by "
        "SciMLBenchmarks (\"RC Circuit\", their machine, not this one). "
        "Compile and simulation seconds are ldaec's --stats (simulation: "
        "initialization, integration, recording)." % (machine(),
                                                      args.repeat),
        "",
        "\n".join(process),
        "",
        "CSV throughput: the file's size over the time from opening it to "
        "closing it (separate runs under strace, median; the file goes to "
        "the page cache of a virtual disk). "
        "Target: 150 MB/s or better.",
        "",
        "\n".join(write)] + ([
            "",
            "The writer alone (`bench/results_bench`, synthetic rows to "
            "/dev/null, best of 3): " + ", ".join(
                "%s: %.0f MB/s" % (size, mbs) for size, mbs in alone) + "."]
            if alone else []))
    write_section(DOC, "RC circuit (SciMLBenchmarks)", text)


if __name__ == "__main__":
    main()
