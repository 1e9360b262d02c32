#!/usr/bin/python3
"""Reference solutions of the planar pendulum chain of bench/run_sga.py
(chain(n): n massless unit links, a unit point mass at the end of each,
hanging from the origin, g = 9.81, straight at the start at the angle
atan(0.6/0.8) from the downward vertical, at rest), independent of ldaec.

Integrated in minimal coordinates, the link angles theta_j from the
downward vertical (p_i = sum_{k<=i} (sin theta_k, -cos theta_k)): with
w_jk = n + 1 - max(j, k), the masses below both links,
  sum_k w_jk cos(theta_j - theta_k) theta_k''
    = -sum_k w_jk sin(theta_j - theta_k) theta_k'^2 - g (n + 1 - j) sin theta_j,
by SciPy's DOP853 at rtol = atol = 1e-13. Cross-checked against the
Cartesian index-1 form (the tensions from the acceleration constraints,
G G^T lam = |d_i'|^2 terms - G a_gravity, at every call) at the same
tolerances: the two must agree to 1e-9 at every output, else no file is
written.

Writes chain3_ref.csv and chain10_ref.csv: time, x1..xn, y1..yn at
t = 0, 0.1, ..., 10. Run once: /usr/bin/python3 chain_ref.py
"""
import csv
import math
import os

import numpy as np
from scipy.integrate import solve_ivp

G = 9.81
THETA0 = math.atan2(0.6, 0.8)
STOP, STEP = 10.0, 0.1
TOL = 1e-13


def angles_rhs(n):
    idx = np.arange(1, n + 1)
    w = n + 1 - np.maximum.outer(idx, idx)  # masses below both links
    below = n + 1 - idx

    def rhs(t, s):
        th, om = s[:n], s[n:]
        diff = np.subtract.outer(th, th)
        M = w * np.cos(diff)
        b = -(w * np.sin(diff)) @ (om * om) - G * below * np.sin(th)
        return np.concatenate([om, np.linalg.solve(M, b)])

    return rhs


def positions(th):
    return np.cumsum(np.sin(th)), np.cumsum(-np.cos(th))


def cartesian_rhs(n):
    """q = (x, y), links d_i = p_i - p_{i-1}; a = -G^T lam - g e_y with
    (G^T lam)_i = lam_i d_i - lam_{i+1} d_{i+1}; the second derivative of
    |d_i|^2 = 1 gives d_i . (a_i - a_{i-1}) + |d_i'|^2 = 0, linear in lam."""

    def links(p):
        return p - np.concatenate([[0.0], p[:-1]])

    def rhs(t, s):
        x, y, u, v = s[:n], s[n:2 * n], s[2 * n:3 * n], s[3 * n:]
        dx, dy, du, dv = links(x), links(y), links(u), links(v)
        # a_i = -lam_i d_i + lam_{i+1} d_{i+1} - g e_y; a_i - a_{i-1} =
        # -2 lam_i d_i + lam_{i+1} d_{i+1} + lam_{i-1} d_{i-1} (a_0 = 0:
        # the first row has -lam_1 d_1 + lam_2 d_2 - g e_y).
        K = np.zeros((n, n))
        rhs_ = -(du * du + dv * dv)
        for i in range(n):
            dot = lambda j: dx[i] * dx[j] + dy[i] * dy[j]
            K[i, i] = -(2.0 if i > 0 else 1.0) * dot(i)
            if i + 1 < n:
                K[i, i + 1] = dot(i + 1)
            if i > 0:
                K[i, i - 1] = dot(i - 1)
        rhs_[0] += G * dy[0]
        lam = np.linalg.solve(K, rhs_)
        lam_next = np.concatenate([lam[1:], [0.0]])
        dx_next = np.concatenate([dx[1:], [0.0]])
        dy_next = np.concatenate([dy[1:], [0.0]])
        ax = -lam * dx + lam_next * dx_next
        ay = -lam * dy + lam_next * dy_next - G
        return np.concatenate([u, v, ax, ay])

    return rhs


def solve(n):
    times = np.linspace(0.0, STOP, int(round(STOP / STEP)) + 1)
    th0 = np.full(n, THETA0)
    sol = solve_ivp(angles_rhs(n), (0.0, STOP),
                    np.concatenate([th0, np.zeros(n)]), method="DOP853",
                    t_eval=times, rtol=TOL, atol=TOL)
    assert sol.success, sol.message
    xs, ys = zip(*(positions(sol.y[:n, k]) for k in range(len(times))))
    x0, y0 = positions(th0)
    cart = solve_ivp(cartesian_rhs(n), (0.0, STOP),
                     np.concatenate([x0, y0, np.zeros(2 * n)]),
                     method="DOP853", t_eval=times, rtol=TOL, atol=TOL)
    assert cart.success, cart.message
    gap = max(np.max(np.abs(cart.y[:n].T - np.array(xs))),
              np.max(np.abs(cart.y[n:2 * n].T - np.array(ys))))
    print(f"chain {n}: angles vs Cartesian index-1 form: {gap:.2e}")
    assert gap < 1e-9, gap
    return times, np.array(xs), np.array(ys)


def write(n):
    times, xs, ys = solve(n)
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)),
                       f"chain{n}_ref.csv")
    with open(out, "w", newline="") as f:
        wr = csv.writer(f)
        wr.writerow(["time"] + [f"x{i}" for i in range(1, n + 1)] +
                    [f"y{i}" for i in range(1, n + 1)])
        for k, t in enumerate(times):
            wr.writerow([repr(float(t))] +
                        [repr(float(v)) for v in xs[k]] +
                        [repr(float(v)) for v in ys[k]])


def main():
    for n in (3, 10):
        write(n)


if __name__ == "__main__":
    main()
