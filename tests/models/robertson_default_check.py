#!/usr/bin/env python3
"""SUNDIALS' idaRoberts_dns example run by ldaec with the default error
test: tests/models/robertson_sundials.lsd at the example's own tolerances
(rtol 1e-4, atol 1e-8 / 1e-6 / 1e-6: --atol 1e-6 times the nominal values)
and at the times of every row idaRoberts_dns.out prints (0.4, 4, ..., 4e10
and its two root times), no --algebraic-error-test.

Every printed value must lie within FACTOR x the example's own error bound
(the weights of its check_ans: rtol |y| + 10 atol_i) plus half a unit in
the last printed digit (the .out has five significant digits).

Usage: robertson_default_check.py LDAEC [OPTION...]. Options after LDAEC
go to ldaec: the ctests give none (the causal form, y3 = 1 - y1 - y2
computed outside the integrator and error-tested through the weights of
y1 and y2, which makes the automatic choice IDA) and --causalize off (all
three unknowns to IDA, as in the example); tests/models/CMakeLists.txt.
Exits 77 (skipped) without the example's output. Standard library only.
"""
import os
import re
import sys

from check_e2e import SKIP, SUNDIALS_OUT, check, finish, run

HERE = os.path.dirname(os.path.abspath(__file__))
NAMES = ("y1", "y2", "y3")
# The printed values are themselves off the true solution
# (reference/robertson_ref.csv, Radau at rtol 1e-12) by up to 2.3 x that
# bound (y1 at t = 4e5); another step sequence of the same method at the
# same tolerances may be off the other way. 3 x passes such a run (ldaec
# with every unknown error-tested: 1.2 x at worst) and fails y3 left out
# of the error test (`--algebraic-error-test off`: 3.8 x at t = 0.4).
FACTOR = 3


def printed():
    """The tolerances and every (t, y1, y2, y3) row of the .out, as text
    (the number of printed digits is part of the bound)."""
    with open(SUNDIALS_OUT) as f:
        text = f.read()
    tol = re.search(r"rtol = (\S+)\s+atol = (\S+) (\S+) (\S+)", text)
    num = r"([0-9.]+e[+-][0-9]+)"
    rows = re.findall(r"^%s\s+%s\s+%s\s+%s\s+\|" % ((num,) * 4), text, re.M)
    return float(tol.group(1)), [float(a) for a in tol.groups()[1:]], rows


def half_unit(text):
    """Half a unit in the last digit of a printed number like 9.8517e-01."""
    mantissa, exponent = text.split("e")
    digits = len(mantissa.split(".")[1])
    return 0.5 * 10.0 ** (int(exponent) - digits)


def main():
    ldaec = sys.argv[1]
    if not os.path.exists(SUNDIALS_OUT):
        print("skipped: no " + SUNDIALS_OUT)
        sys.exit(SKIP)
    rtol, atol, ref = printed()
    check((rtol, atol) == (1e-4, [1e-8, 1e-6, 1e-6]) and len(ref) == 14,
          "idaRoberts_dns.out: rtol 1e-4, atol 1e-8 1e-6 1e-6, 14 rows "
          "(%g, %s, %d)" % (rtol, atol, len(ref)))
    times = ",".join(r[0] for r in ref)
    _, rows, _ = run(ldaec, [
        os.path.join(HERE, "robertson_sundials.lsd"), "--simulate",
        "--rtol", "1e-4", "--atol", "1e-6", "--output-times", times] +
        sys.argv[2:])
    rows = rows[1:]  # the start row
    check(len(rows) == len(ref) and all(
        abs(r["time"] - float(q[0])) <= 1e-9 * float(q[0])
        for r, q in zip(rows, ref)), "a row at each of the %d printed times"
        % len(ref))
    for r, q in zip(rows, ref):
        for i, name in enumerate(NAMES):
            want = float(q[1 + i])
            bound = (FACTOR * (rtol * abs(want) + 10 * atol[i]) +
                     half_unit(q[1 + i]))
            err = abs(r[name] - want)
            check(err <= bound, "%s(%s) = %.5e, printed %s: error %.2e, "
                  "bound %.2e (%.2f x)" % (name, q[0], r[name], q[1 + i],
                                            err, bound, err / bound))
    finish()


if __name__ == "__main__":
    main()
