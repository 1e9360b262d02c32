#!/usr/bin/python3
"""Reference solution of the Robertson kinetics problem (as in SUNDIALS'
idaRoberts_dns.c), computed independently of ldaec and SUNDIALS: the DAE
written as its underlying ODE (y3 = 1 - y1 - y2 substituted) and integrated
with scipy's Radau at rtol 1e-12, atol 1e-20 (y2 falls to 1e-13).
Writes robertson_ref.csv: t, y1, y2, y3 at t = 0.4 * 10^k, k = 0..11.
Run once: /usr/bin/python3 robertson_ref.py
"""
import csv
import os

import numpy as np
from scipy.integrate import solve_ivp


def rhs(t, y):
    y1, y2 = y
    y3 = 1.0 - y1 - y2
    d1 = -0.04 * y1 + 1.0e4 * y2 * y3
    d2 = 0.04 * y1 - 1.0e4 * y2 * y3 - 3.0e7 * y2 * y2
    return [d1, d2]


def jac(t, y):
    y1, y2 = y
    y3 = 1.0 - y1 - y2
    return [[-0.04 - 1.0e4 * y2, 1.0e4 * y3 - 1.0e4 * y2],
            [0.04 + 1.0e4 * y2, -1.0e4 * y3 + 1.0e4 * y2 - 6.0e7 * y2]]


def main():
    times = [0.4 * 10.0 ** k for k in range(12)]
    sol = solve_ivp(rhs, (0.0, times[-1]), [1.0, 0.0], method="Radau",
                    t_eval=times, rtol=1e-12, atol=[1e-20, 1e-24], jac=jac)
    assert sol.success, sol.message
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)),
                       "robertson_ref.csv")
    with open(out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "y1", "y2", "y3"])
        for t, y1, y2 in zip(sol.t, sol.y[0], sol.y[1]):
            w.writerow([repr(float(t)), repr(float(y1)), repr(float(y2)),
                        repr(float(1.0 - y1 - y2))])


if __name__ == "__main__":
    main()
