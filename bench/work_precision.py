#!/usr/bin/python3
"""Work-precision charts: for each model and method, sweep --rtol from 1e-3
to 1e-10, run the built `ldaec` (`ldaec model.lsd --simulate --method M
--rtol R --stats -o out.csv`), measure the error against an independent
reference (scipy, tests/models/reference/*_ref.py) and the wall time, and
draw error vs time (log-log, one curve per method) to PNG with a CSV table
beside it.

Usage: /usr/bin/python3 bench/work_precision.py [--ldaec build/compiler/driver/ldaec]
           [--doc | --out DIR] [--models pendulum,robertson]
           [--methods dd,dd+ida,dd+alg-off,raw,sga,sga+cvode-bdf,ode]
A method is `--method M` optionally followed by variants: `+ida`, `+cvode`,
`+cvode-bdf`, `+cvode-adams` (--integrator), `+alg-off`
(--algebraic-error-test off), `+uncausal` (--causalize off). `sga` is the
SGA's vector field on P_f with CVODE projected onto the constraints (Adams
by default, moving to BDF when stiff; `+cvode-bdf` forces BDF with
CVodeSetProjFn), `ode` the same without projection (its drift). Without --doc or --out the table and chart
go to a temporary directory (tracked files are rewritten only when asked).
A run that fails (non-zero exit status) is listed in the table with its
status and left out of the chart.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.integrate import solve_ivp

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "models", "reference"))
import pendulum_ref  # noqa: E402  (the same formulas as the committed tables)
import robertson_ref  # noqa: E402

RTOLS = [10.0 ** -k for k in range(3, 11)]
TIMEOUT = 120  # seconds per run; a run that takes longer is listed as "timeout"


def pendulum_reference(times, theta0=0.5):
    """x, y of the pendulum in examples/pendulum.lsd (L = 1, g = 9.81, at
    rest at theta0) from the polar equation, DOP853 at 1e-13."""
    rhs, length = pendulum_ref.make(0.0, 1.0)
    sol = solve_ivp(rhs, (0.0, times[-1]), [theta0, 0.0], method="DOP853",
                    t_eval=times, rtol=1e-13, atol=1e-13)
    th = sol.y[0]
    return {"x": np.sin(th), "y": -np.cos(th)}


def robertson_reference(times):
    """y1, y2, y3 of examples/robertson.lsd from Radau at rtol 1e-12."""
    sol = solve_ivp(robertson_ref.rhs, (0.0, times[-1]), [1.0, 0.0],
                    method="Radau", t_eval=times, rtol=1e-12,
                    atol=[1e-20, 1e-24], jac=robertson_ref.jac)
    y1, y2 = sol.y
    return {"y1": y1, "y2": y2, "y3": 1.0 - y1 - y2}


MODELS = {
    # name: (file, extra arguments, reference, error floor per column)
    "pendulum": ("examples/pendulum.lsd", ["--stop", "10", "--interval", "0.05"],
                 pendulum_reference, {"x": 1.0, "y": 1.0}),
    "robertson": ("examples/robertson.lsd", ["--stop", "4e5", "--interval", "800"],
                  robertson_reference, {"y1": 1e-6, "y2": 1e-11, "y3": 1e-6}),
}


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header, data = rows[0], np.array([[float(v) for v in r] for r in rows[1:]])
    return {name: data[:, i] for i, name in enumerate(header)}


def error(result, reference, floors):
    """Largest error over the reported rows, relative to |ref| + floor."""
    worst = 0.0
    for name, floor in floors.items():
        if name not in result:
            continue
        d = np.abs(result[name] - reference[name]) / (np.abs(reference[name]) + floor)
        worst = max(worst, float(np.max(d)))
    return worst


VARIANTS = {"ida": ["--integrator", "ida"], "cvode": ["--integrator", "cvode"],
            "cvode-bdf": ["--integrator", "cvode-bdf"],
            "cvode-adams": ["--integrator", "cvode-adams"],
            "alg-off": ["--algebraic-error-test", "off"],
            "uncausal": ["--causalize", "off"]}


def method_args(spec):
    """`dd+ida+alg-off` -> --method dd --integrator ida --algebraic-error-test off."""
    method, *variants = spec.split("+")
    args = ["--method", method]
    for v in variants:
        args += VARIANTS[v]
    return args


def run(ldaec, model, method, rtol, extra, tmp):
    out = os.path.join(tmp, "out.csv")
    cmd = [ldaec, os.path.join(ROOT, model), "--simulate"] + method_args(method) + [
           "--rtol", repr(rtol), "--stats", "-o", out] + extra
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return "timeout", time.perf_counter() - t0, out, None, ""
    wall = time.perf_counter() - t0
    text = p.stdout + p.stderr
    steps = re.search(r"steps\s+(\d+)", text)
    # The integration's own wall time from --stats (the process time adds
    # parsing and compilation); the process time if it is missing.
    sim = re.search(r"wall time\s+([0-9.eE+-]+) s", text)
    wall = float(sim.group(1)) if sim else wall
    return p.returncode, wall, out, int(steps.group(1)) if steps else None, p.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ldaec", default=os.path.join(ROOT, "build", "compiler", "driver", "ldaec"))
    ap.add_argument("--out", default=None)
    ap.add_argument("--doc", action="store_true",
                    help="write the tables and charts into docs/")
    ap.add_argument("--models", default="pendulum,robertson")
    ap.add_argument("--methods",
                    default="dd,dd+ida,dd+alg-off,raw,sga,sga+cvode-bdf,ode")
    args = ap.parse_args()
    if args.out is None:
        args.out = (os.path.join(ROOT, "docs") if args.doc
                    else tempfile.mkdtemp(prefix="work_precision."))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(args.out, exist_ok=True)
    for name in args.models.split(","):
        model, extra, reference, floors = MODELS[name]
        table = []
        with tempfile.TemporaryDirectory() as tmp:
            ref_cache = None
            for method in args.methods.split(","):
                for rtol in RTOLS:
                    status, wall, out, steps, err_text = run(
                        args.ldaec, model, method, rtol, extra, tmp)
                    err = None
                    if status == 0 and os.path.exists(out):
                        result = read_csv(out)
                        if ref_cache is None or len(ref_cache[0]) != len(result["time"]) \
                                or not np.allclose(ref_cache[0], result["time"]):
                            ref_cache = (result["time"], reference(result["time"]))
                        err = error(result, ref_cache[1], floors)
                    table.append({"model": name, "method": method, "rtol": rtol,
                                  "status": status, "wall_s": wall, "steps": steps,
                                  "error": err})
                    print(f"{name:10s} {method:13s} rtol={rtol:.0e} status={status} "
                          f"time={wall:.3f}s error={err}", flush=True)
                    if status not in (0, 3, "timeout"):
                        print(err_text.strip()[:300], file=sys.stderr)
        csv_path = os.path.join(args.out, f"work_precision_{name}.csv")
        with open(csv_path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(table[0].keys()))
            w.writeheader()
            w.writerows(table)
        fig, ax = plt.subplots(figsize=(7, 5))
        for method in args.methods.split(","):
            pts = [(r["wall_s"], r["error"]) for r in table
                   if r["method"] == method and r["error"] is not None and r["error"] > 0]
            if pts:
                xs, ys = zip(*pts)
                ax.loglog(xs, ys, "o-", label=method)
        ax.set_xlabel("integration wall time (s, from --stats)")
        ax.set_ylabel("max relative error vs reference")
        ax.set_title(f"work-precision: {name} (rtol 1e-3 .. 1e-10)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, f"work_precision_{name}.png"), dpi=110)
        print(f"wrote {csv_path} and the chart beside it")


if __name__ == "__main__":
    main()
