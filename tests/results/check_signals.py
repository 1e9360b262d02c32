#!/usr/bin/env python3
"""A run stopped by SIGINT or SIGTERM keeps its rows (issue 28): ldaec
writes the rows so far as a failed run's, says where it stopped, and exits
128 + the signal (130, 143). Before, the rows were lost (no file at all).
Checks a CSV after SIGINT and a .mat (read by scipy) after SIGTERM, and
that the rows follow the solution, x = cos t.

Usage: check_signals.py LDAEC WORKDIR.
"""
import math
import os
import signal
import subprocess
import sys
import time

import scipy.io

LDAEC, WORK = sys.argv[1], sys.argv[2]
os.makedirs(WORK, exist_ok=True)
model = os.path.join(WORK, "oscillator.lsd")
with open(model, "w") as f:
    f.write("model Oscillator\n"
            "  Real x(start = 1, fixed = true), v(start = 0, fixed = true);\n"
            "equation\n  der(x) = v;\n  der(v) = -x;\nend Oscillator;\n")
failures = []


def check(ok, what):
    print(("ok:   " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)


def stopped_run(out, sig):
    """Runs a long simulation into `out`, sends `sig` once it integrates."""
    if os.path.exists(out):
        os.remove(out)
    p = subprocess.Popen([LDAEC, model, "--simulate", "--stop", "1e6",
                          "--interval", "0.1", "--rtol", "1e-8",
                          "--no-progress", "-o", out],
                         stderr=subprocess.PIPE, text=True)
    # The run has started once the initialization reports (a signal while
    # compiling keeps its default action); then some rows: the whole run
    # takes minutes.
    seen = []
    for line in p.stderr:
        seen.append(line)
        if line.startswith("initialization:"):
            break
    time.sleep(1.0)
    p.send_signal(sig)
    _, err = p.communicate(timeout=300)
    return p.returncode, "".join(seen) + err


rc, err = stopped_run(os.path.join(WORK, "int.csv"), signal.SIGINT)
check(rc == 130, "SIGINT: exit 130 (%d)" % rc)
check("ldaec: SIGINT: the run stopped at t = " in err,
      "SIGINT: says where the run stopped (%s)" % err.strip()[-200:])
rows = open(os.path.join(WORK, "int.csv")).read().splitlines()
check(rows[0] == "time,x,v", "the CSV has its header")
data = [[float(x) for x in r.split(",")] for r in rows[1:]]
check(len(data) > 100, "the rows so far are written (%d)" % len(data))
# Over the first 100 s: the phase error grows over a million periods.
worst = max(abs(x - math.cos(t)) for t, x, _ in data if t <= 100)
check(worst < 1e-5, "the rows follow x = cos t (max error %.2g)" % worst)
check(all(b[0] > a[0] for a, b in zip(data, data[1:])),
      "the rows are whole and in order")

rc, err = stopped_run(os.path.join(WORK, "term.mat"), signal.SIGTERM)
check(rc == 143, "SIGTERM: exit 143 (%d)" % rc)
m = scipy.io.loadmat(os.path.join(WORK, "term.mat"))
d = m["data_2"].T  # one row per time point
check(d.shape[0] > 100 and d.shape[1] == 3,
      "SIGTERM: a valid .mat with the rows so far (%s)" % (d.shape,))
worst = max(abs(row[1] - math.cos(row[0])) for row in d if row[0] <= 100)
check(worst < 1e-5, "its rows follow x = cos t (max error %.2g)" % worst)

print("all passed" if not failures else "%d failed" % len(failures))
sys.exit(1 if failures else 0)
