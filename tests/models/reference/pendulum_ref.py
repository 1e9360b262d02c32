#!/usr/bin/python3
"""Reference solutions of the pendulum in polar form, independent of ldaec:
theta'' = -(g sin(theta) + 2 L'(t) theta') / L(t), with
L(t) = L0 (1 + eps sin(w t)), x = L sin(theta), y = -L cos(theta),
integrated with scipy's DOP853 at rtol = atol = 1e-13.
Writes pendulum_ref.csv (fixed length: eps = 0, theta0 = 1.5, omega0 = 0,
t = 0, 0.1, ..., 100) and pendulum_var_ref.csv (eps = 0.1, w = 1.3,
theta0 = 1.5, omega0 = 0, t = 0, 0.05, ..., 10): columns time, theta, x, y.
L0 = 1, g = 9.81, as the hand-written models in tests/unit/runtime.
Run once: /usr/bin/python3 pendulum_ref.py
"""
import csv
import os

import numpy as np
from scipy.integrate import solve_ivp

L0, G = 1.0, 9.81


def make(eps, w):
    def length(t):
        return (L0 * (1 + eps * np.sin(w * t)), L0 * eps * w * np.cos(w * t))

    def rhs(t, s):
        th, om = s
        L, dL = length(t)
        return [om, -(G * np.sin(th) + 2 * dL * om) / L]

    return rhs, length


def write(name, eps, w, theta0, omega0, stop, step):
    rhs, length = make(eps, w)
    n = int(round(stop / step))
    times = np.array([k * step for k in range(n + 1)])
    sol = solve_ivp(rhs, (0.0, stop), [theta0, omega0], method="DOP853",
                    t_eval=times, rtol=1e-13, atol=1e-13)
    assert sol.success, sol.message
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), name)
    with open(out, "w", newline="") as f:
        wr = csv.writer(f)
        wr.writerow(["time", "theta", "x", "y"])
        for t, th in zip(sol.t, sol.y[0]):
            L, _ = length(t)
            wr.writerow([repr(float(t)), repr(float(th)),
                         repr(float(L * np.sin(th))),
                         repr(float(-L * np.cos(th)))])


def main():
    write("pendulum_ref.csv", 0.0, 1.3, 1.5, 0.0, 100.0, 0.1)
    write("pendulum_var_ref.csv", 0.1, 1.3, 1.5, 0.0, 10.0, 0.05)


if __name__ == "__main__":
    main()
