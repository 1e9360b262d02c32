#!/usr/bin/python3
"""The command-line sweep (issue 16, docs/results.md "Sweeps"): N members
of the RC circuit (tests/models/rc_circuit.lsd, R over a range) with
`ldaec --sweep ... --jobs J -o sweep.mat`, one compile and the members on
J threads, against the reference a shell loop gives: one `ldaec
--simulate --param R=...` process per member (parse, analysis and code
generation every time). Both in this script, on this machine.

Figures: the wall time of the whole sweep process for --jobs 1 and
--jobs <cores>, and of --loop-members separate processes, scaled to N
(every process does the same work). Each figure is the best of --repeat.
Usage: bench/run_sweep_cli.py --ldaec PATH [--members 1000]
                              [--loop-members 50] [--repeat 3] [--write]
  --write  puts the table into docs/benchmarks.md ("Command-line sweep");
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
MODEL = os.path.join(ROOT, "tests", "models", "rc_circuit.lsd")
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402

R_FIRST, R_LAST = 50.0, 200.0


def timed(cmd):
    """(wall seconds, CPU seconds) of one process."""
    t0, c0 = time.perf_counter(), os.times()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall, c1 = time.perf_counter() - t0, os.times()
    if p.returncode != 0:
        sys.exit("ldaec failed (%d): %s\n%s" % (p.returncode, " ".join(cmd),
                                                 p.stderr))
    cpu = (c1.children_user - c0.children_user +
           c1.children_system - c0.children_system)
    return wall, cpu


def sweep(ldaec, members, jobs, scratch):
    return timed([ldaec, MODEL, "--simulate", "--no-progress",
                  "--sweep", "R=%g:%g:%d" % (R_FIRST, R_LAST, members),
                  "--jobs", str(jobs), "-o",
                  os.path.join(scratch, "sweep.mat")])


def loop(ldaec, members, scratch):
    out = os.path.join(scratch, "one.csv")
    wall = cpu = 0.0
    for k in range(members):
        r = R_FIRST + (R_LAST - R_FIRST) * k / max(1, members - 1)
        w, c = timed([ldaec, MODEL, "--simulate", "--no-progress",
                      "--param", "R=%r" % r, "-o", out])
        wall, cpu = wall + w, cpu + c
    return wall, cpu


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ldaec", required=True)
    ap.add_argument("--members", type=int, default=1000)
    ap.add_argument("--loop-members", type=int, default=50)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--write", "--doc", action="store_true",
                    help="write the table into docs/benchmarks.md")
    args = ap.parse_args()
    if args.write:
        os.environ["LDAE_BENCH_DOC"] = "1"
    cores = os.cpu_count() or 1
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as scratch:
        one = min(sweep(args.ldaec, args.members, 1, scratch)
                  for _ in range(args.repeat))
        many = min(sweep(args.ldaec, args.members, cores, scratch)
                   for _ in range(args.repeat))
        lw, lc = min(loop(args.ldaec, args.loop_members, scratch)
                     for _ in range(args.repeat))
    n = args.members
    scale = n / args.loop_members
    looped = (lw * scale, lc * scale)
    rows = [
        ("one process per member (shell loop; %d run, scaled)" %
         args.loop_members, looped),
        ("`--sweep`, `--jobs 1`", one),
        ("`--sweep`, `--jobs %d`" % cores, many),
    ]
    lines = [
        "## Command-line sweep",
        "",
        "`bench/run_sweep_cli.py`: %d members of the RC circuit "
        "(tests/models/rc_circuit.lsd, R from %g to %g), the whole "
        "process's wall time, best of %d; %s, %d cores. The reference is "
        "a shell loop of one `ldaec --simulate --param R=...` per member "
        "(%.1f ms each: parse, analysis and code generation every time). "
        "CPU is the processes' user and system time over the wall time: "
        "below 1 with several jobs means the cores were busy with "
        "something else (load average %.1f when the script started)."
        % (n, R_FIRST, R_LAST, args.repeat, platform.machine(), cores,
           looped[0] / n * 1e3, load),
        "",
        "| how | wall time | per member | CPU | speed-up |",
        "|-----|-----------|------------|-----|----------|",
    ]
    for how, (wall, cpu) in rows:
        lines.append("| %s | %.2f s | %.3f ms | %.2f | %.1fx |" %
                     (how, wall, wall / n * 1e3, cpu / wall,
                      looped[0] / wall))
    lines.append("")
    lines.append(
        "`--jobs %d` against `--jobs 1`: %.2fx (the members are short: "
        "the one compile and the file weigh on both)." %
        (cores, one[0] / many[0]))
    write_section(DOC, "Command-line sweep", "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
