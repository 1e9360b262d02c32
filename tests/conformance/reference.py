#!/usr/bin/env python3
"""Reference values for the conformance suite that are not read from a .mos
file: closed forms (each with its formula) and SciPy solve_ivp solutions.
None of them uses ldaec. `python3 reference.py` prints them all; the values
in manifest.json were computed by these functions."""
import math


def piecewise_linear(t):
    """discreteRelations.mos (PiecewiseLinear): x = sin t,
    x + (if y > 0 then 2y else y) - z = 0, 3x + y - 1 + z = 0.
    Adding the equations: y = (1 - 4x)/3 when that is > 0 (x < 1/4), else
    y = (1 - 4x)/2; z = 1 - 3x - y."""
    x = math.sin(t)
    y = (1 - 4 * x) / 3
    if not y > 0:
        y = (1 - 4 * x) / 2
    return x, y, 1 - 3 * x - y


if __name__ == "__main__":
    for t in (0.1, 1.0, 4.0, 6.0):
        print("piecewise_linear", t, piecewise_linear(t))
