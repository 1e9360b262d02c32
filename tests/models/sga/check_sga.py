#!/usr/bin/env python3
"""The SGA's verdicts (issue 14) on the seeds' worked examples and on the
models the issue names, each expectation derived by hand from the paper in
the model's comments. Standard library only.

Usage: check_sga.py LDAEC [CASE ...]   (no CASE: every case; --list: names)

Each case runs `ldaec MODEL --analyze --json` (with --model and --param as
the case says) and checks the keys `outcome`, `dof`, `free_functions`,
`constraints`, `undetermined`, `differentiation_index`, and where the case
has them `redundant`, `conflict` and `point`.

Constraint expressions are checked numerically, never as text: at random
points of P_f (each case samples its own from the paper's parametrization)
every reported constraint must vanish, and for every k the gradients of the
reported generations 1..k must span the same space as those of the paper's
(so a constraint may come scaled, or combined with earlier ones, and still
pass; a constraint of the wrong generation may not).
The `*-simulate` and `*-sga` cases run --simulate where the issue asks
for it: the equilibrium of the zero-dimensional P_f held (and any other
start refused), the over-determined consistent models (the
parallelogram; Vessiot against the symmetric squares it is made of; the
pendulum with its velocity constraint against ../reference's polar form),
and seed 001's pendulum with --method sga against the polar form's
reference (../reference/pendulum_var_ref.csv: the paper's reduced vector
field);
the `*-why` cases check that --simulate refuses a model without a unique
solution and says why.
Exit 1 on a failed check.
"""
import json
import keyword
import math
import os
import random
import re
import io
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from check_e2e import read_csv, read_ref  # noqa: E402

# --- evaluating lsd expressions -------------------------------------------

FUNCTIONS = {
    name: getattr(math, name)
    for name in ("sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh",
                 "cosh", "tanh", "exp", "log", "log10", "sqrt")
}
FUNCTIONS.update(abs=abs, min=min, max=max, noEvent=lambda x: x,
                 sign=lambda x: (x > 0) - (x < 0))


def ident(name):
    """An lsd name as a Python identifier: quoted names ('a.b') and Python
    keywords (a variable called `lambda`) get a prefix."""
    if name.startswith("'"):
        return "_q_" + re.sub(r"\W", "_", name[1:-1])
    return "_k_" + name if keyword.iskeyword(name) else name


def to_python(expr):
    """lsd expression text -> Python: `^` is the power."""
    if "der(" in expr:
        raise ValueError("a constraint over t and y contains der(): " + expr)
    expr = re.sub(r"'[^']*'|[A-Za-z_]\w*", lambda m: ident(m[0]), expr)
    return expr.replace("^", "**")


def scope_of(env):
    return dict(FUNCTIONS, **{ident(k): v for k, v in env.items()})


def evaluate(expr, env):
    return eval(to_python(expr), {"__builtins__": {}}, scope_of(env))


def gradient(expr, env, names):
    code = compile(to_python(expr), "<constraint>", "eval")
    scope = scope_of(env)
    grad = []
    for name in names:
        h = 1e-6 * max(1.0, abs(env[name]))
        scope[ident(name)] = env[name] + h
        up = eval(code, {"__builtins__": {}}, scope)
        scope[ident(name)] = env[name] - h
        down = eval(code, {"__builtins__": {}}, scope)
        scope[ident(name)] = env[name]
        grad.append((up - down) / (2 * h))
    return grad


def rank(rows, tol=1e-6):
    """Numerical rank of rows, each scaled to unit length first (constraints
    are defined up to a factor)."""
    work = []
    for row in rows:
        norm = math.sqrt(sum(v * v for v in row))
        if norm > 1e-300:
            work.append([v / norm for v in row])
    r = 0
    cols = len(work[0]) if work else 0
    for col in range(cols):
        pivot = max(range(r, len(work)), key=lambda i: abs(work[i][col]),
                    default=None)
        if pivot is None or abs(work[pivot][col]) <= tol:
            continue
        work[r], work[pivot] = work[pivot], work[r]
        for i in range(r + 1, len(work)):
            f = work[i][col] / work[r][col]
            work[i] = [a - f * b for a, b in zip(work[i], work[r])]
        r += 1
    return r


# --- the cases -------------------------------------------------------------


class Case:
    def __init__(self, file, model, outcome, variables, params=None,
                 overrides=None, dof=None, free=None, gens=None,
                 gen1_from=None, undetermined=None, index=None,
                 redundant=None, conflict_from=None, point=None,
                 steps=None, sample=None):
        self.file = file
        self.model = model
        self.outcome = outcome
        self.variables = variables
        self.params = dict(params or {})
        self.overrides = dict(overrides or {})
        self.params.update(self.overrides)
        self.dof = dof
        self.free = free
        self.gens = gens            # the paper's constraints, per generation
        self.gen1_from = gen1_from  # equations the primary ones come from
        self.undetermined = undetermined
        self.index = index
        # (the counts allowed, the equations that may be named; None: any)
        self.redundant = redundant
        self.conflict_from = conflict_from
        self.point = point
        self.steps = steps          # sga_steps: the step that ends it
        self.sample = sample        # rng, params -> a point of P_f

    def args(self):
        """ldaec's arguments naming the model and the case's parameters."""
        out = [os.path.join(HERE, self.file), "--model", self.model]
        for key, value in self.overrides.items():
            out += ["--param", "%s=%r" % (key, value)]
        return out


def uniform(rng, lo, hi):
    return rng.uniform(lo, hi)


CONTROL = dict(A11=-1, A12=1, A21=1, A22=2, u1=0.5, u2=-1)
CONTROL_EQ1 = "der(x1) = A11 * x1 + A12 * x2 + u1"
CONTROL_EQ2 = "0 = A21 * x1 + A22 * x2 + u2"

GENERAL = dict(b12=0, k11=1, k12=0, k21=0, k22=1, c1=0, c2=0)
GENERAL_RANK_1 = dict(k12=1, k21=1, c2=1)
GENERAL_ONE = dict(k22=0)  # with the defaults k21 = c2 = 0: xi2 = 0
GENERAL_VARS = ["x1", "x2", "x3", "x4"]

ROBOT = dict(l=1, m0=1, m1=2, m2=1.5, m=0.5, R=0.1)
ROBOT["I"] = (ROBOT["m"] + ROBOT["m0"] + (ROBOT["m1"] + ROBOT["m2"]) / 3) \
    * ROBOT["l"] ** 2
ROBOT_VARS = ["phi", "omega", "x", "v", "tau1", "tau2"]
ROBOT_D = "(I + (m0 + m2)*x^2 + (2*m0 + m2)*l*x)"
ROBOT_K = "(2*(m0 + m2)*x + (2*m0 + m2)*l)"
ROBOT_XI3 = ("(tau2/R + omega^2*(m2*(x + l/2) + m0*(x + l)))/(m0 + m2)"
             " - (tau1 - %s*omega*v)/%s" % (ROBOT_K, ROBOT_D))


def robot_tracking_point(rng, p):
    x, v, tau1 = uniform(rng, -0.5, 0.5), uniform(rng, -1, 1), \
        uniform(rng, -1, 1)
    omega = v
    D = p["I"] + (p["m0"] + p["m2"]) * x**2 + (2 * p["m0"] + p["m2"]) \
        * p["l"] * x
    K = 2 * (p["m0"] + p["m2"]) * x + (2 * p["m0"] + p["m2"]) * p["l"]
    tau2 = p["R"] * ((p["m0"] + p["m2"]) * (tau1 - K * omega * v) / D
                     - omega**2 * (p["m2"] * (x + p["l"] / 2)
                                   + p["m0"] * (x + p["l"])))
    return dict(phi=p["l"] + x, omega=omega, x=x, v=v, tau1=tau1, tau2=tau2,
                time=0.0)


PVL = dict(L0=1, eps=0.1, w=1.3, g=9.81, theta0=1.5)
PVL_R = "(L0*(1 + eps*sin(w*time)))"
PVL_RD = "(L0*eps*w*cos(w*time))"
PVL_RDD = "(-L0*eps*w^2*sin(w*time))"
PEND_VARS = ["x", "y", "vx", "vy"]


def pendulum_point(R, Rd, Rdd, g, t, rng, force):
    """A point of the pendulum's P_f at time t for a rod of length R(t):
    position on the circle, velocity radial R' plus tangential, the force
    from the acceleration-level constraint."""
    th, thd = uniform(rng, -3, 3), uniform(rng, -2, 2)
    x, y = R * math.sin(th), -R * math.cos(th)
    vx = Rd * math.sin(th) + R * thd * math.cos(th)
    vy = -Rd * math.cos(th) + R * thd * math.sin(th)
    pt = dict(x=x, y=y, vx=vx, vy=vy, time=t)
    pt[force] = (vx**2 + vy**2 - g * y - (R * Rdd + Rd**2)) / R**2
    return pt


def pvl_point(rng, p):
    t = uniform(rng, 0, 10)
    w, L0, eps = p["w"], p["L0"], p["eps"]
    R = L0 * (1 + eps * math.sin(w * t))
    Rd = L0 * eps * w * math.cos(w * t)
    Rdd = -L0 * eps * w**2 * math.sin(w * t)
    return pendulum_point(R, Rd, Rdd, p["g"], t, rng, "tau")


PEND = dict(L=1, g=9.81, theta0=0.5)
PEND_PHI = ["x^2 + y^2 - L^2", "x*vx + y*vy",
            "vx^2 + vy^2 - lambda*(x^2 + y^2) - g*y"]


def pend_point(rng, p):
    return pendulum_point(p["L"], 0, 0, p["g"], 0.0, rng, "lambda")


TRANSAMP = dict(Ub=6, Uf=0.026, alpha=0.99, beta=1e-6, R0=1000, R1=9000,
                R2=9000, R3=9000, R4=9000, R5=9000, R6=9000, R7=9000,
                R8=9000, R9=9000, C1=1e-6, C2=2e-6, C3=3e-6, C4=4e-6,
                C5=5e-6, pi=math.pi)
TA_UE = "0.1*sin(200*pi*time)"
TA_IE1 = "beta*(exp((U2 - U3)/Uf) - 1)"
TA_IE2 = "beta*(exp((U5 - U6)/Uf) - 1)"
TRANSAMP_C = [
    "(%s - U1)/R0 + (Ub - U2)/R2 - U2/R1 - (1 - alpha)*%s" % (TA_UE, TA_IE1),
    "(Ub - U4)/R4 - alpha*%s + (Ub - U5)/R6 - U5/R5 - (1 - alpha)*%s"
    % (TA_IE1, TA_IE2),
    "(Ub - U7)/R8 - alpha*%s - U8/R9" % TA_IE2,
]


def transamp_point(rng, p):
    ie = lambda d: p["beta"] * (math.exp(d / p["Uf"]) - 1)
    t = uniform(rng, 0, 0.2)
    U2 = uniform(rng, 2, 4)
    U3 = U2 - uniform(rng, 0.05, 0.2)
    U5 = uniform(rng, 2, 4)
    U6 = U5 - uniform(rng, 0.05, 0.2)
    U7 = uniform(rng, 3, 6)
    U1 = 0.1 * math.sin(200 * math.pi * t) + p["R0"] * (
        (p["Ub"] - U2) / p["R2"] - U2 / p["R1"]
        - (1 - p["alpha"]) * ie(U2 - U3))
    U4 = p["Ub"] + p["R4"] * (
        -p["alpha"] * ie(U2 - U3) + (p["Ub"] - U5) / p["R6"] - U5 / p["R5"]
        - (1 - p["alpha"]) * ie(U5 - U6))
    U8 = p["R9"] * ((p["Ub"] - U7) / p["R8"] - p["alpha"] * ie(U5 - U6))
    return dict(U1=U1, U2=U2, U3=U3, U4=U4, U5=U5, U6=U6, U7=U7, U8=U8,
                time=t)


VESSIOT_VARS = ["y1", "y2", "y3", "z1", "z2", "z3", "w1", "w2", "w3"]
VESSIOT_C = [
    "y3^2 - y1*y2",
    "y3*z3 - (y1*z2 + y2*z1)/2",
    "z3^2 - z1*z2 + y3*w3 - (y1*w2 + y2*w1)/2",
    "z3*w3 - (z1*w2 + z2*w1)/2",
    "w3^2 - w1*w2 - (z3^2 - z1*z2)",
]


def vessiot_point(rng, p):
    """(u^2, v^2, u v) and two derivatives at t = 0 for solutions
    u = a cos(t/2) + b sin(t/2), v = c cos(t/2) + d sin(t/2) of
    y'' + y/4 = 0 (p = 0, q = 1, r = 0 only)."""
    a, b, c, d = (uniform(rng, -2, 2) for _ in range(4))
    u, u1, u2 = a, b / 2, -a / 4
    v, v1, v2 = c, d / 2, -c / 4
    return dict(y1=u * u, y2=v * v, y3=u * v,
                z1=2 * u * u1, z2=2 * v * v1, z3=u1 * v + u * v1,
                w1=2 * u1 * u1 + 2 * u * u2, w2=2 * v1 * v1 + 2 * v * v2,
                w3=u2 * v + 2 * u1 * v1 + u * v2, time=0.0)


CASES = {
    # seed 000 §6 Example 1, the four cases
    "control-unique": Case(
        "control_linear.lsd", "ControlLinear", "unique", ["x1", "x2"],
        params=CONTROL, dof=1, free=0,
        gens=[["A21*x1 + A22*x2 + u2"]], gen1_from=[CONTROL_EQ2],
        undetermined=[], index=1,
        sample=lambda rng, p: dict(
            x1=(x1 := uniform(rng, -3, 3)),
            x2=-(p["A21"] * x1 + p["u2"]) / p["A22"], time=0.0)),
    "control-gauge": Case(
        "control_linear.lsd", "ControlLinear", "not_unique", ["x1", "x2"],
        params=CONTROL, overrides=dict(A22=0, A21=0, u2=0), dof=2, free=1,
        gens=[], undetermined=["x2"],
        sample=lambda rng, p: dict(x1=uniform(rng, -3, 3),
                                   x2=uniform(rng, -3, 3), time=0.0)),
    "control-no-solution": Case(
        "control_linear.lsd", "ControlLinear", "no_solution", ["x1", "x2"],
        params=CONTROL, overrides=dict(A22=0, A12=0),
        conflict_from=[CONTROL_EQ1, CONTROL_EQ2]),
    "control-point": Case(
        "control_linear.lsd", "ControlLinear", "unique", ["x1", "x2"],
        params=CONTROL, overrides=dict(A22=0), dof=0, free=0,
        gens=[["A21*x1 + A22*x2 + u2"], ["A11*x1 + A12*x2 + u1"]],
        gen1_from=[CONTROL_EQ2], undetermined=[], index=2,
        point=dict(x1=1.0, x2=0.5),
        sample=lambda rng, p: dict(x1=1.0, x2=0.5, time=0.0)),
    # seed 000 §6 Example 1, the general situation (n = 4, dim ker T = 2)
    "general-rank-2": Case(
        "control_general.lsd", "ControlGeneral", "unique", GENERAL_VARS,
        params=GENERAL, dof=2, free=0, gens=[["x3", "x4"]],
        undetermined=[], index=1,
        sample=lambda rng, p: dict(x1=uniform(rng, -2, 2),
                                   x2=uniform(rng, -2, 2), x3=0.0, x4=0.0,
                                   time=0.0)),
    "general-rank-1": Case(
        "control_general.lsd", "ControlGeneral", "not_unique",
        GENERAL_VARS, params=GENERAL, overrides=GENERAL_RANK_1, dof=2,
        free=1, gens=[["x3 + x4", "x3 + x4 + x1"]],
        undetermined=["x3", "x4"],
        sample=lambda rng, p: dict(x1=0.0, x2=uniform(rng, -2, 2),
                                   x4=(x4 := uniform(rng, -2, 2)), x3=-x4,
                                   time=0.0)),
    "general-rank-1-new": Case(
        "control_general.lsd", "ControlGeneral", "not_unique",
        GENERAL_VARS, params=GENERAL, overrides=dict(GENERAL_RANK_1, b12=1),
        dof=1, free=1, gens=[["x3 + x4", "x3 + x4 + x1"], ["x2"]],
        undetermined=["x3", "x4"],
        sample=lambda rng, p: dict(x1=0.0, x2=0.0,
                                   x4=(x4 := uniform(rng, -2, 2)), x3=-x4,
                                   time=0.0)),
    "general-one-2a": Case(
        "control_general.lsd", "ControlGeneral", "not_unique",
        GENERAL_VARS, params=GENERAL, overrides=dict(GENERAL_ONE, k12=1),
        dof=3, free=1, gens=[["x3 + x4"]], undetermined=["x3", "x4"],
        sample=lambda rng, p: dict(x1=uniform(rng, -2, 2),
                                   x2=uniform(rng, -2, 2),
                                   x4=(x4 := uniform(rng, -2, 2)), x3=-x4,
                                   time=0.0)),
    "general-one-2b": Case(
        "control_general.lsd", "ControlGeneral", "not_unique",
        GENERAL_VARS, params=GENERAL,
        overrides=dict(GENERAL_ONE, k11=0, k12=1), dof=3, free=1,
        gens=[["x4"]], undetermined=["x3"],
        sample=lambda rng, p: dict(x1=uniform(rng, -2, 2),
                                   x2=uniform(rng, -2, 2),
                                   x3=uniform(rng, -2, 2), x4=0.0,
                                   time=0.0)),
    "general-one-2ci": Case(
        "control_general.lsd", "ControlGeneral", "not_unique",
        GENERAL_VARS, params=GENERAL,
        overrides=dict(GENERAL_ONE, k11=0, c1=1), dof=3, free=2,
        gens=[["x2"]], undetermined=["x3", "x4"],
        sample=lambda rng, p: dict(x1=uniform(rng, -2, 2), x2=0.0,
                                   x3=uniform(rng, -2, 2),
                                   x4=uniform(rng, -2, 2), time=0.0)),
    "general-one-2cii": Case(
        "control_general.lsd", "ControlGeneral", "not_unique",
        GENERAL_VARS, params=GENERAL,
        overrides=dict(k11=0, k22=0, c2=1, b12=1), dof=2, free=2,
        gens=[["x1"], ["x2"]], undetermined=["x3", "x4"],
        sample=lambda rng, p: dict(x1=0.0, x2=0.0, x3=uniform(rng, -2, 2),
                                   x4=uniform(rng, -2, 2), time=0.0)),
    "general-rank-0": Case(
        "control_general.lsd", "ControlGeneral", "not_unique",
        GENERAL_VARS, params=GENERAL, overrides=dict(k11=0, k22=0), dof=4,
        free=2, gens=[], undetermined=["x3", "x4"]),
    # seed 000 §6 Example 2: the telescopic robot arm, sliding control
    "robot-arm-tracking": Case(
        "robot_arm.lsd", "RobotArmTracking", "not_unique", ROBOT_VARS,
        params=ROBOT, dof=3, free=1,
        gens=[["l + x - phi"], ["v - omega"], [ROBOT_XI3]],
        gen1_from=["l + x - phi = 0"], undetermined=["tau1", "tau2"],
        sample=robot_tracking_point),
    "robot-arm-free": Case(
        "robot_arm.lsd", "RobotArmFree", "not_unique", ROBOT_VARS,
        params=ROBOT, dof=6, free=2, gens=[],
        undetermined=["tau1", "tau2"],
        sample=lambda rng, p: dict(
            {n: uniform(rng, -1, 1) for n in ROBOT_VARS}, time=0.0)),
    "sliding-transversal": Case(
        "sliding_control.lsd", "SlidingTransversal", "unique",
        ["x1", "x2", "x3", "u"], dof=2, free=0,
        gens=[["x2 + sin(x1)"], ["sin(x1) + cos(x1)*x2 + u"]],
        gen1_from=["x2 + sin(x1) = 0"], undetermined=[], index=2,
        sample=lambda rng, p: dict(
            x1=(x1 := uniform(rng, -3, 3)), x2=-math.sin(x1),
            x3=uniform(rng, -1, 1),
            u=-math.sin(x1) + math.cos(x1) * math.sin(x1), time=0.0)),
    "sliding-tangent": Case(
        "sliding_control.lsd", "SlidingTangent", "unique",
        ["x1", "x2", "x3", "u"], params=dict(s=0.3), dof=1, free=0,
        gens=[["sin(x1) - s"], ["cos(x1)*x2"],
              ["-sin(x1)*x2^2 + cos(x1)*(sin(x1) + u)"]],
        gen1_from=["sin(x1) - s = 0"], undetermined=[], index=3,
        sample=lambda rng, p: dict(
            x1=rng.choice([math.asin(p["s"]), math.pi - math.asin(p["s"])]),
            x2=0.0, x3=uniform(rng, -1, 1), u=-p["s"], time=0.0)),
    "sliding-transversal-alias": Case(
        "sliding_control.lsd", "SlidingTransversalAlias", "unique",
        ["x1", "x2", "x3", "u"], dof=2, free=0,
        gens=[["x1 + x2"], ["x2 + sin(x1) + u"]], gen1_from=["x1 + x2 = 0"],
        undetermined=[], index=2,
        sample=lambda rng, p: dict(
            x1=(x1 := uniform(rng, -1, 1)), x2=-x1, x3=uniform(rng, -1, 1),
            u=x1 - math.sin(x1), time=0.0)),
    "sliding-tangent-alias": Case(
        "sliding_control.lsd", "SlidingTangentAlias", "unique",
        ["x1", "x2", "x3", "u"], params=dict(c=0.3), dof=1, free=0,
        gens=[["x1 - c"], ["x2"], ["sin(x1) + u"]],
        gen1_from=["x1 - c = 0"], undetermined=[], index=3,
        sample=lambda rng, p: dict(x1=p["c"], x2=0.0,
                                   x3=uniform(rng, -1, 1),
                                   u=-math.sin(p["c"]), time=0.0)),
    # seed 001 §7
    "pendulum-variable-length": Case(
        "pendulum_variable_length.lsd", "PendulumVariableLength", "unique",
        PEND_VARS + ["tau"], params=PVL, dof=2, free=0,
        gens=[["x^2 + y^2 - %s^2" % PVL_R],
              ["x*vx + y*vy - %s*%s" % (PVL_R, PVL_RD)],
              ["vx^2 + vy^2 - tau*%s^2 - g*y - (%s*%s + %s^2)"
               % (PVL_R, PVL_R, PVL_RDD, PVL_RD)]],
        gen1_from=["x^2 + y^2 = (L0 * (1 + eps * sin(w * time)))^2"],
        undetermined=[], index=3, steps=4, sample=pvl_point),
    # structure fooled by cancellation
    "cancel-not-unique": Case(
        "cancellation.lsd", "CancelNotUnique", "not_unique", ["x", "y"],
        dof=1, free=1, gens=[["x + y - sin(time)"]],
        gen1_from=["x + y = sin(time)"], undetermined=["x", "y"],
        sample=lambda rng, p: dict(
            time=(t := uniform(rng, 0, 10)), x=(x := uniform(rng, -2, 2)),
            y=math.sin(t) - x)),
    "cancel-no-solution": Case(
        "cancellation.lsd", "CancelNoSolution", "no_solution", ["x", "y"],
        conflict_from=["der(x) + der(y) = cos(time) + 1",
                       "x + y = sin(time)"]),
    # a singular capacitor matrix although every node is differentiated
    "transamp": Case(
        "transamp.lsd", "Transamp", "unique", ["U%d" % i for i in
                                                range(1, 9)],
        params=TRANSAMP, dof=5, free=0, gens=[TRANSAMP_C], undetermined=[],
        index=1, sample=transamp_point),
    # over-determined, consistent
    "parallelogram": Case(
        "parallelogram.lsd", "Parallelogram", "unique", ["a1", "a2"],
        params=dict(L=1), dof=1, free=0,
        gens=[["L*cos(a1) - L*cos(a2)"]], undetermined=[], index=1,
        redundant=({1}, ["L * cos(a1) = L * cos(a2)",
                         "L * sin(a1) = L * sin(a2)"]),
        sample=lambda rng, p: dict(a1=(a := uniform(rng, -3, 3)), a2=a,
                                   time=0.0)),
    "vessiot": Case(
        "vessiot.lsd", "Vessiot", "unique", VESSIOT_VARS,
        params=dict(p=0, q=1, r=0), dof=4, free=0,
        gens=[[c] for c in VESSIOT_C], gen1_from=["y3^2 - y1 * y2 = 0"],
        # y3^2 = y1 y2 is not implied by the others, only kept by them
        # from a start on P_f: naming it redundant is optional.
        undetermined=[], redundant=({0, 1}, None), sample=vessiot_point),
    "pendulum-velocity": Case(
        "pendulum.lsd", "PendulumVelocity", "unique",
        PEND_VARS + ["lambda"], params=PEND, dof=2, free=0,
        gens=[PEND_PHI[:2], PEND_PHI[2:]],
        gen1_from=["x^2 + y^2 = L^2", "x * vx + y * vy = 0"],
        undetermined=[], index=2,
        # none (as Vessiot) or any one: with x vx + y vy = 0, der(x) = vx
        # follows too
        redundant=({0, 1}, None),
        sample=pend_point),
    # over-determined, inconsistent
    "rail": Case(
        "rail.lsd", "Rail", "no_solution", PEND_VARS, params=dict(g=9.81),
        conflict_from=["y = 0", "der(vy) = -g"]),
    # baselines
    "pendulum": Case(
        "pendulum.lsd", "Pendulum", "unique", PEND_VARS + ["lambda"],
        params=PEND, dof=2, free=0, gens=[[c] for c in PEND_PHI],
        gen1_from=["x^2 + y^2 = L^2"], undetermined=[], index=3,
        sample=pend_point),
    "ode": Case(
        "basics.lsd", "Oscillator", "unique", ["x", "v"], params=dict(k=4),
        dof=2, free=0, gens=[], undetermined=[], index=0,
        sample=lambda rng, p: dict(x=uniform(rng, -1, 1),
                                   v=uniform(rng, -1, 1), time=0.0)),
    "index-one": Case(
        "basics.lsd", "IndexOne", "unique", ["x", "z"], dof=1, free=0,
        gens=[["z - sin(x) - time"]], gen1_from=["z = sin(x) + time"],
        undetermined=[], index=1,
        sample=lambda rng, p: dict(
            time=(t := uniform(rng, 0, 5)), x=(x := uniform(rng, -2, 2)),
            z=math.sin(x) + t)),
}

# --- checking --------------------------------------------------------------


class Checker:
    def __init__(self, name):
        self.name = name
        self.failures = []

    def expect(self, ok, what):
        if not ok:
            self.failures.append(what)
        return ok


def squash(text):
    return re.sub(r"\s+", "", text)


def count_of(value):
    return len(value) if isinstance(value, list) else value


def point_of(value):
    """`point` as {name: value}, [[name, value]] or [{name, value}]."""
    if isinstance(value, dict):
        return value
    out = {}
    for item in value or []:
        if isinstance(item, dict):
            out[item["name"]] = item["value"]
        else:
            out[item[0]] = item[1]
    return out


def check_constraints(case, report, c):
    gens = report.get("constraints")
    if not c.expect(isinstance(gens, list), "constraints is %r" % (gens,)):
        return
    counts = [len(g) for g in gens]
    want = [len(g) for g in case.gens]
    c.expect(counts == want,
             "constraints per generation %s, expected %s" % (counts, want))
    for g in gens:
        for con in g:
            c.expect(isinstance(con, dict) and "expr" in con
                     and isinstance(con.get("from"), list) and con["from"],
                     "constraint without expr or sources: %r" % (con,))
    if case.gen1_from and gens:
        sources = {squash(s) for con in gens[0] for s in con.get("from", [])}
        for eq in case.gen1_from:
            c.expect(squash(eq) in sources,
                     "primary constraints do not come from '%s' (from: %s)"
                     % (eq, sorted(sources)))
    if counts != want or not case.sample:
        return
    rng = random.Random(14)
    for _ in range(3):
        env = dict(case.params)
        env.update(case.sample(rng, case.params))
        names = case.variables
        mine, theirs = [], []
        for k, (gm, gt) in enumerate(zip(case.gens, gens)):
            for con in gt:
                try:
                    value = evaluate(con["expr"], env)
                    grad = gradient(con["expr"], env, names)
                except Exception as err:  # any unreadable expression fails
                    c.expect(False, "cannot evaluate constraint '%s': %s"
                             % (con.get("expr"), err))
                    return
                scale = 1 + math.sqrt(sum(g * g for g in grad)) * \
                    math.sqrt(sum(env[n] ** 2 for n in names))
                if not c.expect(abs(value) <= 1e-7 * scale,
                                "generation %d constraint '%s' is %g on P_f "
                                "at %s" % (k + 1, con["expr"], value, env)):
                    return
                theirs.append(grad)
            mine += [gradient(e, env, names) for e in gm]
            r_mine, r_theirs = rank(mine), rank(theirs)
            r_both = rank(mine + theirs)
            if not c.expect(r_mine == r_theirs == r_both,
                            "generations 1..%d span another space than the "
                            "paper's (ranks: paper %d, reported %d, together "
                            "%d) at %s" % (k + 1, r_mine, r_theirs, r_both,
                                           env)):
                return


def check_case(ldaec, name):
    case = CASES[name]
    c = Checker(name)
    cmd = [ldaec] + case.args() + ["--analyze", "--json"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    # A model without a unique solution may make --analyze fail, after its
    # report.
    allowed = (0,) if case.outcome == "unique" else (0, 1)
    if not c.expect(proc.returncode in allowed and proc.stdout.strip(),
                    "%s exited %d: %s" % (
            " ".join(cmd), proc.returncode, proc.stderr.strip()[-2000:])):
        return c
    report = json.loads(proc.stdout)
    c.expect(report.get("outcome") == case.outcome,
             "outcome %r, expected %r" % (report.get("outcome"),
                                          case.outcome))
    if case.dof is not None:
        c.expect(report.get("dof") == case.dof,
                 "dof %r, expected %d" % (report.get("dof"), case.dof))
    if case.free is not None:
        got = count_of(report.get("free_functions"))
        c.expect(got == case.free,
                 "free_functions %r, expected %d" % (got, case.free))
    if case.undetermined is not None:
        # The paper's gauge fields move every variable of
        # case.undetermined; a report may name them all, or one per free
        # function (the ones left to choose), but none outside.
        got = set(report.get("undetermined") or [])
        want = set(case.undetermined)
        c.expect(got == want or (got < want and len(got) == case.free),
                 "undetermined %r, expected %r (or %s of them)"
                 % (sorted(got), sorted(want), case.free))
    if case.index is not None:
        got = report.get("differentiation_index")
        c.expect(got == case.index, "differentiation_index %r, expected %d"
                 % (got, case.index))
    if case.steps is not None:
        got = report.get("sga_steps")
        c.expect(got == case.steps, "sga_steps %r, expected %d"
                 % (got, case.steps))
    linear = report.get("linear")
    if case.dof is not None and isinstance(linear, dict):
        # Wong sequences and the SGA agree on linear models (seed 002):
        # dim V = dim P_f, and the pencil is regular iff the solution is
        # unique.
        c.expect(linear.get("dim_V") == case.dof, "linear.dim_V %r, dim P_f "
                 "%r" % (linear.get("dim_V"), case.dof))
        c.expect(linear.get("regular") == (case.outcome == "unique"),
                 "linear.regular %r for a %s solution"
                 % (linear.get("regular"), case.outcome))
    if case.gens is not None:
        check_constraints(case, report, c)
    if case.redundant is not None:
        counts, allowed = case.redundant
        got = report.get("redundant")
        c.expect(isinstance(got, list) and len(got) in counts
                 and (allowed is None or all(
                     squash(g) in {squash(a) for a in allowed}
                     for g in got)),
                 "redundant %r, expected %s of %r" % (got, sorted(counts),
                                                      allowed))
    if case.conflict_from is not None:
        conflict = report.get("conflict")
        sources = {squash(s) for s in (conflict or {}).get("from", [])}
        c.expect(isinstance(conflict, dict) and all(
            squash(eq) in sources for eq in case.conflict_from),
            "conflict %r does not name %r" % (conflict, case.conflict_from))
    if case.point is not None:
        got = point_of(report.get("point"))
        c.expect(set(got) == set(case.point) and all(
            abs(got[n] - v) <= 1e-9 * (1 + abs(v))
            for n, v in case.point.items()),
            "point %r, expected %r" % (got, case.point))
    return c


def simulate(args):
    """Runs ldaec --simulate; (exit status, CSV rows, stderr)."""
    cmd = [LDAEC[0], "--no-progress", "--simulate"] + args
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    rows = read_csv(io.StringIO(proc.stdout)) if proc.returncode == 0 else []
    return proc.returncode, rows, proc.stderr


def control_point_simulate(c):
    model = os.path.join(HERE, "control_linear.lsd")
    rc, rows, err = simulate([model, "--param", "A22=0", "--stop", "1",
                                 "--interval", "0.25"])
    if c.expect(rc == 0 and len(rows) == 5, "the equilibrium (1, 0.5) did "
                "not run: exit %d, %d rows: %s" % (rc, len(rows), err[-800:])):
        worst = max(max(abs(r["x1"] - 1), abs(r["x2"] - 0.5)) for r in rows)
        c.expect(worst <= 1e-9, "the equilibrium moved by %.2e" % worst)
    rc, _, err = simulate([model, "--param", "A22=0", "--param", "x10=2"])
    c.expect(rc != 0 and "x1" in err, "x1 = 2 is no point of P_f, yet "
             "--simulate exited %d (%s)" % (rc, err[-400:]))


def parallelogram_simulate(c):
    rc, rows, err = simulate([os.path.join(HERE, "parallelogram.lsd"),
                                 "--stop", "2", "--interval", "0.5"])
    if c.expect(rc == 0 and len(rows) == 5, "exit %d, %d rows: %s"
                % (rc, len(rows), err[-800:])):
        worst = max(max(abs(r["a1"] - 0.3 - r["time"]),
                        abs(r["a2"] - 0.3 - r["time"])) for r in rows)
        c.expect(worst <= 1e-6, "a1, a2 differ from 0.3 + t by %.2e"
                 % worst)


def pendulum_variable_length_sga(c):
    ref = read_ref("pendulum_var_ref.csv")
    rc, rows, err = simulate([
        os.path.join(HERE, "pendulum_variable_length.lsd"), "--method", "sga",
        "--rtol", "1e-9", "--outputs", "x,y"])
    if not c.expect(rc == 0, "exit %d: %s" % (rc, err[-800:])):
        return
    if c.expect(len(rows) == len(ref) and all(
            abs(r["time"] - q["time"]) <= 1e-9 for r, q in zip(rows, ref)),
            "%d rows, the reference has %d" % (len(rows), len(ref))):
        worst = max(abs(r[n] - q[n]) for r, q in zip(rows, ref)
                    for n in ("x", "y"))
        c.expect(worst <= 1e-6, "x, y differ from the polar form by %.2e"
                 % worst)


def why_not(name):
    """--simulate on a model without a unique solution exits 1 and says
    why: for a model without solution that it has none (or which
    constraint cannot hold, or that the inputs violate one); otherwise
    what is left free, quoting a variable the paper's gauge fields move
    (alone or in a combination such as 'x3 - x4')."""
    case = CASES[name]

    def check(c):
        rc, _, err = simulate(case.args())
        if case.outcome == "no_solution":
            said = any(w in err for w in ("no solution", "cannot hold",
                                          "violate"))
            what = "that there is no solution"
        else:
            quoted = set()
            for text in re.findall(r"'([^']*)'", err):
                quoted.update(re.findall(r"[A-Za-z_]\w*", text))
            said = bool(quoted & set(case.undetermined))
            what = "which of %s is free" % ", ".join(case.undetermined)
        c.expect(rc == 1 and said, "--simulate exited %d without saying %s: "
                 "%s" % (rc, what, err[-600:]))
    return check


def vessiot_simulate(c):
    """The symmetric squares of u = cos(t/2) + sin(t/2),
    v = cos(t/2) - sin(t/2): y = (1 + sin t, 1 - sin t, cos t)."""
    rc, rows, err = simulate([os.path.join(HERE, "vessiot.lsd"), "--stop",
                              "10", "--interval", "0.5", "--rtol", "1e-9"])
    if c.expect(rc == 0 and len(rows) == 21, "exit %d, %d rows: %s"
                % (rc, len(rows), err[-800:])):
        worst = max(max(abs(r["y1"] - 1 - math.sin(r["time"])),
                        abs(r["y2"] - 1 + math.sin(r["time"])),
                        abs(r["y3"] - math.cos(r["time"]))) for r in rows)
        c.expect(worst <= 1e-6, "y differs from the symmetric squares by "
                 "%.2e" % worst)


def pendulum_velocity_simulate(c):
    """With its velocity constraint written twice, the pendulum released
    at 1.5 rad moves as the polar form says (../reference; 1e-5 is BDF's
    phase error over 10 s at rtol 1e-9, as check_e2e.py's pendulum), and
    the equation left out holds at every output."""
    ref = read_ref("pendulum_ref.csv")
    rc, rows, err = simulate([
        os.path.join(HERE, "pendulum.lsd"), "--model", "PendulumVelocity",
        "--param", "theta0=1.5", "--stop", "10", "--interval", "0.1",
        "--rtol", "1e-9", "--outputs", "x,y,vx,vy"])
    if c.expect(rc == 0 and len(rows) == 101, "exit %d, %d rows: %s"
                % (rc, len(rows), err[-800:])):
        worst = max(abs(r[n] - q[n]) for r, q in zip(rows, ref)
                    for n in ("x", "y"))
        c.expect(worst <= 1e-5, "x, y differ from the polar form by %.2e"
                 % worst)
        drift = max(abs(r["x"] * r["vx"] + r["y"] * r["vy"]) for r in rows)
        c.expect(drift <= 1e-7, "x vx + y vy = 0 is off by %.2e" % drift)


SIMULATIONS = {
    "control-point-simulate": control_point_simulate,
    "parallelogram-simulate": parallelogram_simulate,
    "vessiot-simulate": vessiot_simulate,
    "pendulum-velocity-simulate": pendulum_velocity_simulate,
    "pendulum-variable-length-sga": pendulum_variable_length_sga,
}
SIMULATIONS.update({name + "-why": why_not(name) for name, case in
                    CASES.items() if case.outcome != "unique"})
LDAEC = []


def run_case(ldaec, name):
    if name in CASES:
        return check_case(ldaec, name)
    c = Checker(name)
    SIMULATIONS[name](c)
    return c


def main(argv):
    if len(argv) >= 2 and argv[1] == "--list":
        print("\n".join(list(CASES) + list(SIMULATIONS)))
        return 0
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    LDAEC.append(argv[1])
    names = argv[2:] or list(CASES) + list(SIMULATIONS)
    unknown = [n for n in names if n not in CASES and n not in SIMULATIONS]
    if unknown:
        print("unknown case(s): %s" % ", ".join(unknown), file=sys.stderr)
        return 2
    failed = 0
    for name in names:
        c = run_case(argv[1], name)
        if c.failures:
            failed += 1
            print("FAIL %s:" % name)
            for f in c.failures:
                print("  " + f)
        else:
            print("ok   %s" % name)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
