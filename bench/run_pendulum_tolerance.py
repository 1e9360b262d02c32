#!/usr/bin/python3
"""What rtol 1e-9 buys on the Cartesian pendulum over 100 s (issue 14's
"--method sga --rtol 1e-9: x, y match the polar formulation to 1e-6").

The global error of a 100 s run at a fixed tolerance is a sum of local
errors with signs, so one start angle says little: this script runs 11
start angles theta0 in [1.40, 1.60] (rest, L = 1, g = 9.81, the swing
of examples/pendulum.lsd with --param theta0) and reports, per method,
the median and largest error in x, y over t = 0, 0.1, ..., 100 against
the polar ODE integrated by SciPy's DOP853 at 1e-13, and how many of the
11 are within 1e-6. Methods:
  - ldaec --method sga (the SGA's vector field, CVODE Adams, projected),
  - ldaec --method dd (the default: IDA, BDF),
  - ldaec on the polar ODE itself (the minimal coordinates: what no
    formulation of the constrained model can beat with the same
    integrator), --integrator cvode-adams,
  - SciPy's DOP853 and LSODA on the polar ODE at rtol = atol = the same
    tolerance (other integrators' error per tolerance),
  - SciPy's DOP853 on the Cartesian pendulum's vector field on P_f
    (lambda from the acceleration constraint), the step's end and every
    output row projected onto the position and velocity constraints:
    what an 8th-order explicit Runge-Kutta method in sga's place gives.

Usage: /usr/bin/python3 bench/run_pendulum_tolerance.py
           [--ldaec build/compiler/driver/ldaec] [--rtols 1e-9,1e-10] [--doc]
"""
import argparse
import csv
import io
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy.integrate import DOP853, solve_ivp

from benchdoc import write_section

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
G = 9.81
STOP, STEP = 100.0, 0.1
ANGLES = np.linspace(1.40, 1.60, 11)

POLAR = """model Polar
  parameter Real g = 9.81;
  parameter Real theta0 = 1.5;
  Real theta(start = theta0, fixed = true);
  Real omega(start = 0, fixed = true);
  Real x;
  Real y;
equation
  der(theta) = omega;
  der(omega) = -g * sin(theta);
  x = sin(theta);
  y = -cos(theta);
end Polar;
"""


def polar(theta0, times, method, rtol):
    sol = solve_ivp(lambda t, s: [s[1], -G * np.sin(s[0])], (0.0, STOP),
                    [theta0, 0.0], method=method, t_eval=times, rtol=rtol,
                    atol=rtol)
    assert sol.success, sol.message
    return np.sin(sol.y[0]), -np.cos(sol.y[0])


def cartesian_field(t, s):
    x, y, vx, vy = s
    lam = (vx * vx + vy * vy - G * y) / (x * x + y * y)
    return np.array([vx, vy, -lam * x, -lam * y - G])


def onto_constraints(s):
    """The nearest point of x^2 + y^2 = 1, x vx + y vy = 0."""
    r = np.hypot(s[0], s[1])
    x, y = s[0] / r, s[1] / r
    along = x * s[2] + y * s[3]
    return np.array([x, y, s[2] - along * x, s[3] - along * y])


def cartesian_projected(theta0, times, rtol):
    """DOP853 stepping through SciPy's solver interface; after each step
    the state is projected and the first stage (FSAL) re-evaluated there.
    """
    solver = DOP853(cartesian_field, 0.0,
                    np.array([np.sin(theta0), -np.cos(theta0), 0.0, 0.0]),
                    STOP, rtol=rtol, atol=rtol)
    rows, k = [solver.y[:2]], 1
    while solver.status == "running":
        solver.step()
        dense = solver.dense_output()
        solver.y = onto_constraints(solver.y)
        solver.f = cartesian_field(solver.t, solver.y)
        for k in range(k, len(times)):
            if times[k] > solver.t:
                break
            rows.append(onto_constraints(dense(times[k]))[:2])
        else:
            k = len(times)
    rows = np.array(rows)
    return rows[:, 0], rows[:, 1]


def ldaec_xy(ldaec, model, theta0, rtol, extra):
    cmd = [ldaec, model, "--simulate", "--param", "theta0=%r" % theta0,
           "--stop", str(STOP), "--interval", str(STEP), "--rtol", rtol,
           "--outputs", "x,y", "--stats", "-o", "-"] + extra
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    if run.returncode != 0:
        return None, None
    rows = list(csv.DictReader(io.StringIO(run.stdout)))
    steps = next(int(line.split()[-1]) for line in run.stderr.splitlines()
                 if line.startswith("steps "))
    return (np.array([float(r["x"]) for r in rows]),
            np.array([float(r["y"]) for r in rows])), steps


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ldaec", default=os.path.join(
        ROOT, "build", "compiler", "driver", "ldaec"))
    ap.add_argument("--rtols", default="1e-9,1e-10")
    ap.add_argument("--doc", action="store_true",
                    help="write the section into docs/benchmarks.md")
    args = ap.parse_args()
    if args.doc:
        os.environ["LDAE_BENCH_DOC"] = "1"

    times = np.linspace(0.0, STOP, int(round(STOP / STEP)) + 1)
    refs = [polar(th, times, "DOP853", 1e-13) for th in ANGLES]
    tmp = tempfile.mkdtemp(prefix="ldaec-pendtol-")
    polar_model = os.path.join(tmp, "polar.lsd")
    with open(polar_model, "w") as f:
        f.write(POLAR)
    pendulum = os.path.join(ROOT, "examples", "pendulum.lsd")
    methods = [
        ("ldaec --method sga", pendulum, ["--method", "sga"]),
        ("ldaec --method dd", pendulum, []),
        ("ldaec, polar ODE, CVODE Adams", polar_model,
         ["--integrator", "cvode-adams"]),
        ("SciPy DOP853, polar ODE", "DOP853", None),
        ("SciPy LSODA, polar ODE", "LSODA", None),
        ("SciPy DOP853, Cartesian on P_f, projected", cartesian_projected,
         None),
    ]

    lines = []
    for rtol in args.rtols.split(","):
        lines.append("")
        lines.append("rtol = atol = %s:" % rtol)
        lines.append("")
        lines.append("| method | median error | largest | within 1e-6 | "
                     "median steps |")
        lines.append("|---|---|---|---|---|")
        for name, what, extra in methods:
            errors, steps = [], []
            for th, (rx, ry) in zip(ANGLES, refs):
                if callable(what):
                    xy, n = what(th, times, float(rtol)), None
                elif extra is None:
                    xy, n = polar(th, times, what, float(rtol)), None
                else:
                    xy, n = ldaec_xy(args.ldaec, what, th, rtol, extra)
                if xy is None:
                    errors.append(float("inf"))
                    continue
                errors.append(max(np.abs(xy[0] - rx).max(),
                                  np.abs(xy[1] - ry).max()))
                if n is not None:
                    steps.append(n)
            e = np.array(errors)
            lines.append("| %s | %.2e | %.2e | %d of %d | %s |" % (
                name, np.median(e), e.max(), (e <= 1e-6).sum(), len(e),
                "%d" % np.median(steps) if steps else "n/a"))
            print(lines[-1], file=sys.stderr)

    section = "\n".join([
        "## Pendulum: what rtol 1e-9 buys (issue 14)",
        "",
        "`bench/run_pendulum_tolerance.py`: the Cartesian pendulum "
        "(examples/pendulum.lsd) from rest at 11 angles theta0 in "
        "[1.40, 1.60], 100 s; the error is the largest |x, y - polar| "
        "over the 1001 rows, the polar reference DOP853 at 1e-13. The "
        "error of one 100 s run at one tolerance is a sum of local errors "
        "with signs, so a single angle says little (at theta0 = 1.5 sga "
        "is 1.4e-6 at 1e-9, the polar ODE with the same CVODE Adams "
        "1.25e-6 in plain C and 2.5e-7 through ldaec's weights).",
    ] + lines + [
        "",
        "The issue asks sga for 1e-6 at rtol 1e-9. Nothing built on CVODE "
        "reaches that reliably, not even on the minimal coordinates: see "
        "the polar ODE's own row. Among SciPy's integrators on the polar "
        "ODE only DOP853 comes close (its error estimate combines a 5th- "
        "and a 3rd-order one), and on the constrained model, the field on "
        "P_f projected after every step as sga does, it does not: its last "
        "row. An error controlled per step adds up over the run's "
        "thousands of steps; 1e-6 after 100 s needs rtol 1e-10, where sga "
        "meets it at every angle (ctest `model.sga_methods` at theta0 = "
        "1.5); docs/runtime.md discusses it.",
    ])
    write_section(os.path.join(ROOT, "docs", "benchmarks.md"),
                  "Pendulum: what rtol 1e-9 buys (issue 14)", section)


if __name__ == "__main__":
    main()
