#!/usr/bin/env python3
"""End-to-end checks of the program `ldaec --emit c --main` writes, built
with the exact command its header prints (libldaert) and compared with
`ldaec --simulate`, which runs the same runtime code.

Cases:
  params MODEL  --help; --param re-evaluating bound parameters and start
                values (analytic solution and --simulate); refusal of a
                structural parameter; the CSV columns; a model with no
                unknowns; initial equations and a fixed algebraic value
                (refused before the runtime took over); --integrator (an
                ODE: CVODE by default) and --stats; a numerical failure
                (exit 3, rows kept)
  andrews MODEL Andrews' squeezing mechanism (q[1] fixed and algebraic in
                the first state set): the Bari test set's reference at 0.03
  pendulum MODEL the Cartesian pendulum from theta0 = 1.5: the state set
                switches as in --simulate, the same values; theta0 given
                at run time instead
Standard library only.

Usage: check_emit_main.py LDAEC CASE MODEL
"""
import io
import json
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

from check_e2e import ROOT, SKIP, check, finish, read_csv, stat


def rows(text):
    return read_csv(io.StringIO(text))


def run(args):
    return subprocess.run(args, capture_output=True, text=True, timeout=120)


def simulate(ldaec, model, args):
    return run([ldaec, "--no-progress", model, "--simulate"] + args)


def compile_command(src, exe):
    """The command the header of the emitted `src` prints, building `exe`:
    its `NAME.c` and `-o NAME` point at `src` and `exe`."""
    with open(src) as f:
        header = f.read(4000)
    m = re.search(r"Compile \(docs/embedding-c\.md\):\n\s*(cc .*)\n", header)
    if not m:
        return None
    words = shlex.split(m.group(1))
    for i, w in enumerate(words):
        if w.endswith(".c"):
            words[i] = src
        elif i > 0 and words[i - 1] == "-o":
            words[i] = exe
    return words


def compile_emitted(src, exe):
    """Builds the emitted program with its own command; the cc result (or
    None when the header has no command)."""
    cmd = compile_command(src, exe)
    if cmd is None:
        return None
    if not shutil.which(cmd[0]):
        print("skipped: no cc")
        sys.exit(SKIP)
    return run(cmd)


def build(ldaec, model, tmp, name, extra=()):
    src, exe = os.path.join(tmp, name + ".c"), os.path.join(tmp, name)
    emit = run([ldaec, model, "--emit", "c", "--main", "-o", src] +
               list(extra))
    check(emit.returncode == 0, "ldaec --emit c --main exits 0 on " + name)
    if emit.returncode != 0:
        sys.stderr.write(emit.stderr[-3000:])
        finish()
    comp = compile_emitted(src, exe)
    check(comp is not None and comp.returncode == 0,
          "the header's command compiles %s: %s" %
          (name, " ".join(compile_command(src, exe) or ["(none)"])))
    if comp is None or comp.returncode != 0:
        sys.stderr.write(comp.stderr[-3000:] if comp else "")
        finish()
    return exe


def same(prog, sim, what, tol):
    """The emitted program's CSV equals --simulate's to `tol` (absolute),
    header and row count exactly."""
    check(prog.returncode == sim.returncode,
          "%s: both exit %d (%d)" % (what, sim.returncode, prog.returncode))
    check(prog.stdout.split("\n")[0] == sim.stdout.split("\n")[0],
          "%s: same header as --simulate: %s" %
          (what, prog.stdout.split("\n")[0][:100]))
    got, ref = rows(prog.stdout), rows(sim.stdout)
    diff = max((abs(a[c] - b[c]) for a, b in zip(got, ref) for c in a),
               default=0.0)
    check(len(got) == len(ref) and len(got) > 0 and diff <= tol,
          "%s: %d rows, emitted == --simulate to %.0e (%.1e)" %
          (what, len(got), tol, diff))
    return got


def write(tmp, name, text):
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def params(ldaec, model, tmp):
    grid = ["--stop", "1", "--interval", "0.25", "--rtol", "1e-9"]
    exe = build(ldaec, model, tmp, "params")

    helped = run([exe, "--help"])
    check(helped.returncode == 0 and "Usage: ./model" in helped.stdout
          and "  k2 = 6\n" in helped.stdout
          and "  n = 2 (fixes the structure)" in helped.stdout
          and "--integrator" in helped.stdout,
          "--help prints the usage and the parameters, exit 0")

    for ps, k2, x0 in (([], 6, 3), (["k=1"], 3, 2),
                       (["k=1", "k2=10"], 10, 2)):
        args = grid + sum((["--param", p] for p in ps), [])
        got = same(run([exe] + args), simulate(ldaec, model, args),
                   "--param %s" % ps, 1e-7)
        worst = max(abs(r["x"] - x0 * math.exp(-k2 * r["time"]))
                    for r in got)
        check(len(got) == 5 and worst < 1e-4,
              "x = %g*exp(-%g t) with %s (max error %.1e)" %
              (x0, k2, ps, worst))
        k = 1 if ps else 2
        check(all(abs(r["y"] - (2 * r["x"] + k)) < 1e-7 for r in got),
              "y = 2x + k with k = %g" % k)

    for args, code, text in (
            (["--param", "n=3"], 2, "parameter 'n' fixes the model's "
             "structure"),
            (["--param", "k=abc"], 2, "'abc' is not a finite number"),
            (["--param", "kk=1"], 2, "no parameter 'kk'; did you mean 'k'"),
            (["--stop", "nan"], 2, "--stop: 'nan' is not a finite number"),
            (["--integrator", "rk4"], 2, "--integrator: 'rk4' is not one of"),
            (["--algebraic-error-test", "yes"], 2,
             "--algebraic-error-test: 'yes' is not one of on, off, auto"),
            (["--stop", "-1"], 2, "the stop time -1 is before the start "
             "time 0"),
            (["--frobnicate"], 2, "unknown option '--frobnicate'"),
            (["--rtol"], 2, "option '--rtol' needs a value"),
            (["-o", os.path.join(tmp, "no", "such", "dir.csv")], 2,
             "cannot write")):
        bad = run([exe] + args)
        check(bad.returncode == code and bad.stdout == "" and
              bad.stderr.startswith("error: ") and text in bad.stderr,
              "%s exits %d before any work: %s" %
              (" ".join(args), code, bad.stderr.strip()[:120]))

    # --stats, --integrator and --algebraic-error-test reach the runtime.
    for extra in (["--integrator", "ida"],
                  ["--integrator", "auto", "--algebraic-error-test", "on"]):
        prog = run([exe] + grid + extra + ["--stats"])
        check(prog.returncode == 0 and stat(prog.stderr, "steps") and
              len(rows(prog.stdout)) == 5,
              "%s --stats: %s steps on stderr, 5 rows" %
              (" ".join(extra), stat(prog.stderr, "steps")))
    out = os.path.join(tmp, "out.csv")
    prog = run([exe] + grid + ["-o", out])
    with open(out) as f:
        check(prog.returncode == 0 and prog.stdout == "" and
              len(rows(f.read())) == 5, "-o FILE writes the CSV there")

    const = write(tmp, "const.lsd",
                  "model C\n  parameter Real a = 2;\n  Real x;\n  Real y;\n"
                  "equation\n  x = 0;\n  y = a*x + a;\nend C;\n")
    exe = build(ldaec, const, tmp, "const")
    prog = run([exe] + grid + ["--param", "a=3"])
    got = rows(prog.stdout)
    check(prog.returncode == 0 and len(got) == 5 and
          all(r["x"] == 0 and r["y"] == 3 for r in got),
          "a model with no unknowns writes its closed form (y = a = 3)")

    # Refused by --emit c --main before the runtime ran the program: an
    # initial equation, a fixed algebraic value. Both give x = 2 exp(-t).
    for name, text, what in (
            ("init", "model I\n  Real x;\ninitial equation\n  x = 2;\n"
             "equation\n  der(x) = -x;\nend I;\n", "initial equation x = 2"),
            ("fixed", "model F\n  Real x;\n  Real y(start = 3, fixed = true);"
             "\nequation\n  der(x) = -x;\n  y = x + 1;\nend F;\n",
             "fixed algebraic y(0) = 3, y = x + 1")):
        lsd = write(tmp, name + ".lsd", text)
        exe = build(ldaec, lsd, tmp, name)
        got = same(run([exe] + grid), simulate(ldaec, lsd, grid), what, 1e-9)
        worst = max(abs(r["x"] - 2 * math.exp(-r["time"])) +
                    abs(r.get("y", r["x"] + 1) - r["x"] - 1) for r in got)
        check(worst < 1e-6, "%s met: x = 2 exp(-t) (%.1e)" % (what, worst))

    # An explicit ODE: auto picks CVODE; --integrator picks as in ldaec.
    osc = write(tmp, "osc.lsd",
                "model O\n  Real x(start = 1, fixed = true);\n"
                "  Real v(start = 0, fixed = true);\nequation\n"
                "  der(x) = v;\n  der(v) = -x;\nend O;\n")
    exe = build(ldaec, osc, tmp, "osc")
    which = lambda text: (re.findall(r"^integrator\s+(.*)$", text, re.M)
                          or ["?"])[0]
    for integ, name in (("auto", "CVODE (BDF)"), ("ida", "IDA"),
                        ("cvode-adams", "CVODE (Adams)")):
        args = ["--stop", "10", "--integrator", integ, "--stats"]
        prog, sim = run([exe] + args), simulate(ldaec, osc, args)
        check(which(prog.stderr) == name == which(sim.stderr) and
              prog.stdout == sim.stdout and prog.returncode == 0,
              "--integrator %s: %s ran, CSV byte-equal to --simulate's" %
              (integ, which(prog.stderr)))

    # A numerical failure: the runtime's report, exit 3, rows kept.
    blow = write(tmp, "blow.lsd",
                 "model B\n  Real x(start = 1, fixed = true);\n  Real y;\n"
                 "equation\n  der(x) = -1;\n  y = sqrt(x);\nend B;\n")
    exe = build(ldaec, blow, tmp, "blow")
    args = ["--stop", "2", "--interval", "0.25"]
    prog, sim = run([exe] + args), simulate(ldaec, blow, args)
    got = rows(prog.stdout)
    def error_line(text):
        return next((l for l in text.split("\n") if "error: " in l), "")
    check(prog.returncode == 3 and 1 <= len(got) < 9 and
          all(r["time"] <= 1 for r in got) and
          len(got) == len(rows(sim.stdout)),
          "sqrt of a negative x: exit 3, the %d rows before it kept (as "
          "--simulate)" % len(got))
    mine = error_line(prog.stderr)
    check(mine.startswith("error: simulation failed at t = ") and
          mine[len("error: "):] in error_line(sim.stderr),
          "the failure report of --simulate: " + mine[:120])


def andrews(ldaec, model, tmp):
    """q[1] is fixed and algebraic in the first state set: IDACalcIC could
    not hold it, the runtime's initialization does."""
    with open(os.path.join(ROOT, "bench", "bari", "reference.json")) as f:
        ref = json.load(f)["andrews"]
    exe = build(ldaec, model, tmp, "andrews")
    args = ["--rtol", "1e-8", "--atol", "1e-8", "--interval", "0.003"]
    got = same(run([exe] + args), simulate(ldaec, model, args),
               "andrews, rtol = atol = 1e-8", 1e-6)
    last = got[-1]
    check(abs(last["time"] - ref["t_end"]) < 1e-12,
          "the last row is at t = %g" % ref["t_end"])
    err = max(abs(last[n] - r) / abs(r) for n, r in
              zip(ref["names"][:ref["scd_components"]], ref["reference"]))
    scd = -math.log10(max(err, 1e-16))
    check(scd >= 4, "the 7 positions at t = 0.03 match the test set's "
          "reference: scd %.2f >= 4" % scd)
    q1 = -0.0617138900142764496358948458001
    check(abs(got[0]["q[1]"] - q1) <= 1e-12 * abs(q1),
          "q[1](0) keeps its fixed start value (%r)" % got[0]["q[1]"])


def pendulum(ldaec, model, tmp):
    # Started near the horizontal (theta0 = 1.5), the pendulum changes
    # state set twice per swing.
    args = ["--rtol", "1e-9", "--stop", "10", "--interval", "0.05", "--stats"]
    theta = ["--param", "theta0=1.5"]
    exe = build(ldaec, model, tmp, "pendulum", theta)
    prog, sim = run([exe] + args), simulate(ldaec, model, args + theta)
    got = same(prog, sim, "pendulum from theta0 = 1.5, 0..10 s, rtol 1e-9",
               0.0)
    switches = stat(prog.stderr, "state set switches")
    check(switches is not None and switches >= 10 and
          switches == stat(sim.stderr, "state set switches"),
          "the state set switches %s times, as in --simulate (%s)" %
          (switches, stat(sim.stderr, "state set switches")))
    check(prog.stderr.count("state selection switched from") == switches,
          "each switch is reported on stderr")
    drift = max(abs(r["x"] ** 2 + r["y"] ** 2 - 1) for r in got)
    check(drift < 1e-7, "on the circle throughout (|x^2 + y^2 - 1| <= %.1e)"
          % drift)

    # theta0 changed at run time: the start values are re-bound, but the
    # choices made at compile time from the start values (which state set
    # comes first) stay, so the values agree to the integration error.
    exe = build(ldaec, model, tmp, "pendulum05")
    prog = run([exe] + args + theta)
    again = rows(prog.stdout)
    diff = max(abs(a[c] - b[c]) for a, b in zip(again, got) for c in "xy")
    check(prog.returncode == 0 and len(again) == len(got) and diff < 1e-4,
          "--param theta0=1.5 at run time: x, y as compiled with it "
          "(%.1e)" % diff)
    check(stat(prog.stderr, "state set switches") == switches,
          "and the same %s switches" % stat(prog.stderr,
                                            "state set switches"))


def main():
    ldaec, case, model = sys.argv[1], sys.argv[2], sys.argv[3]
    if not shutil.which("cc"):
        print("skipped: no cc")
        sys.exit(SKIP)
    # The test's own working directory, not the system temporary directory.
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as tmp:
        {"params": params, "andrews": andrews,
         "pendulum": pendulum}[case](ldaec, model, tmp)
    finish()


if __name__ == "__main__":
    main()
