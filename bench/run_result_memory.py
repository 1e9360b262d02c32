#!/usr/bin/python3
"""Memory of a long run (issue 28, docs/results.md "Rows written as the
run goes"): the rows go to the result file as the run produces them, so a
run's peak memory is the model's, whatever the number of rows.

Figures, each the peak resident set (ru_maxrss of the ldaec process):
- the oscillator (bench/oscillator.lsd) with --every-step for about 10^4
  and 10^7 steps, CSV to /dev/null and .mat to a scratch file; the ratio
  of the long run to the short one (target: within 1.10);
- the SciMLBenchmarks RC circuit (tests/models/rc_circuit_sciml.lsd) at
  N = 3000 sections, compiled only (the model), and run with --interval
  0.1 and 0.01 (101 and 1001 rows of 63,014 columns: 51 MB and 504 MB of
  result data) to /dev/null.

Usage: bench/run_result_memory.py --ldaec PATH [--steps 10000000] [--doc]
  --doc   writes the table into docs/benchmarks.md ("Memory of long runs");
          without it the table is printed only.
Standard library only.
"""
import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DOC = os.path.join(ROOT, "docs", "benchmarks.md")
OSC = os.path.join(HERE, "oscillator.lsd")
RC = os.path.join(ROOT, "tests", "models", "rc_circuit_sciml.lsd")
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402

# Steps per unit time of the oscillator at the default tolerance (CVODE
# BDF, rtol 1e-6): 8.14 (1,009,629 steps to t = 124,000).
STEPS_PER_TIME = 8.14


def peak(cmd):
    """(peak resident set in MiB, wall seconds, stderr) of one process."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True)
    err = p.stderr.read()
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        sys.exit("ldaec failed (%d): %s\n%s" % (p.returncode, " ".join(cmd),
                                                 err[-2000:]))
    return usage.ru_maxrss / 1024.0, time.perf_counter() - t0, err


def steps_of(err):
    for line in err.splitlines():
        if line.startswith("steps "):
            return int(line.split()[1])
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ldaec", required=True)
    ap.add_argument("--steps", type=int, default=10_000_000)
    ap.add_argument("--doc", action="store_true")
    a = ap.parse_args()
    if a.doc:
        os.environ["LDAE_BENCH_DOC"] = "1"
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        osc = {}
        for steps in (10_000, a.steps):
            # The steps per unit time fall as the run goes on: the stop
            # time is scaled by the steps a try took, until within 5%.
            stop = steps / STEPS_PER_TIME
            for fmt, out in (("CSV", os.devnull),
                             (".mat", os.path.join(tmp, "osc.mat"))):
                for attempt in range(6):
                    mib, wall, err = peak([a.ldaec, OSC, "--simulate",
                                           "--every-step", "--stop",
                                           "%.6g" % stop, "--stats",
                                           "--no-progress", "-o", out])
                    taken = steps_of(err)
                    if abs(taken - steps) > 0.05 * steps:
                        stop *= steps / taken
                    else:
                        break
                osc[(steps, fmt)] = mib
                rows.append("| oscillator, --every-step to t = %.6g, %s | %s "
                            "| %.1f | %.1f |" % (stop, fmt,
                                                 "{:,}".format(taken),
                                                 mib, wall))
        rc = []
        for label, extra in (("compiled only", ["--compile-only"]),
                             ("--interval 0.1", ["--interval", "0.1"]),
                             ("--interval 0.01", ["--interval", "0.01"])):
            mib, wall, _ = peak([a.ldaec, RC, "--simulate", "--param",
                                 "N=3000", "--no-progress", "-o", os.devnull]
                                + extra)
            rc.append(mib)
            rows.append("| RC circuit N = 3000, %s | | %.1f | %.1f |"
                        % (label, mib, wall))
    ratios = ["%s %.3f" % (fmt, osc[(a.steps, fmt)] / osc[(10_000, fmt)])
              for fmt in ("CSV", ".mat")]
    ok = all(osc[(a.steps, f)] <= 1.10 * osc[(10_000, f)]
             for f in ("CSV", ".mat"))
    section = """## Memory of long runs

`bench/run_result_memory.py` ({date}, {machine}): the peak resident set of
the ldaec process (ru_maxrss). The rows go to the result file as the run
produces them (docs/results.md, "Rows written as the run goes"), so a long
run holds none of them.

| run | steps | peak (MiB) | wall (s) |
|---|---:|---:|---:|
{rows}

Long run against the short one (target ≤ 1.10): {ratios}: **{verdict}**.
The RC circuit's run adds {rc_run:.1f} MiB to the compiled model at 101
rows and {rc_run2:.1f} MiB at 1001 rows (63,014 columns: its result data
would be 51 and 504 MB).
""".format(date=time.strftime("%Y-%m-%d"), machine=platform.machine(),
           rows="\n".join(rows), ratios=", ".join(ratios),
           verdict="pass" if ok else "FAIL", rc_run=rc[1] - rc[0],
           rc_run2=rc[2] - rc[0])
    write_section(DOC, "Memory of long runs", section)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
