#!/usr/bin/env python3
"""Reference values for the conformance suite that are not read from a .mos
file: closed forms (each with its formula) and SciPy solve_ivp solutions.
None of them uses ldaec. `python3 reference.py` prints them all; the values
in manifest.json were computed by these functions (SciPy is needed only for
switched_rlc, and only to recompute; run.py needs no SciPy)."""
import math

G = 9.81


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


def bouncing_ball(t, h0=1.0, e=0.8):
    """ModelicaByExample BouncingBall: free fall from h0 at rest,
    h'' = -g; at h = 0 the velocity becomes -e times the impact velocity.
    Flight k starts at t_k with upward speed u_k: h = u_k s - g s^2/2,
    lasting 2 u_k / g; the first impact at sqrt(2 h0 / g) with speed
    g sqrt(2 h0 / g). Returns (h, v) for t before the Zeno point."""
    t1 = math.sqrt(2 * h0 / G)
    if t < t1:
        return h0 - G * t * t / 2, -G * t
    tk, u = t1, e * G * t1
    while t >= tk + 2 * u / G:
        tk += 2 * u / G
        u *= e
    s = t - tk
    return u * s - G * s * s / 2, u - G * s


def hysteresis(t, C=1.0, h=2.0, Q=25.0, Tamb=285.0, Tbar=295.0):
    """ModelicaByExample HysteresisControl: C T' = Q_on - h (T - Tamb),
    T(0) = Tbar + 5, heater off. Off: T relaxes to Tamb until T < Tbar - 1;
    on: to Tamb + Q/h until T > Tbar + 1. Each phase is
    T = Tend + (T0 - Tend) exp(-h s / C), and the phase lasts
    C/h ln((T0 - Tend)/(Tswitch - Tend))."""
    T0, heat, tk = Tbar + 5, False, 0.0
    while True:
        Tend = Tamb + (Q / h if heat else 0.0)
        Tsw = Tbar + 1 if heat else Tbar - 1
        dur = C / h * math.log((T0 - Tend) / (Tsw - Tend))
        if t < tk + dur:
            return Tend + (T0 - Tend) * math.exp(-h * (t - tk) / C), heat
        tk += dur
        T0, heat = Tsw, not heat


def cooling_steady_then_dynamic(t, h=0.7, A=1.0, m=0.1, c_p=1.2):
    """ModelicaByExample NewtonCoolingSteadyThenDynamic: steady start
    T = 298.15; for s = t - 0.5 > 0, T_inf = 298.15 - 20 s and with
    k = hA/(m c_p), e = T - T_inf obeys e' = -k e + 20, e(0) = 0:
    T = 298.15 - 20 s + (20/k)(1 - exp(-k s))."""
    k = h * A / (m * c_p)
    s = max(0.0, t - 0.5)
    return 298.15 - 20 * s + (20 / k) * (1 - math.exp(-k * s))


def switched_rlc(ts, Vb=24.0, L=1.0, R=100.0, C=1e-3):
    """ModelicaByExample SwitchedRLC: everything 0 until the switch at
    t = 0.5, then L i_L' = Vb - V, C V' = i_L - V/R; SciPy solve_ivp
    (Radau, rtol 1e-12, atol 1e-12) from the state (V, i_L) = (0, 0) at
    t = 0.5. Returns {t: (V, i_L)}."""
    from scipy.integrate import solve_ivp

    def f(_t, y):
        V, iL = y
        return [(iL - V / R) / C, (Vb - V) / L]

    out = {}
    for t in ts:
        if t <= 0.5:
            out[t] = (0.0, 0.0)
            continue
        sol = solve_ivp(f, (0.5, t), [0.0, 0.0], method="Radau", rtol=1e-12, atol=1e-12)
        out[t] = (float(sol.y[0, -1]), float(sol.y[1, -1]))
    return out


def _ivp(f, y0, ts, t0=0.0):
    """SciPy solve_ivp (Radau, rtol = atol = 1e-12) from t0; the state at each
    of ts."""
    from scipy.integrate import solve_ivp
    sol = solve_ivp(f, (t0, max(ts)), y0, method="Radau", rtol=1e-12, atol=1e-12,
                    t_eval=sorted(ts), dense_output=False)
    return {t: [float(v) for v in sol.y[:, i]] for i, t in enumerate(sorted(ts))}


def lotka_volterra(ts, alpha=0.1, beta=0.02, gamma=0.4, delta=0.02, x0=10.0, y0=10.0):
    """ModelicaByExample ClassicModel: x' = x (alpha - beta y),
    y' = y (delta x - gamma) from the start values (10, 10)."""
    return _ivp(lambda t, u: [u[0] * (alpha - beta * u[1]), u[1] * (delta * u[0] - gamma)], [x0, y0], ts)


def second_order_system(ts, J1=0.4, J2=1.0, c1=11.0, c2=5.0, d1=0.2, d2=1.0):
    """ModelicaByExample RotationalSMD.SecondOrderSystem, state
    (phi1, phi2, omega1, omega2) from (0, 1, 0, 0)."""
    def f(t, u):
        p1, p2, w1, w2 = u
        return [w1, w2, (c1 * (p2 - p1) + d1 * (w2 - w1)) / J1,
                (c1 * (p1 - p2) + d1 * (w1 - w2) - c2 * p2 - d2 * w2) / J2]
    return _ivp(f, [0.0, 1.0, 0.0, 0.0], ts)


def rlc1(ts, Vb=24.0, L=1.0, R=100.0, C=1e-3):
    """ModelicaByExample RLC1: C V' = i_L - V/R, L i_L' = Vb - V from the
    start values V = i_L = 0 (no initial equations: the defaults)."""
    return _ivp(lambda t, u: [(u[1] - u[0] / R) / C, (Vb - u[0]) / L], [0.0, 0.0], ts)


def newton_cooling_dynamic(t, T0=363.15, h=0.7, A=1.0, m=0.1, c_p=1.2):
    """ModelicaByExample NewtonCoolingDynamic: T(0) = T0, k = hA/(m c_p);
    T = 298.15 + (T0 - 298.15) exp(-k t) for t <= 0.5; after, with
    s = t - 0.5, T_inf = 298.15 - 20 s and e = T - T_inf obeys
    e' = -k e + 20 from e0 = (T0 - 298.15) exp(-k/2):
    T = 298.15 - 20 s + (20/k)(1 - exp(-k s)) + e0 exp(-k s)."""
    k = h * A / (m * c_p)
    if t <= 0.5:
        return 298.15 + (T0 - 298.15) * math.exp(-k * t)
    s = t - 0.5
    e0 = (T0 - 298.15) * math.exp(-0.5 * k)
    return 298.15 - 20 * s + (20 / k) * (1 - math.exp(-k * s)) + e0 * math.exp(-k * s)


def decay(t):
    """ModelicaByExample Decay1, Decay2: x' = -sqrt(x), x(0) = 1:
    x = (1 - t/2)^2 for t <= 2."""
    return (1 - t / 2) ** 2


def chattering_events2(t):
    """OpenModelica ChatteringPackage ChatteringEvents2: w' = 1 - w,
    w(0) = 0: w = 1 - exp(-t); while x > 0, x' = 2(-1 - w) = -4 + 2 exp(-t),
    x(0) = 1: x = 3 - 4t - 2 exp(-t), zero at t* = 0.42219...; after t*
    the Filippov solution slides on x = 0 (|w| < 1)."""
    x = 3 - 4 * t - 2 * math.exp(-t)
    return max(x, 0.0), 1 - math.exp(-t)


def reset_exponential(t, h=0.2, a=2.0):
    """OpenModelica TestNoEventsFlags (testnoEventsFlag): x' = 2x,
    reinit(x, 1) at every sample(0, 0.2): x = exp(2 (t - t_k)) with t_k the
    last sample instant; b = x > 1.2, b1 = 2x > 2.5."""
    s = t - h * math.floor(t / h + 1e-12)
    x = math.exp(a * s)
    return x, x > 1.2, a * x > 2.5


def sample_and_hold(ts, h=0.125):
    """ModelicaByExample SpeedMeasurement.SampleAndHold: omega1_measured is
    omega1 of second_order_system at the last sample instant k h (k = 0, 1,
    ...; sample(0, h) fires at the start)."""
    inst = sorted({h * math.floor(t / h + 1e-12) for t in ts})
    sol = second_order_system([t for t in inst if t > 0] or [h])
    out = {}
    for t in ts:
        tk = h * math.floor(t / h + 1e-12)
        out[t] = 0.0 if tk == 0 else sol[tk][2]
    return out


def interval_measure(ts, teeth=200):
    """ModelicaByExample SpeedMeasurement.IntervalMeasure on
    second_order_system: a tooth event when phi1 reaches the last tooth level
    L plus or minus tooth_angle = 2*3.14159/teeth (L = phi1(0) = 0 at the
    start, then the phi1 of the event); omega1_measured = tooth_angle / (the
    time since the previous event, or since the start). SciPy solve_ivp
    (Radau, rtol = atol = 1e-12) with event location. Returns
    {t: omega1_measured after the last event before t} (0 before the
    first: the default start)."""
    from scipy.integrate import solve_ivp
    J1, J2, c1, c2, d1, d2 = 0.4, 1.0, 11.0, 5.0, 0.2, 1.0
    ta = 2 * 3.14159 / teeth

    def f(t, u):
        p1, p2, w1, w2 = u
        return [w1, w2, (c1 * (p2 - p1) + d1 * (w2 - w1)) / J1,
                (c1 * (p1 - p2) + d1 * (w1 - w2) - c2 * p2 - d2 * w2) / J2]
    t0, u, L, last, meas = 0.0, [0.0, 1.0, 0.0, 0.0], 0.0, 0.0, 0.0
    events = []
    tend = max(ts)
    while t0 < tend:
        up = lambda t, y: y[0] - (L + ta)
        dn = lambda t, y: y[0] - (L - ta)
        up.terminal = dn.terminal = True
        up.direction, dn.direction = 1, -1
        sol = solve_ivp(f, (t0, tend), u, method="Radau", rtol=1e-12, atol=1e-12,
                        events=[up, dn])
        if sol.status != 1:
            break
        te = [e[0] for e in sol.t_events if len(e)][0]
        u = sol.y[:, -1].tolist()
        meas = ta / (te - last)
        events.append((te, meas))
        L, last, t0 = u[0], te, te
    out = {}
    for t in ts:
        prior = [m for (te, m) in events if te <= t]
        out[t] = prior[-1] if prior else 0.0
    return out, events


def when_reinit_sine(t):
    """OpenModelica whenTest2: x' = 10 sin t, x(0) = 1, reinit(x, 1) when
    x > 1.5: between resets x = x_k + 10 (cos t_k - cos t), so the k-th reset
    is at cos t = 1 - 0.05 k (t = 0.3176, 0.4510, 0.5548, 0.6435, 0.7227,
    0.7954, 0.8632, 0.9273) and x(t) = 1 + 10 (c_k - cos t) with c_k the
    cosine of the last reset (1 before the first)."""
    k = 0
    while math.cos(t) < 1 - 0.05 * (k + 1):
        k += 1
    return 1 + 10 * ((1 - 0.05 * k) - math.cos(t))


if __name__ == "__main__":
    for t in (0.1, 1.0, 4.0, 6.0):
        print("piecewise_linear", t, piecewise_linear(t))
    for t in (0.3, 1.0, 2.0, 2.9):
        print("bouncing_ball", t, bouncing_ball(t))
    for t in (0.2, 0.5, 1.0, 2.0, 3.0):
        print("hysteresis", t, hysteresis(t))
    for t in (0.25, 0.75, 1.5):
        print("cooling_steady_then_dynamic", t, cooling_steady_then_dynamic(t))
    print("switched_rlc", switched_rlc([0.25, 0.6, 1.0, 2.0]))
    print("lotka_volterra", lotka_volterra([5.0, 10.0, 20.0]))
    print("second_order_system", second_order_system([0.5, 1.0, 3.0]))
    print("rlc1", rlc1([0.05, 0.2, 1.0]))
    for t in (0.1, 0.5, 0.75, 1.0, 1.5):
        print("newton_cooling_dynamic", t, newton_cooling_dynamic(t))
    for t in (0.1, 0.5, 1.0, 1.5):
        print("decay", t, decay(t))
    for t in (0.2, 0.25, 1.0):
        print("chattering_events2", t, chattering_events2(t))
    for t in (0.05, 0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 0.9):
        print("reset_exponential", t, reset_exponential(t))
    print("sample_and_hold", sample_and_hold([0.1, 0.3, 0.55, 0.9]))
    print("interval_measure", interval_measure([0.1, 0.3, 0.5, 1.0])[0])
    for t in (0.5, 0.9):
        print("when_reinit_sine", t, when_reinit_sine(t))
