#!/usr/bin/env python3
"""Checks tests/models/cascaded_first_order.lsd (ScalableTestSuite's
CascadedFirstOrder) against its closed form.

N equal lags tau x'[i] = x[i-1] - x[i] driven by the unit step x[0] = 1
from rest: x[i] is the Erlang distribution function of order i and rate
1 / tau, x[i](t) = P(i, t / tau), the regularized lower incomplete gamma
function (erlang_cdf below; bench/run_cascaded.py uses it too).

1. N = 100 at the experiment's Tolerance 1e-6 (atol = rtol, ldaec's
   default), 501 rows to StopTime 2: every x[i] at every row within
   100 x rtol of P(i, t / tau).
2. N = 100 at rtol = atol = 1e-10: every value within 1e-7.

Usage: cascaded_check.py LDAEC MODEL. Standard library only.
"""
import math
import sys

from check_e2e import check, finish, run

# The global error of a BDF run grows past the local tolerance along the
# chain and over 200 time constants: at N = 100 the hand-written SUNDIALS
# programs (bench/cascaded_*.c) reach 1.8e-5 (IDA) and 2.3e-5 (CVODE) at
# rtol 1e-6, 8e-9 at rtol 1e-10, ldaec the same. The bounds leave room for
# other step sequences (4x and 10x) and still fail a wrong model: a
# coefficient off by 1% moves x[i] by 1e-3 and more.
BOUNDS = ((1e-6, 1e-4), (1e-10, 1e-7))  # (rtol = atol, largest error)


def poisson_term(k, x):
    """e^-x x^k / k!, by logarithms (x up to a few 10^5 and k alike)."""
    if x == 0:
        return 1.0 if k == 0 else 0.0
    return math.exp(k * math.log(x) - x - math.lgamma(k + 1))


def erlang_cdf(n, x):
    """P(n, x) for a positive integer n: the probability of at least n
    Poisson events of mean x. Sums whichever tail is short and decreasing,
    so both small and large values keep their absolute accuracy."""
    if x <= 0:
        return 0.0
    if x < n:  # terms k >= n decrease: the upper tail of the Poisson sum
        total, k = 0.0, n
        while True:
            term = poisson_term(k, x)
            total += term
            if term <= 1e-18 * total:  # also a first term below 1e-308
                return total
            k += 1
    # Terms k < n increase towards k = n - 1: sum from there downwards.
    total = 0.0
    for k in range(n - 1, -1, -1):
        term = poisson_term(k, x)
        total += term
        if term <= 1e-18 * total:
            break
    return 1.0 - total


def max_error(rows, n, tau=None):
    """The largest |x[i](t) - P(i, t / tau)| over the rows and every x[i]
    the rows hold (tau = 1 / n, the model's T = 1)."""
    tau = tau or 1.0 / n
    worst = 0.0
    for row in rows:
        for name, value in row.items():
            if name.startswith("x["):
                i = int(name[2:-1])
                worst = max(worst, abs(value - erlang_cdf(i, row["time"] / tau)))
    return worst


def main():
    ldaec, model = sys.argv[1], sys.argv[2]
    n = 100
    for rtol, bound in BOUNDS:
        tolerances = ([] if rtol == 1e-6 else  # the experiment's Tolerance
                      ["--rtol", repr(rtol), "--atol", repr(rtol)])
        _, rows, _ = run(ldaec, [model, "--simulate", "--param", "N=%d" % n]
                         + tolerances)
        check(len(rows) == 501 and abs(rows[-1]["time"] - 2) < 1e-12,
              "501 rows from 0 to StopTime 2 (%d)" % len(rows))
        check(all("x[%d]" % i in rows[0] for i in range(1, n + 1)),
              "x[1] ... x[%d] written" % n)
        err = max_error(rows, n)
        check(err <= bound, "rtol %g: |x[i] - P(i, t/tau)| <= %g at every "
              "row (max %.2e)" % (rtol, bound, err))
    finish()


if __name__ == "__main__":
    main()
