#!/usr/bin/python3
"""Significant correct digits (scd) on problems of the Bari Test Set for IVP
Solvers: SciPy's BDF on an ODE form of each (bench/bari/problems.py)
against ldaec on the models as their users write them: Andrews' squeezing
mechanism and the car axis (index 3: tests/models/andrews.lsd,
car_axis.lsd), HIRES (tests/models/hires.lsd), the Chemical Akzo Nobel
problem (index 1: tests/models/chemakzo.lsd) and the transistor amplifier
(index 1 with a singular capacitor matrix: tests/models/sga/transamp.lsd),
all at rtol = atol = 1e-6, 1e-8, 1e-10.

scd = -log10(max relative error at the end time) over the components the
test set's getscd uses: andrews the 7 positions, every other problem all
of its components (caraxis: positions, velocities, multipliers, its
positions-only scd reported too). Reference solutions:
bench/bari/reference.json.

Usage: scd.py [--ldaec PATH] [--json] [--doc]
  --json   writes bench/bari/scipy_bdf.json (SciPy's scd per problem and
           tolerance, read by the ctest model.bari_scd)
  --doc    writes the table into docs/validation.md
Needs numpy and scipy (Debian: python3-scipy).
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.integrate import solve_ivp

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import problems  # noqa: E402

TOLS = [1e-6, 1e-8, 1e-10]
DOC = os.path.join(ROOT, "docs", "validation.md")


def load_reference():
    with open(os.path.join(HERE, "reference.json")) as f:
        return json.load(f)


def scd(values, ref, ncomp):
    """The test set's scd: -log10 of the largest relative error."""
    err = max(abs(v - r) / abs(r) for v, r in zip(values[:ncomp],
                                                 ref[:ncomp]))
    return -math.log10(max(err, 1e-16))


# name: (rhs(t, y), y0, t_end, the compared components from (t, y at the
# end), how many of them are positions (reported apart), or None)
SCIPY_FORMS = {
    "andrews": (lambda t, y: problems.andrews_rhs(t, y),
                problems.andrews_y0, 0.03,
                lambda t, y: problems.andrews_full(y), 7),
    "caraxis": (problems.caraxis_rhs, problems.caraxis_y0, 3.0,
                problems.caraxis_full, 4),
    "hires": (problems.hires_rhs, problems.hires_y0, 321.8122,
              lambda t, y: list(y), None),
    "chemakzo": (problems.chemakzo_rhs, problems.chemakzo_y0, 180.0,
                 lambda t, y: problems.chemakzo_full(y), None),
    "transamp": (problems.transamp_rhs, problems.transamp_y0, 0.2,
                 problems.transamp_full, None),
}
# Positions-only scd is reported for the mechanisms whose scd is not it.
POSITIONS_REPORTED = ("caraxis",)


def run_scipy(name, tol):
    """(full end vector, seconds, steps) of BDF on the ODE form."""
    rhs, y0, t_end, full, _ = SCIPY_FORMS[name]
    start = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, t_end), y0(), method="BDF", rtol=tol,
                    atol=tol)
    seconds = time.perf_counter() - start
    if not sol.success:
        raise RuntimeError("%s at tol %g: %s" % (name, tol, sol.message))
    return full(t_end, sol.y[:, -1]), seconds, len(sol.t) - 1


def run_ldaec(ldaec, problem, tol):
    """(end vector in the reference's order, seconds, []) of ldaec
    --simulate, or (None, seconds, stderr lines) when it fails; seconds =
    (the whole run, the simulator's own wall time from --stats)."""
    model = os.path.join(ROOT, problem["model"])
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.csv")
        start = time.perf_counter()
        proc = subprocess.run(
            [ldaec, "--no-progress", model, "--simulate", "--rtol", repr(tol),
             "--atol", repr(tol), "--outputs", ",".join(problem["names"]),
             "--stats", "-o", out], capture_output=True, text=True,
            timeout=600)
        seconds = (time.perf_counter() - start, None)
        if proc.returncode != 0:
            return None, seconds, proc.stderr.strip().splitlines()
        m = re.search(r"^wall time\s+([0-9.eE+-]+)", proc.stderr, re.M)
        seconds = (seconds[0], float(m.group(1)) if m else None)
        with open(out) as f:
            last = list(csv.DictReader(f))[-1]
    if abs(float(last["time"]) - problem["t_end"]) > 1e-12:
        return None, seconds, ["last row at t = %s" % last["time"]]
    return [float(last[n]) for n in problem["names"]], seconds, []


def measure(ldaec):
    refs = load_reference()
    rows = []
    for name in SCIPY_FORMS:
        problem = refs[name]
        ref, ncomp = problem["reference"], problem["scd_components"]
        npos = SCIPY_FORMS[name][4] or ncomp
        for tol in TOLS:
            full, secs, steps = run_scipy(name, tol)
            row = {"problem": name, "tol": tol,
                   "scipy_scd": scd(full, ref, ncomp),
                   "scipy_pos_scd": scd(full, ref, npos),
                   "scipy_seconds": secs, "scipy_steps": steps}
            if ldaec:
                vals, secs, err = run_ldaec(ldaec, problem, tol)
                row["ldaec_seconds"], row["ldaec_sim_seconds"] = secs
                if vals is None:
                    errors = [l for l in err if "error:" in l] or err
                    row["ldaec_error"] = (errors[0].split("error: ", 1)[-1]
                                          if errors else "failed")
                    row["ldaec_stderr"] = err
                else:
                    row["ldaec_scd"] = scd(vals, ref, ncomp)
                    row["ldaec_pos_scd"] = scd(vals, ref, npos)
            rows.append(row)
            print(json.dumps({k: v for k, v in row.items()
                              if k != "ldaec_stderr"}), flush=True)
    return rows


def table(rows):
    lines = [
        "| problem | rtol = atol | SciPy BDF scd | SciPy BDF time (s) "
        "| ldaec scd | ldaec time (s): whole run (simulation) |",
        "|---|---:|---:|---:|---:|---:|"]
    for r in rows:
        if "ldaec_scd" in r:
            ours = "%.2f" % r["ldaec_scd"]
            if r["problem"] in POSITIONS_REPORTED:
                ours += " (positions %.2f)" % r["ldaec_pos_scd"]
        else:
            ours = "fails: %s" % r.get("ldaec_error", "not run")
        theirs = "%.2f" % r["scipy_scd"]
        if r["problem"] in POSITIONS_REPORTED:
            theirs += " (positions %.2f)" % r["scipy_pos_scd"]
        secs = "-"
        if "ldaec_seconds" in r:
            secs = "%.3f" % r["ldaec_seconds"]
            if r.get("ldaec_sim_seconds") is not None:
                secs += " (%.3f)" % r["ldaec_sim_seconds"]
        lines.append("| %s | %g | %s | %.3f | %s | %s |" % (
            r["problem"], r["tol"], theirs, r["scipy_seconds"], ours, secs))
    return "\n".join(lines)


def write_doc(rows):
    marker_start = "<!-- bari-scd-table -->"
    marker_end = "<!-- /bari-scd-table -->"
    text = open(DOC).read()
    head, rest = text.split(marker_start, 1)
    _, tail = rest.split(marker_end, 1)
    stamp = "Measured %s by `bench/bari/scd.py --doc`, load average %.2f." % (
        time.strftime("%Y-%m-%d"), os.getloadavg()[0])
    with open(DOC, "w") as f:
        f.write(head + marker_start + "\n" + stamp + "\n\n" + table(rows) +
                "\n" + marker_end + tail)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ldaec", help="the ldaec binary (omit: SciPy only)")
    ap.add_argument("--json", action="store_true",
                    help="write bench/bari/scipy_bdf.json")
    ap.add_argument("--doc", action="store_true",
                    help="write the table into docs/validation.md")
    args = ap.parse_args()
    rows = measure(args.ldaec)
    print(table(rows))
    if args.json:
        data = {"_made_by": "bench/bari/scd.py --json (SciPy %s, BDF on an "
                "ODE form, bench/bari/problems.py)" % __import__("scipy").__version__,
                "scd": {}}
        for r in rows:
            data["scd"].setdefault(r["problem"], {})[repr(r["tol"])] = round(
                r["scipy_scd"], 3)
        with open(os.path.join(HERE, "scipy_bdf.json"), "w") as f:
            json.dump(data, f, indent=2)
            f.write("\n")
    if args.doc:
        write_doc(rows)


if __name__ == "__main__":
    main()
