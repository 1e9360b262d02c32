#!/usr/bin/env python3
"""Checks tests/models/heat2d.lsd (SUNDIALS' idaHeat2D form).

1. N = 10 (SUNDIALS' grid): the max norm of u at t = 0 and t = 0.01 equals
   the one idaHeat2D_klu.out prints (9.75461e-01, 8.24056e-01; 6 digits).
2. N = 40 (1,444 interior unknowns: the sparse initialization): u at
   t = 0.01 equals the exact solution of the semi-discrete system, computed
   here by the discrete sine transform (the eigenvectors of the 5-point
   Laplacian with zero boundary values), to 1e-6; the log names the sparse
   path.
3. heat2d_tied.lsd (36 interior unknowns, initial equations in y and y'):
   u[2,2] + u[3,3] = 1 from starts 0 gives 0.5 each (the minimum-norm move
   of the tied block), der(u[4,4]) = 0 makes u[4,4] the mean of its
   neighbours, every other value the initial profile.

Usage: heat2d_check.py LDAEC MODEL (heat2d.lsd; heat2d_tied.lsd is read from
its folder). Standard library only.
"""
import math
import os
import sys

from check_e2e import check, finish, run


def simulate(ldaec, model, n, extra=()):
    """The CSV rows and the log of one run (a failed run ends the check)."""
    _, rows, log = run(ldaec, [model, "--simulate", "--param", "N=%d" % n,
                               "--rtol", "1e-10", "--atol", "1e-10"] +
                       list(extra))
    return rows, log


def value(row, i, j):
    """u[i,j] (1-based); boundary values alias elimination removed are 0."""
    return row.get("u[%d,%d]" % (i, j), 0.0)


def exact(n, t):
    """The semi-discrete solution at t on the interior of an n x n grid."""
    m = n - 2
    dx = 1.0 / (n - 1)
    s = [[math.sin(math.pi * k * i / (n - 1)) for i in range(1, m + 1)]
         for k in range(1, m + 1)]
    lam = [(2 - 2 * math.cos(math.pi * k / (n - 1))) / dx ** 2
           for k in range(1, m + 1)]
    x = [i * dx for i in range(1, m + 1)]
    u0 = [[16 * a * (1 - a) * b * (1 - b) for b in x] for a in x]
    # Coefficients c[k][l] = (2/(n-1))^2 sum_ij s[k][i] s[l][j] u0[i][j].
    norm = (2.0 / (n - 1)) ** 2
    tmp = [[sum(s[l][j] * u0[i][j] for j in range(m)) for l in range(m)]
           for i in range(m)]
    c = [[norm * sum(s[k][i] * tmp[i][l] for i in range(m)) for l in range(m)]
         for k in range(m)]
    for k in range(m):
        for l in range(m):
            c[k][l] *= math.exp(-(lam[k] + lam[l]) * t)
    tmp = [[sum(c[k][l] * s[l][j] for l in range(m)) for j in range(m)]
           for k in range(m)]
    return [[sum(s[k][i] * tmp[k][j] for k in range(m)) for j in range(m)]
            for i in range(m)]


def main():
    ldaec, model = sys.argv[1], sys.argv[2]
    rows, _ = simulate(ldaec, model, 10)
    if rows:
        for row, ref in ((rows[0], 9.75461e-01), (rows[-1], 8.24056e-01)):
            umax = max(abs(value(row, i, j)) for i in range(1, 11)
                       for j in range(1, 11))
            check(abs(umax - ref) <= 6e-6,
                  "N = 10, t = %g: max |u| %.7f, idaHeat2D_klu.out %.6f" %
                  (row["time"], umax, ref))
    n = 40
    rows, log = simulate(ldaec, model, n)
    if rows:
        check("sparse Newton iteration" in log,
              "N = 40: initialized by the sparse path")
        ref = exact(n, rows[-1]["time"])
        err = max(abs(value(rows[-1], i + 2, j + 2) - ref[i][j])
                  for i in range(n - 2) for j in range(n - 2))
        check(abs(rows[-1]["time"] - 0.01) < 1e-12 and err <= 1e-6,
              "N = 40, t = 0.01: max error vs the exact semi-discrete "
              "solution %.2e" % err)
    tied = os.path.join(os.path.dirname(model), "heat2d_tied.lsd")
    rows, log = simulate(ldaec, tied, 8, ["--stop", "0"])
    if rows:
        r = rows[0]
        check("(1 in minimum-norm blocks)" in log,
              "tied: one minimum-norm block")
        check(abs(value(r, 2, 2) - 0.5) < 1e-12 and
              abs(value(r, 3, 3) - 0.5) < 1e-12,
              "tied: u[2,2] = %.15g, u[3,3] = %.15g (0.5 each)" %
              (value(r, 2, 2), value(r, 3, 3)))
        mean = (value(r, 3, 4) + value(r, 5, 4) + value(r, 4, 3) +
                value(r, 4, 5)) / 4
        check(abs(value(r, 4, 4) - mean) < 1e-12,
              "tied: u[4,4] = %.15g, the mean of its neighbours %.15g" %
              (value(r, 4, 4), mean))
        dx = 1.0 / 7
        worst = max(abs(value(r, i, j) - 16 * (i - 1) * dx * (1 - (i - 1) * dx)
                        * (j - 1) * dx * (1 - (j - 1) * dx))
                    for i in range(2, 8) for j in range(2, 8)
                    if (i, j) not in ((2, 2), (3, 3), (4, 4)))
        check(worst < 1e-12, "tied: the other values on the profile "
              "(largest difference %.1e)" % worst)
    finish()


if __name__ == "__main__":
    main()
