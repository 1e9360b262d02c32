#!/usr/bin/env python3
"""End-to-end checks of the program `ldaec --emit c --main` writes: --help,
--param re-evaluating bound parameters and start values (against the
analytic solution and against `ldaec --simulate --param`), refusal of a
structural parameter, the same CSV columns as --simulate, a model with no
unknowns, and the refusal of initial equations. Standard library only.

Usage: check_emit_main.py LDAEC MODEL
"""
import csv
import io
import math
import os
import shutil
import subprocess
import sys
import tempfile

SKIP = 77
failures = []


def check(ok, what):
    print(("ok:   " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)


def finish():
    print("%d check(s) failed" % len(failures) if failures else "all passed")
    sys.exit(1 if failures else 0)


def rows(text):
    return [{k: float(v) for k, v in r.items()}
            for r in csv.DictReader(io.StringIO(text))]


def build(ldaec, cc, model, tmp, name, extra=()):
    src, exe = os.path.join(tmp, name + ".c"), os.path.join(tmp, name)
    emit = subprocess.run([ldaec, model, "--emit", "c", "--main", "-o", src]
                          + list(extra), capture_output=True, text=True)
    if emit.returncode != 0:
        return None, emit
    comp = subprocess.run(
        [cc, "-O2", src, "-lsundials_ida", "-lsundials_nvecserial",
         "-lsundials_sunlinsoldense", "-lsundials_sunmatrixdense", "-lm",
         "-o", exe], capture_output=True, text=True)
    check(comp.returncode == 0, "cc compiles the emitted C of " + name)
    if comp.returncode != 0:
        sys.stderr.write(comp.stderr[-3000:])
        finish()
    return exe, emit


def main():
    ldaec, model = sys.argv[1], sys.argv[2]
    cc = shutil.which("cc")
    if not cc:
        print("skipped: no cc")
        sys.exit(SKIP)
    run = lambda args: subprocess.run(args, capture_output=True, text=True,
                                      timeout=60)
    grid = ["--stop", "1", "--interval", "0.25", "--rtol", "1e-9"]
    # The test's own working directory, not the system temporary directory.
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as tmp:
        exe, _ = build(ldaec, cc, model, tmp, "params")

        helped = run([exe, "--help"])
        check(helped.returncode == 0 and "Usage: ./model" in helped.stdout
              and "  k2 = 6\n" in helped.stdout
              and "  n = 2 (fixes the structure)" in helped.stdout,
              "--help prints the usage and the parameters, exit 0")

        for params, k2, x0 in (([], 6, 3), (["k=1"], 3, 2),
                               (["k=1", "k2=10"], 10, 2)):
            args = grid + sum((["--param", p] for p in params), [])
            prog = run([exe] + args)
            sim = run([ldaec, "--no-progress", model, "--simulate"] + args)
            check(prog.returncode == 0 and sim.returncode == 0,
                  "emitted and --simulate exit 0 with %s" % params)
            got, ref = rows(prog.stdout), rows(sim.stdout)
            check(prog.stdout.splitlines()[0] == sim.stdout.splitlines()[0],
                  "same header as --simulate: %s" % prog.stdout.split("\n")[0])
            worst = max(abs(r["x"] - x0 * math.exp(-k2 * r["time"]))
                        for r in got)
            check(len(got) == 5 and worst < 1e-4,
                  "x = %g*exp(-%g t) with %s (max error %.1e)" %
                  (x0, k2, params, worst))
            k = 1 if params else 2
            check(all(abs(r["y"] - (2 * r["x"] + k)) < 1e-7 for r in got),
                  "y = 2x + k with k = %g" % k)
            diff = max(abs(a[c] - b[c]) for a, b in zip(got, ref) for c in a)
            check(diff < 1e-7, "emitted == --simulate with %s (%.1e)" %
                  (params, diff))

        bad = run([exe, "--param", "n=3"])
        check(bad.returncode == 2 and "parameter 'n' fixes the model's "
              "structure" in bad.stderr, "a structural --param exits 2: " +
              bad.stderr.strip())
        bad = run([exe, "--param", "k=abc"])
        check(bad.returncode == 2 and "'abc' is not a finite number" in
              bad.stderr, "--param k=abc exits 2: " + bad.stderr.strip())
        bad = run([exe, "--param", "kk=1"])
        check(bad.returncode == 2 and "no parameter 'kk'" in bad.stderr,
              "--param kk=1 exits 2: " + bad.stderr.strip())
        bad = run([exe, "--stop", "nan"])
        check(bad.returncode == 2, "--stop nan exits 2")

        const = os.path.join(tmp, "const.lsd")
        with open(const, "w") as f:
            f.write("model C\n  parameter Real a = 2;\n  Real x;\n  Real y;\n"
                    "equation\n  x = 0;\n  y = a*x + a;\nend C;\n")
        exe, _ = build(ldaec, cc, const, tmp, "const")
        prog = run([exe] + grid + ["--param", "a=3"])
        got = rows(prog.stdout)
        check(prog.returncode == 0 and len(got) == 5 and
              all(r["x"] == 0 and r["y"] == 3 for r in got),
              "a model with no unknowns writes its closed form (y = a = 3)")

        init = os.path.join(tmp, "init.lsd")
        with open(init, "w") as f:
            f.write("model I\n  Real x;\ninitial equation\n  x = 2;\n"
                    "equation\n  der(x) = -x;\nend I;\n")
        exe, emit = build(ldaec, cc, init, tmp, "init")
        check(exe is None and emit.returncode == 1 and
              "init.lsd:4:3: error: the emitted main cannot honour initial "
              "equations yet" in emit.stderr,
              "--main refuses initial equations at their location: " +
              emit.stderr.strip().split("\n")[0])
    finish()


if __name__ == "__main__":
    main()
