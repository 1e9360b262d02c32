#!/usr/bin/env python3
"""The cost of events (issue 15): bench/relay.lsd, a relay oscillator with
10^4 state events over its run (model Relay: the relation x > 0 found by
root finding at every crossing, the integrator restarted), against runs
without events: Smooth, a harmonic oscillator with the same period run over
the time that takes it as many steps as Relay takes (its stop time scaled
from one calibrating run), and RelayNoEvent, the relay inside noEvent (the
integrator stepping across the force's jumps, error-test failures instead
of events). Median of --repeat interleaved runs of each, `ldaec --simulate
--stats`: the integration time (wall time less initialization, as --stats
prints them), steps, events.
Cost per event = (integration time of Relay - of Smooth) / events; the
ratio: Relay / Smooth, both taking the same number of steps.
Accuracy: the relay conserves the energy v^2/2 + F |x| = F A; its largest
deviation over the output rows says what each relay run's answer is worth.

Usage: run_events.py [--ldaec build/compiler/driver/ldaec] [--repeat 5]
                     [--doc]
  --doc  writes the table into docs/benchmarks.md (section "Events").
Standard library only.
"""
import argparse
import csv
import io
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MODEL = os.path.join(HERE, "relay.lsd")
F, A = 1.0, 0.5
STOP = 20000.0  # 10^4 crossings of x = 0
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402
from benchrun import machine, median, run_cpu, stat  # noqa: E402


def energy_error(stdout):
    rows = list(csv.DictReader(io.StringIO(stdout)))
    return max(abs(0.5 * float(r["v"])**2 + F * abs(float(r["x"])) - F * A)
               for r in rows)


def simulate(ldaec, model, stop):
    return run_cpu([ldaec, MODEL, "--model", model, "--simulate", "--stats",
                    "--no-progress", "--outputs", "x,v", "--stop", repr(stop),
                    "--interval", repr(stop / 200)])


def measure(ldaec, model, stop, repeat_index, results):
    out, err, wall, cpu = simulate(ldaec, model, stop)
    r = results.setdefault(model, {"integration": [], "cpu": []})
    r["integration"].append(stat(err, "wall time") -
                            stat(err, "initialization time"))
    r["cpu"].append(cpu)
    if repeat_index == 0:
        r["steps"] = stat(err, "steps")
        try:
            r["events"] = stat(err, "events")
        except RuntimeError:
            r["events"] = 0
        r["energy"] = energy_error(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ldaec", default=os.path.join(
        ROOT, "build", "compiler", "driver", "ldaec"))
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--doc", action="store_true")
    args = ap.parse_args()

    # The stop time at which Smooth takes Relay's steps.
    steps = {m: stat(simulate(args.ldaec, m, STOP)[1], "steps")
             for m in ("Relay", "Smooth")}
    stops = {"Relay": STOP, "RelayNoEvent": STOP,
             "Smooth": STOP * steps["Relay"] / steps["Smooth"]}
    results = {}
    for i in range(args.repeat):
        for model in ("Relay", "Smooth", "RelayNoEvent"):
            measure(args.ldaec, model, stops[model], i, results)
    ev, sm, no = results["Relay"], results["Smooth"], results["RelayNoEvent"]
    t_ev, t_sm = median(ev["integration"]), median(sm["integration"])
    n = ev["events"]
    per_event = (t_ev - t_sm) / n * 1e3 if n else float("nan")
    lines = [
        "| model | stop (s) | events | steps | integration ms (median of %d)"
        " | process CPU ms (median) | largest energy error |" % args.repeat,
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for name, model in (("Relay (x > 0 an event)", "Relay"),
                        ("Smooth (no event, the same steps)", "Smooth"),
                        ("RelayNoEvent (noEvent(x > 0))", "RelayNoEvent")):
        r = results[model]
        lines.append("| %s | %.0f | %d | %d | %.1f | %.1f | %s |" % (
            name, stops[model], r["events"], r["steps"],
            median(r["integration"]) * 1e3, median(r["cpu"]) * 1e3,
            "%.1e" % r["energy"] if model != "Smooth" else ""))
    table = "\n".join(lines)
    summary = ("Cost per event: %.3f ms ((%.1f - %.1f) ms / %d events); "
               "Relay / Smooth at the same steps: %.2fx the integration "
               "time. Relay / RelayNoEvent: %.2fx the integration time, "
               "%.2fx the steps." % (
                   per_event, t_ev * 1e3, t_sm * 1e3, n, t_ev / t_sm,
                   t_ev / median(no["integration"]),
                   ev["steps"] / no["steps"]))
    print(table)
    print(summary)
    if args.doc:
        os.environ["LDAE_BENCH_DOC"] = "1"
    write_section(
        os.path.join(ROOT, "docs", "benchmarks.md"), "Events",
        "## Events\n\n"
        "`bench/run_events.py --doc` (%s). bench/relay.lsd: a mass pushed "
        "towards x = 0 by a relay force, 10^4 crossings of x = 0 in "
        "20000 s, `ldaec --simulate --stats` with default tolerances. "
        "Relay: x > 0 is an event (root finding, a restart of the "
        "integrator, two output rows per event); Smooth: a harmonic "
        "oscillator of the same period over the time that takes it as many "
        "steps (no event: the reference for the cost per event); "
        "RelayNoEvent: the same relay in noEvent, the integrator stepping "
        "across the jumps of the force. Integration time = wall time less initialization as "
        "--stats prints them. The energy v^2/2 + F |x| is conserved; its "
        "largest error over the output rows is what each answer is "
        "worth: Relay's is the integrator's own error at the default "
        "tolerances, about 1.2e-6 per half swing, with no jump at the "
        "events (so the amplitude shrinks and the crossings come a little "
        "early: more than 10^4 in 20000 s).\n\n%s\n\n%s\n" % (
            machine(), table, summary))


if __name__ == "__main__":
    main()
