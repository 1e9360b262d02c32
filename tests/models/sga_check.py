#!/usr/bin/env python3
"""End-to-end checks of `--method sga` and `--method ode` (issue 14's
must-show) with the real ldaec binary:

1. The Cartesian pendulum (examples/pendulum.lsd, theta0 = 1.5), 100 s,
   `--method sga`: x(t), y(t) against the polar formulation integrated
   independently (reference/pendulum_ref.csv: SciPy's DOP853 at rtol
   1e-13, reference/pendulum_ref.py): within 1e-6 at rtol 1e-10, 5e-6 at
   1e-9 (measured 6.5e-8 and 1.4e-6; over 11 start angles the error at
   1e-9 spreads from 1.1e-6 to 7.8e-6, bench/run_pendulum_tolerance.py,
   so the bound at 1e-9 is not the issue's 1e-6; CVODE's Adams on the
   polar ODE itself: 4.0e-8 and 1.25e-6). `--method dd` (BDF) is 1.6e-4 off at
   1e-9 (docs/runtime.md).
2. 1000 s: the position and velocity constraints hold to 1e-10 at every
   output row.
3. `--method ode` (no projection): the drift `--stats` reports grows with
   the length of the run; `sga` reports none above 1e-10.
4. Robertson (examples/robertson.lsd) with `--method sga`: the values of
   reference/robertson_ref.csv to 1e-3 relative, y1 + y2 + y3 = 1 to
   1e-12 at every row, and `--integrator auto` moves from Adams to BDF.
5. Seed 001 section 7's variable-length pendulum (time-dependent
   constraints; tests/models/pendulum_variable_length.lsd), rtol 1e-10:
   x, y within 1e-8 of reference/pendulum_var_ref.csv (measured 1.4e-9;
   dd: 6.6e-8), x^2 + y^2 = R(t)^2 to 1e-12 at every row.
6. Andrews' squeezing mechanism (tests/models/andrews.lsd: 77 SGA
   coordinates, dim P_f = 2), `--method sga` at rtol = atol = 1e-8 and
   1e-10 to the test set's end time 0.03: the angles q within 100 rtol
   relative and the velocities within 100 rtol of the largest (1e3) of
   the test set's reference (bench/bari/reference.json; measured 1.9e-8,
   2.8e-8 at 1e-8 and 8.2e-10, 1.2e-9 at 1e-10); the loop closures g(q)
   to 1e-10 at every output row and every constraint generation to 1e-10
   (`largest drift residual`); `--integrator auto` stays with Adams.

Usage: sga_check.py LDAEC. Standard library only.
"""
import json
import math
import os
import sys

from check_e2e import (HERE, ROOT, check, finish, read_ref, run, same_times,
                       stat)

PENDULUM = os.path.join(ROOT, "examples", "pendulum.lsd")
ROBERTSON = os.path.join(ROOT, "examples", "robertson.lsd")
BARI_REFERENCE = os.path.join(ROOT, "bench", "bari", "reference.json")


def constraints(rows):
    pos = max(abs(r["x"]**2 + r["y"]**2 - 1) for r in rows)
    vel = max(abs(r["x"] * r["vx"] + r["y"] * r["vy"]) for r in rows)
    return pos, vel


def pendulum(ldaec):
    ref = read_ref("pendulum_ref.csv")
    common = [PENDULUM, "--simulate", "--param", "theta0=1.5",
              "--outputs", "x,y,vx,vy", "--stats"]
    grid = ["--stop", "100", "--interval", "0.1"]
    # CVODE's Adams on the polar ODE itself is 1.25e-6 off at rtol 1e-9
    # (4.0e-8 at 1e-10): the 1e-6 needs 1e-10; at 1e-9 sga is
    # bounded here against dd's BDF (1.6e-4, docs/runtime.md).
    for rtol, bound in (("1e-9", 5e-6), ("1e-10", 1e-6)):
        _, rows, err = run(ldaec, common + grid + ["--method", "sga",
                                                   "--rtol", rtol])
        same_times(rows, ref)
        pos = max(abs(r[n] - q[n]) for r, q in zip(rows, ref)
                  for n in ("x", "y"))
        check(pos <= bound, "sga, rtol %s, 100 s: |x, y - polar| <= %g "
              "(max %.2e)" % (rtol, bound, pos))
    c = constraints(rows)
    check(max(c) <= 1e-10, "sga, 100 s: position and velocity constraints "
          "<= 1e-10 at every row (%.2e, %.2e)" % c)
    check("projected onto the constraints" in err,
          "sga: --stats names the projection")

    _, rows, err = run(ldaec, common + ["--method", "sga", "--rtol", "1e-9",
                                        "--stop", "1000", "--interval", "0.5"])
    c = constraints(rows)
    check(len(rows) == 2001 and max(c) <= 1e-10,
          "sga, rtol 1e-9, 1000 s: position and velocity constraints "
          "<= 1e-10 at all %d rows (%.2e, %.2e)" % ((len(rows),) + c))
    drift = stat(err, "largest drift residual")
    check(drift is not None and drift <= 1e-10,
          "sga, 1000 s: largest drift residual %s <= 1e-10" % drift)

    drifts = []
    for stop in ("10", "100", "1000"):
        _, rows, err = run(ldaec, common + ["--method", "ode", "--rtol",
                                            "1e-9", "--stop", stop])
        drifts.append(stat(err, "largest drift residual"))
    check(all(d is not None for d in drifts) and
          drifts[0] < drifts[1] < drifts[2] and drifts[2] > 1e-8,
          "ode, rtol 1e-9: the drift grows over 10, 100, 1000 s "
          "(%s)" % ", ".join("%.2e" % d for d in drifts if d is not None))


def robertson(ldaec):
    ref = read_ref("robertson_ref.csv")
    times = ",".join(repr(r["time"]) for r in ref)
    _, rows, err = run(ldaec, [ROBERTSON, "--simulate", "--method", "sga",
                               "--rtol", "1e-8", "--atol", "1e-12",
                               "--output-times", times, "--stats"])
    rows = rows[1:]  # the start row; the reference begins at 0.4
    same_times(rows, ref)
    worst = 0
    for r, q in zip(rows, ref):
        for n in ("y1", "y2", "y3"):
            if q[n] > 1e-20:
                worst = max(worst, abs(r[n] - q[n]) / q[n])
    check(worst <= 1e-3, "Robertson, sga: y1, y2, y3 vs reference <= 1e-3 "
          "relative (max %.2e)" % worst)
    cons = max(abs(r["y1"] + r["y2"] + r["y3"] - 1) for r in rows)
    check(cons <= 1e-12, "Robertson, sga: |y1 + y2 + y3 - 1| <= 1e-12 "
          "(max %.2e)" % cons)
    check("Adams, then BDF" in err, "Robertson, auto: Adams moved to BDF")


def variable_length(ldaec):
    ref = read_ref("pendulum_var_ref.csv")
    _, rows, _ = run(ldaec, [
        os.path.join(HERE, "pendulum_variable_length.lsd"), "--simulate",
        "--method", "sga", "--rtol", "1e-10", "--outputs", "x,y,R"])
    same_times(rows, ref)
    pos = max(abs(r[n] - q[n]) for r, q in zip(rows, ref) for n in ("x", "y"))
    check(pos <= 1e-8, "variable length, sga: |x, y - polar| <= 1e-8 "
          "(max %.2e)" % pos)
    length = max(abs(r["x"]**2 + r["y"]**2 - r["R"]**2) for r in rows)
    check(length <= 1e-12, "variable length, sga: |x^2+y^2-R(t)^2| <= 1e-12 "
          "(max %.2e)" % length)


def andrews_closures(q):
    """The three loops' closure conditions g(q) = 0 of the test set (the
    last six equations of andrews.lsd), in metres."""
    rr, d, ss, e, zt, zf, u = 7e-3, 28e-3, 35e-3, 2e-2, 4e-2, 2e-2, 4e-2
    xa, ya, xb, yb = -0.06934, -0.00227, -0.03635, 0.03273
    be, th, ga, ph, de, om, ep = q
    x = rr * math.cos(be) - d * math.cos(be + th)
    y = rr * math.sin(be) - d * math.sin(be + th)
    return [x - ss * math.sin(ga) - xb,
            y + ss * math.cos(ga) - yb,
            x - e * math.sin(ph + de) - zt * math.cos(de) - xa,
            y + e * math.cos(ph + de) - zt * math.sin(de) - ya,
            x - zf * math.cos(om + ep) - u * math.sin(ep) - xa,
            y - zf * math.sin(om + ep) + u * math.cos(ep) - ya]


def andrews(ldaec):
    with open(BARI_REFERENCE) as f:
        prob = json.load(f)["andrews"]
    names, ref = prob["names"], prob["reference"]
    vmax = max(abs(v) for v in ref[7:])
    # CVODE bounds local errors by rtol; over the 0.03 s the mechanism's
    # fastest rate (466/s at the start) grows them about tenfold (measured:
    # 2 rtol at 1e-8, 8 rtol at 1e-10); 100 rtol leaves a decade for
    # platforms and still asks 8 digits at 1e-10, where SciPy's BDF on
    # the index-1 form reaches 6.8 (bench/bari/scipy_bdf.json).
    for tol in (1e-8, 1e-10):
        _, rows, err = run(ldaec, [
            os.path.join(HERE, "andrews.lsd"), "--simulate", "--method",
            "sga", "--rtol", repr(tol), "--atol", repr(tol), "--outputs",
            ",".join(names), "--stats"])
        last = rows[-1]
        check(abs(last["time"] - prob["t_end"]) <= 1e-12 and len(rows) == 31,
              "Andrews, sga, rtol %g: 31 rows to t = 0.03" % tol)
        qerr = max(abs(last[n] - r) / abs(r) for n, r in zip(names[:7],
                                                             ref[:7]))
        verr = max(abs(last[n] - r) for n, r in zip(names[7:], ref[7:]))
        verr /= vmax
        check(qerr <= 100 * tol and verr <= 100 * tol,
              "Andrews, sga, rtol %g: q within %g relative (%.2e), v within "
              "%g of max |v| (%.2e) of the test set's reference at t = 0.03"
              % (tol, 100 * tol, qerr, 100 * tol, verr))
        closure = max(abs(g) for r in rows for g in andrews_closures(
            [r["q[%d]" % i] for i in range(1, 8)]))
        check(closure <= 1e-10, "Andrews, sga, rtol %g: loop closures "
              "<= 1e-10 at every row (%.2e)" % (tol, closure))
        drift = stat(err, "largest drift residual")
        check(drift is not None and drift <= 1e-10,
              "Andrews, sga, rtol %g: largest drift residual %s <= 1e-10"
              % (tol, drift))
        check("CVODE (Adams), projected" in err,
              "Andrews, sga, auto: Adams throughout (not stiff)")


def main():
    ldaec = sys.argv[1]
    pendulum(ldaec)
    robertson(ldaec)
    variable_length(ldaec)
    andrews(ldaec)
    finish()


if __name__ == "__main__":
    main()
