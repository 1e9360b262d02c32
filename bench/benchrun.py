"""Running the programs a benchmark compares: ldaec and the hand-written
SUNDIALS references, which print their statistics in the same "name value"
lines as `ldaec --stats`. Standard library only."""
import argparse
import os
import re
import resource
import statistics
import subprocess
import time


def stat(text, name):
    """The number after `name` at the start of a line of --stats output."""
    m = re.search(r"^%s\s+([0-9.eE+-]+)" % re.escape(name), text, re.M)
    if not m:
        raise RuntimeError("no '%s' in the statistics:\n%s" %
                           (name, text[-2000:]))
    return float(m.group(1))


def word(text, name):
    """The text after `name` (for example "integrator  cvode-bdf"), or
    None when the line is absent."""
    m = re.search(r"^%s\s+(\S.*)$" % re.escape(name), text, re.M)
    return m.group(1).strip() if m else None


def integration_time(text):
    """The integration part of a run: "integration time" where the program
    prints it, else ldaec's wall time less its initialization."""
    if re.search(r"^integration time\s", text, re.M):
        return stat(text, "integration time")
    return stat(text, "wall time") - stat(text, "initialization time")


def run(cmd, timeout=3600):
    """Runs `cmd`; (stdout, stderr, whole process wall time in seconds).
    A failure raises with the end of its stderr."""
    return run_cpu(cmd, timeout)[:3]


def run_cpu(cmd, timeout=3600):
    """run(), and the child's CPU time (user + system seconds), which a
    loaded machine disturbs less than the wall time."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True,
                          timeout=timeout)
    seconds = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise RuntimeError("%s exited %d:\n%s" % (
            " ".join(cmd), proc.returncode, proc.stderr[-3000:]))
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime -
                                                before.ru_stime)
    return proc.stdout, proc.stderr, seconds, cpu


def median(values):
    return statistics.median(values)


def machine():
    """The line every section starts with: date, machine, load."""
    return "%s, %s, load average %.2f on a shared %d-core machine" % (
        time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), os.uname().machine,
        os.getloadavg()[0], os.cpu_count())


def parse_args(doc, root, sizes=None, repeat=3, extra=None):
    """The options every side-by-side script takes: --build (the build
    directory, default build/), --sizes when it has sizes, --repeat,
    --doc, and the script's own (`extra(parser)` adds them). Sets
    args.build (absolute) and args.ldaec."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(root, "build"))
    if sizes:
        ap.add_argument("--sizes", default=sizes)
    ap.add_argument("--repeat", type=int, default=repeat)
    ap.add_argument("--doc", action="store_true")
    if extra:
        extra(ap)
    args = ap.parse_args()
    args.build = os.path.abspath(args.build)
    args.ldaec = os.path.join(args.build, "compiler", "driver", "ldaec")
    if args.doc:
        os.environ["LDAE_BENCH_DOC"] = "1"
    return args
