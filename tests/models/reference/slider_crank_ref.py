#!/usr/bin/python3
"""Reference solution of SUNDIALS' slider crank (idaSlCrank_dns.c) at its 41
output times, independent of ldaec: the index-1 ODE form (positions and
velocities; accelerations and multipliers from
[M G'; G 0] [a; lambda] = [Q; -gamma] at each call) integrated with
SciPy's DOP853 at rtol = atol = 1e-13. Writes slider_crank_ref.csv
(time, q, x, p). Parameters and initial values of the example's main and
setIC: a = 0.5, J1 = 1, m2 = 1, J2 = 2, k = 1, c = 1, l0 = 1, F = 1,
q = pi/2, p = asin(-a), x = cos(p), velocities 0.
"""
import math
import os

import numpy as np
from scipy.integrate import solve_ivp

a, J1, m2, J2, k, c, l0, F = 0.5, 1.0, 1.0, 2.0, 1.0, 1.0, 1.0, 1.0


def forces(q, x, p, qd, xd, pd):
    """The example's force(): generalized forces of the spring-damper
    between crank and rod and of the constant force on the rod."""
    s1, c1, s2, c2 = math.sin(q), math.cos(q), math.sin(p), math.cos(p)
    s21, c21 = s2*c1 - c2*s1, c2*c1 + s2*s1
    l = math.sqrt(x*x - x*(c2 + a*c1) + (1 + a*a)/4 + a*c21/2)
    ld = (2*x*xd - xd*(c2 + a*c1) + x*(s2*pd + a*s1*qd)
          - a*s21*(pd - qd)/2) / (2*l)
    fl = (k*(l - l0) + c*ld) / l
    return np.array([-fl*a*(s21/2 + x*s1)/2,
                     fl*(c2/2 - x + a*c1/2) + F,
                     -fl*(x*s2 - a*s21/2)/2 - F*s2])


def rhs(t, y):
    q, x, p, qd, xd, pd = y
    s1, c1, s2, c2 = math.sin(q), math.cos(q), math.sin(p), math.cos(p)
    # Constraints x - cos p - a cos q = 0, -sin p - a sin q = 0.
    G = np.array([[a*s1, 1.0, s2], [-a*c1, 0.0, -c2]])
    gamma = np.array([c2*pd*pd + a*c1*qd*qd, s2*pd*pd + a*s1*qd*qd])
    K = np.zeros((5, 5))
    K[:3, :3] = np.diag([J1, m2, J2])
    K[:3, 3:], K[3:, :3] = G.T, G
    sol = np.linalg.solve(K, np.concatenate([forces(q, x, p, qd, xd, pd),
                                             -gamma]))
    return np.concatenate([[qd, xd, pd], sol[:3]])


def main():
    p0 = math.asin(-a)
    y0 = [math.pi/2, math.cos(p0), p0, 0.0, 0.0, 0.0]
    times = [0.25*i for i in range(41)]
    sol = solve_ivp(rhs, (0, 10), y0, method="DOP853", t_eval=times,
                    rtol=1e-13, atol=1e-13)
    assert sol.success, sol.message
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)),
                       "slider_crank_ref.csv")
    with open(out, "w") as f:
        f.write("time,q,x,p\n")
        for i, t in enumerate(sol.t):
            f.write("%r,%.15e,%.15e,%.15e\n" % (t, sol.y[0, i], sol.y[1, i],
                                               sol.y[2, i]))


if __name__ == "__main__":
    main()
