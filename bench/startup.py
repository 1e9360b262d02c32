#!/usr/bin/python3
"""Start-up of the ldaec process and the choice of backend (issue 13, "fast
start").

1. The pendulum command, `ldaec examples/pendulum.lsd --simulate -o
   /dev/null`, as a whole process: the median of --runs runs, wall time
   and CPU time (user + system of the child), with --jit auto (the
   default), on and off; beside /bin/true (what starting any process costs
   this script) and, with --before, another ldaec binary (e.g. one linked
   against libLLVM).
2. Where the time of that command goes (medians over --runs runs): the
   dynamic loader (LD_DEBUG=statistics, converted at the TSC rate),
   start-up and exit of the process (the CPU time of `ldaec --version`,
   which includes the loader and the static initializers), the stages
   --time-passes prints (frontend, passes, codegen) and the simulator's own "wall time"
   (--stats: initialization, integration, output grid); the rest is the
   CSV and the exit. Then the same run under callgrind (when valgrind is
   installed): instructions per part, exact whatever the load.
3. The backend threshold of --jit auto: whole-process CPU time with --jit on
   and --jit off for models of growing size, with the operations per
   evaluation --stats reports ("backend:" line). The interpreter wins below
   the crossover, the JIT above; Codegen.h's kAutoJitWork sits there.

CPU time is the figure to compare on a shared machine (wall time waits
for the other processes); both are printed.
Usage: bench/startup.py --ldaec PATH [--before PATH] [--runs 50]
                        [--sweep-runs 5] [--no-sweep] [--doc]
  --doc   writes the tables into docs/benchmarks.md ("Start-up").
Standard library only.
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DOC = os.path.join(ROOT, "docs", "benchmarks.md")
PENDULUM = os.path.join(ROOT, "examples", "pendulum.lsd")
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402

# (label, model file, parameter overrides) in growing size.
SWEEP = [("pendulum", "examples/pendulum.lsd", [])] + \
    [("Robertson", "tests/models/robertson_sundials.lsd", [])] + \
    [("RC ladder N=%d" % n, "examples/rc_ladder.lsd", ["N=%d" % n])
     for n in (10, 30, 100, 200, 300, 1000)] + \
    [("SciML RC N=%d" % n, "tests/models/rc_circuit_sciml.lsd", ["N=%d" % n])
     for n in (10, 30, 100, 300)] + \
    [("cascaded N=%d" % n, "tests/models/cascaded_first_order.lsd",
      ["N=%d" % n]) for n in (10, 100, 1000, 2000, 3000)]


def run_once(cmd, env=None):
    """(wall seconds, CPU seconds, stderr text) of one process."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, env=env)
    err = p.stderr.read().decode(errors="replace")
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        raise RuntimeError("%s: exit %d\n%s" %
                           (" ".join(cmd), p.returncode, err[-2000:]))
    return wall, usage.ru_utime + usage.ru_stime, err


def interleaved(cmds, runs):
    """Median wall and CPU milliseconds of each command over `runs` rounds;
    each round runs every command once, so a change in the machine's load
    falls on all of them alike."""
    walls = [[] for _ in cmds]
    cpus = [[] for _ in cmds]
    for _ in range(runs):
        for i, cmd in enumerate(cmds):
            w, c, _ = run_once(cmd)
            walls[i].append(w)
            cpus[i].append(c)
    return [(statistics.median(w) * 1e3, statistics.median(c) * 1e3)
            for w, c in zip(walls, cpus)]


def number(text, pattern):
    m = re.search(pattern, text, re.M)
    return float(m.group(1)) if m else float("nan")


def tsc_hz():
    """The TSC rate LD_DEBUG's cycle counts tick at (about the nominal
    clock on CPUs with a constant TSC)."""
    try:
        with open("/proc/cpuinfo") as f:
            m = re.search(r"model name.*@\s*([0-9.]+)GHz", f.read())
            if m:
                return float(m.group(1)) * 1e9
        with open("/proc/cpuinfo") as f:
            return float(re.search(r"cpu MHz\s*:\s*([0-9.]+)", f.read())
                         .group(1)) * 1e6
    except (OSError, AttributeError):
        return float("nan")


def pendulum_table(ldaec, before, runs):
    base = [PENDULUM, "--simulate", "-o", os.devnull, "--no-progress"]
    rows = [("/bin/true (process spawn)", ["/bin/true"])]
    if before:
        rows.append(("before: %s" % before, [before] + base))
    for jit in ("auto", "on", "off"):
        rows.append(("--jit %s" % jit, [ldaec] + base + ["--jit", jit]))
    times = interleaved([cmd for _, cmd in rows], runs)
    lines = ["| run | wall median (ms) | CPU median (ms) |",
             "|---|---:|---:|"]
    for (label, _), (wall, cpu) in zip(rows, times):
        lines.append("| %s | %.1f | %.1f |" % (label, wall, cpu))
    return lines


def breakdown(ldaec, runs):
    """Each part's median, from runs that alternate with the whole
    command and `--version`."""
    base = [ldaec, PENDULUM, "--simulate", "-o", os.devnull, "--no-progress"]
    parts = {k: [] for k in ("loader", "frontend", "passes", "codegen", "run",
                             "version", "whole")}
    env = dict(os.environ, LD_DEBUG="statistics")
    for _ in range(runs):
        _, _, err = run_once(base + ["--time-passes", "--stats"])
        for k in ("frontend", "passes", "codegen"):
            parts[k].append(number(err, r"^%s: ([0-9.eE+-]+) ms" % k))
        parts["run"].append(number(err, r"^wall time\s+([0-9.eE+-]+)") * 1e3)
        _, _, err = run_once(base, env)
        parts["loader"].append(
            number(err, r"total startup time in dynamic loader: ([0-9]+) "
                   r"cycles") / tsc_hz() * 1e3)
        # CPU time for the two whole processes: on a loaded machine their
        # wall time also counts waiting to be scheduled.
        parts["version"].append(run_once([ldaec, "--version"])[1] * 1e3)
        parts["whole"].append(run_once(base)[1] * 1e3)
    med = {k: statistics.median(v) for k, v in parts.items()}
    rest = med["whole"] - med["version"] - sum(
        med[k] for k in ("frontend", "passes", "codegen", "run"))
    lines = ["| part of `--jit auto` | median (ms) |", "|---|---:|",
             "| dynamic loader (LD_DEBUG=statistics) | %.2f |" % med["loader"],
             "| process start-up and exit, loader included (`ldaec "
             "--version`, CPU) | %.2f |" % med["version"]]
    for k, label in (("frontend", "frontend: read, parse, flatten"),
                     ("passes", "passes"), ("codegen", "codegen"),
                     ("run", "simulation (--stats wall time)")):
        lines.append("| %s | %.2f |" % (label, med[k]))
    lines.append("| the rest (CSV, freeing) | %.2f |" % rest)
    lines.append("| whole process (CPU) | %.2f |" % med["whole"])
    return lines


# Inclusive instruction counts callgrind_annotate prints for the parts of a
# run, by function; the static initializers and exit handlers are what runs
# below main in the executable but outside main.
PROFILE_PARTS = [
    ("dynamic loader", r"rtld\.c:_dl_start "),
    ("frontend: read, parse, flatten", r"frontend::compileFile\("),
    ("passes", r"passes::runPipeline\("),
    ("codegen (plan, interpreter tables)", r"codegen::compile\("),
    ("simulation", r"runtime::simulate\("),
    ("CSV", r"runtime::writeCsv\(ldae::runtime::SimResult const&, std::__cxx11"),
]


def profile(ldaec, cpu_ms):
    """Instructions of each part of one `--jit auto` run under callgrind
    (exact and independent of the machine's load), and the CPU time they
    stand for at the measured median."""
    out = os.path.join(os.environ.get("TMPDIR", "/tmp"),
                       "ldaec-startup.%d.callgrind" % os.getpid())
    subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=" +
                    out, ldaec, PENDULUM, "--simulate", "-o", os.devnull,
                    "--no-progress"], capture_output=True, check=True)
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", out],
                          capture_output=True, text=True, check=True).stdout
    os.unlink(out)

    def count(pattern):
        for line in text.splitlines():
            m = re.match(r"\s*([0-9,]+) \(", line)
            if m and re.search(pattern, line):
                return int(m.group(1).replace(",", ""))
        return 0

    total = count(r"PROGRAM TOTALS")
    rows = [(label, count(pat)) for label, pat in PROFILE_PARTS]
    rows.insert(1, ("static initializers and exit (ANTLR's parser tables)",
                    count(r"\(below main\) \[.*ldaec\]") -
                    count(r"main\.cpp:main ")))
    rows.append(("the rest (process set-up, freeing)",
                 total - sum(n for _, n in rows)))
    lines = ["| part of `--jit auto` | instructions (millions) | share | "
             "about (ms of CPU) |", "|---|---:|---:|---:|"]
    for label, n in rows + [("whole process", total)]:
        lines.append("| %s | %.1f | %.0f%% | %.1f |" %
                     (label, n / 1e6, 100.0 * n / total, cpu_ms * n / total))
    return lines


def sweep(ldaec, runs):
    lines = ["| model | operations per evaluation | --jit on CPU (ms) | "
             "--jit off CPU (ms) | off / on | auto picks |",
             "|---|---:|---:|---:|---:|---|"]
    for label, path, params in SWEEP:
        cmd = [ldaec, os.path.join(ROOT, path), "--simulate", "-o",
               os.devnull, "--no-progress"]
        for p in params:
            cmd += ["--param", p]
        _, _, err = run_once(cmd + ["--stats"])
        work = int(number(err, r"^backend: .*--jit auto: ([0-9]+) "))
        picks = "JIT" if re.search(r"^backend: LLVM JIT", err, re.M) \
            else "interpreter"
        (_, on), (_, off) = interleaved(
            [cmd + ["--jit", "on"], cmd + ["--jit", "off"]], runs)
        lines.append("| %s | %d | %.1f | %.1f | %.2f | %s |" %
                     (label, work, on, off, off / on, picks))
        print(lines[-1], flush=True)
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ldaec", required=True)
    ap.add_argument("--before", help="another ldaec to compare with")
    ap.add_argument("--runs", type=int, default=50)
    ap.add_argument("--sweep-runs", type=int, default=5)
    ap.add_argument("--no-sweep", action="store_true")
    ap.add_argument("--doc", action="store_true")
    args = ap.parse_args()
    if args.doc:
        os.environ["LDAE_BENCH_DOC"] = "1"

    out = ["## Start-up", "",
           "`bench/startup.py` (%d runs each, medians; the machine's load "
           "inflates wall time, CPU time is what to compare). The "
           "command: `ldaec examples/pendulum.lsd --simulate -o /dev/null`."
           % args.runs, ""]
    out += pendulum_table(args.ldaec, args.before, args.runs)
    print("\n".join(out), flush=True)
    part = breakdown(args.ldaec, args.runs)
    print("\n".join(part), flush=True)
    out += ["", "Where the time of `--jit auto` goes (timed; on a loaded "
            "machine the stages' wall time and the processes' CPU time do "
            "not add up exactly):", ""] + part
    if shutil.which("valgrind") and shutil.which("callgrind_annotate"):
        cpu = interleaved([[args.ldaec, PENDULUM, "--simulate", "-o",
                            os.devnull, "--no-progress"]], args.runs)[0][1]
        part = profile(args.ldaec, cpu)
        print("\n".join(part), flush=True)
        out += ["", "The same run counted in instructions (callgrind; the "
                "loader's count is inflated by valgrind's own preloaded "
                "libraries, LD_DEBUG's figure above is the real one):", ""]
        out += part
    if not args.no_sweep:
        out += ["", "The threshold of `--jit auto` (whole process, "
                "median of %d runs; operations per evaluation as `--stats` "
                "reports them):" % args.sweep_runs, ""]
        out += sweep(args.ldaec, args.sweep_runs)
    write_section(DOC, "Start-up", "\n".join(out) + "\n")


if __name__ == "__main__":
    main()
