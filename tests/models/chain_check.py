#!/usr/bin/env python3
"""End-to-end check of the planar pendulum chain of bench/run_sga.py
(chain(n): n unit links with unit masses hanging from the origin, straight
at the start, Cartesian coordinates, one tension per link; issue 14) with
the real ldaec binary, 10 s at rtol 1e-8, against
reference/chain{3,10}_ref.csv (minimal coordinates with SciPy's DOP853 at
rtol 1e-13, cross-checked against the Cartesian index-1 form;
reference/chain_ref.py):

1. `--method sga`: x_i, y_i within the bound of the reference at every
   output; the position and velocity constraints hold to 1e-10 at every
   row and --stats' drift stays below 1e-10; the start, consistent in
   positions and velocities, keeps them (only the tensions are solved).
   Measured: 1.7e-6 (3 links, 1121 steps) and 1.4e-6 (10 links, 2855
   steps); at rtol 1e-10 1.1e-8 and 6.5e-9.

2. `--method dd` (the default): the link constraints make one block of n
   rows over 2n positions (and one of the velocities below it), chosen at
   run time (docs/runtime.md, "Dynamic state selection"): states
   $stateset1.x = A (x, y) and $stateset2.x = A (u, v) with A from a
   column-pivoted factorization. x_i, y_i within 1e-6 of the reference at
   every output; position and velocity constraints within 1e-7 and the
   drift below 1e-7. Measured at rtol 1e-8: 1.6e-7 (3 links, 3914 steps,
   no switch) and 1.7e-7 (10 links, 5276 steps, 2 switches of the
   velocities); constraints 2.4e-9 / 1.8e-8 and 1.1e-8 / 3.3e-8. The 3-link
   chain at rtol 1e-6 runs to 10 s (it stopped at t = 0.77 with the one
   fixed state set this replaced): 1.5e-5 from the reference (bound 1e-4).

Usage: chain_check.py LDAEC. Standard library only.
"""
import os
import sys
import tempfile

from check_e2e import ROOT, check, finish, read_ref, run, same_times, stat

sys.path.insert(0, os.path.join(ROOT, "bench"))
from run_sga import chain  # noqa: E402  (the benchmark's own model)

COMMON = ["--simulate", "--stop", "10", "--interval", "0.1", "--rtol", "1e-8",
          "--stats"]
# Largest |x_i, y_i - reference| over the run at rtol 1e-8 (measured
# 1.7e-6 and 1.4e-6).
SGA_BOUND = {3: 1e-5, 10: 1e-5}
# The same for --method dd (measured 1.6e-7 and 1.7e-7).
DD_BOUND = {3: 1e-6, 10: 1e-6}


def model(tmp, n):
    path = os.path.join(tmp, "chain%d.lsd" % n)
    with open(path, "w") as f:
        f.write(chain(n))
    return path


def position_error(rows, ref, n):
    names = ["x%d" % i for i in range(1, n + 1)] + \
        ["y%d" % i for i in range(1, n + 1)]
    return max(abs(r[k] - q[k]) for r, q in zip(rows, ref) for k in names)


def constraints(rows, n):
    """The largest |link length^2 - 1| and |d_i . d_i'| over all rows."""
    pos = vel = 0.0
    for r in rows:
        for i in range(1, n + 1):
            dx = r["x%d" % i] - (r["x%d" % (i - 1)] if i > 1 else 0.0)
            dy = r["y%d" % i] - (r["y%d" % (i - 1)] if i > 1 else 0.0)
            du = r["u%d" % i] - (r["u%d" % (i - 1)] if i > 1 else 0.0)
            dv = r["v%d" % i] - (r["v%d" % (i - 1)] if i > 1 else 0.0)
            pos = max(pos, abs(dx * dx + dy * dy - 1))
            vel = max(vel, abs(dx * du + dy * dv))
    return pos, vel


def constraints_hold(rows, err, n, method, bound):
    c = constraints(rows, n)
    check(max(c) <= bound, "%s, %d links: position and velocity constraints "
          "<= %g at every row (%.2e, %.2e)" % ((method, n, bound) + c))
    drift = stat(err, "largest drift residual")
    check(drift is not None and drift <= bound,
          "%s, %d links: largest drift residual %s <= %g"
          % (method, n, drift, bound))


def sga(tmp, ldaec, n):
    ref = read_ref("chain%d_ref.csv" % n)
    _, rows, err = run(ldaec, [model(tmp, n), "--method", "sga"] + COMMON)
    same_times(rows, ref)
    e = position_error(rows, ref, n)
    check(e <= SGA_BOUND[n], "sga, %d links, 10 s: |x, y - reference| <= %g "
          "(max %.2e, %d steps)" % (n, SGA_BOUND[n], e, stat(err, "steps") or -1))
    constraints_hold(rows, err, n, "sga", 1e-10)
    moved = [line.split("'")[1] for line in err.splitlines()
             if line.startswith("  '") and " from " in line]
    check(moved and all(v.startswith("lam") for v in moved),
          "sga, %d links: the start moves the tensions only (%s)"
          % (n, ", ".join(moved)))


def dd(tmp, ldaec, n, rtol="1e-8", bound=None):
    ref = read_ref("chain%d_ref.csv" % n)
    args = COMMON[:COMMON.index("--rtol")] + ["--rtol", rtol, "--stats"]
    status, rows, err = run(ldaec, [model(tmp, n), "--method", "dd"] + args)
    check(status == 0 and rows and float(rows[-1]["time"]) == 10,
          "dd, %d links, rtol %s: runs to 10 s (status %d)" % (n, rtol, status))
    same_times(rows, ref)
    bound = bound or DD_BOUND[n]
    e = position_error(rows, ref, n)
    check(e <= bound, "dd, %d links, rtol %s: |x, y - reference| <= %g "
          "(max %.2e, %d steps, %s state switches)"
          % (n, rtol, bound, e, stat(err, "steps") or -1,
             stat(err, "state set switches")))
    if rtol != "1e-8":
        return
    constraints_hold(rows, err, n, "dd", 1e-7)


def main():
    ldaec = sys.argv[1]
    with tempfile.TemporaryDirectory(prefix="ldaec-chain-") as tmp:
        for n in (3, 10):
            sga(tmp, ldaec, n)
            dd(tmp, ldaec, n)
        dd(tmp, ldaec, 3, rtol="1e-6", bound=1e-4)
    finish()


if __name__ == "__main__":
    main()
