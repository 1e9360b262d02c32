#!/usr/bin/python3
"""End-to-end benchmarks of the ldaec binary (bench/run_e2e.sh runs this):

1. Robertson (tests/models/robertson_sundials.lsd, idaRoberts_dns.c's
   tolerances and output times) vs SUNDIALS' example compiled with -O2:
   steps, integration time (ldaec's --stats "wall time": initialization and
   integration, no compilation) vs the example's main called in a loop;
   compile time reported separately.
2. `ldaec examples/pendulum.lsd --simulate` parse-to-CSV process wall time.
3. Compile time (parse to ready to integrate, `--simulate --compile-only`)
   of examples/rc_ladder.lsd for N sections, per stage (--time-passes),
   with the LLVM JIT and with the interpreter (--jit off); chart to
   docs/e2e_compile_time.png.
Every figure is the minimum of several runs (the machine is shared).
Writes the `## End to end` section of docs/benchmarks.md.
Usage: /usr/bin/python3 bench/e2e_bench.py LDAEC
"""
import os
import re
import subprocess
import sys
import tempfile
import time

from benchdoc import write_section

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOCS = os.path.join(ROOT, "docs")
EXAMPLE = "/usr/share/doc/libsundials-dev/examples/ida/serial/idaRoberts_dns.c"
# The -O2 SUNDIALS ldaec links (docs/sundials.md), not Debian's -O0 one.
SUNDIALS = os.environ.get("LDAEC_SUNDIALS_PREFIX", "/opt/ldaec/sundials-6.4.1")
LIBS = ["-I" + SUNDIALS + "/include", "-L" + SUNDIALS + "/lib",
        "-lsundials_ida", "-lsundials_nvecserial", "-lsundials_sunlinsoldense",
        "-lsundials_sunmatrixdense", "-lm"]
ROBERTSON_TIMES = ",".join("%g" % (0.4 * 10**k) for k in range(12))
LADDER_JIT = [10, 100, 1000, 10**4, 10**5]
LADDER_INTERP = [10, 100, 1000, 10**4]
TIMEOUT = 600


def ldaec_run(ldaec, args):
    t0 = time.perf_counter()
    p = subprocess.run([ldaec, "--no-progress"] + args, capture_output=True,
                       text=True, timeout=TIMEOUT)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError("ldaec %s: exit %d\n%s" %
                           (" ".join(args), p.returncode, p.stderr[-2000:]))
    return wall, p.stderr


def number(text, label):
    m = re.search(r"^%s:?\s+([0-9.eE+-]+)" % re.escape(label), text, re.M)
    return float(m.group(1)) if m else float("nan")


def robertson(ldaec, reps=20):
    args = [os.path.join(ROOT, "tests", "models", "robertson_sundials.lsd"),
            "--simulate", "--rtol", "1e-4", "--atol", "1e-6",
            "--algebraic-error-test", "on", "--output-times", ROBERTSON_TIMES,
            "--stats", "-o", os.devnull]
    integ, comp, steps = [], [], 0
    for _ in range(reps):
        _, err = ldaec_run(ldaec, args)
        integ.append(number(err, "wall time"))
        comp.append(number(err, "compile time"))
        steps = int(number(err, "steps"))
    with tempfile.TemporaryDirectory() as tmp:
        harness = os.path.join(tmp, "harness.c")
        with open(harness, "w") as f:
            f.write(HARNESS)
        obj = os.path.join(tmp, "roberts.o")
        subprocess.run(["cc", "-O2", "-Dmain=example_main", "-c", EXAMPLE,
                        "-o", obj], check=True)
        exe = os.path.join(tmp, "theirs")
        subprocess.run(["cc", "-O2", harness, obj, "-o", exe] + LIBS,
                       check=True)
        plain = os.path.join(tmp, "example")
        subprocess.run(["cc", "-O2", EXAMPLE, "-o", plain] + LIBS, check=True)
        out = subprocess.run([plain], capture_output=True, text=True).stdout
        their_steps = int(re.search(r"^Steps\s*=\s*(\d+)", out, re.M).group(1))
        p = subprocess.run([exe, "200"], capture_output=True, text=True)
        their_us = float(re.search(r"us_per_run=([0-9.]+)", p.stderr).group(1))
    return {"steps": steps, "their_steps": their_steps,
            "us": min(integ) * 1e6, "their_us": their_us,
            "compile_ms": min(comp) * 1e3}


HARNESS = r"""
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
int example_main(void);
static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
/* The example's main, run `reps` times per batch; best batch reported. */
int main(int argc, char **argv) {
  int reps = argc > 1 ? atoi(argv[1]) : 200;
  double best = 1e300;
  fflush(stdout);
  if (!freopen("/dev/null", "w", stdout)) return 1;
  for (int b = 0; b < 5; ++b) {
    double t0 = now();
    for (int i = 0; i < reps; ++i) example_main();
    double us = (now() - t0) * 1e6 / reps;
    if (us < best) best = us;
  }
  fprintf(stderr, "us_per_run=%.1f\n", best);
  return 0;
}
"""


def pendulum(ldaec, reps=10):
    args = [os.path.join(ROOT, "examples", "pendulum.lsd"), "--simulate",
            "-o", os.devnull]
    return min(ldaec_run(ldaec, args)[0] for _ in range(reps))


def ladder(ldaec, n, jit, reps):
    """Min over reps of (process wall, frontend, passes, codegen) in ms."""
    args = [os.path.join(ROOT, "examples", "rc_ladder.lsd"), "--param",
            "N=%d" % n, "--simulate", "--compile-only", "--time-passes",
            "--jit", "on" if jit else "off"]
    best = None
    for _ in range(reps):
        wall, err = ldaec_run(ldaec, args)
        row = (wall * 1e3, number(err, "frontend"), number(err, "passes"),
               number(err, "codegen"))
        if best is None or row[0] < best[0]:
            best = row
    return best


def chart(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for jit, style in ((True, "o-"), (False, "s--")):
        pts = [(n, r) for (n, j, r) in rows if j == jit]
        ns = [n for n, _ in pts]
        ax.loglog(ns, [r[0] / 1e3 for _, r in pts], style,
                  label="total, %s" % ("LLVM JIT" if jit else "interpreter"))
        if jit:
            ax.loglog(ns, [r[3] / 1e3 for _, r in pts], "x:",
                      label="codegen (JIT)")
        else:
            ax.loglog(ns, [r[1] / 1e3 for _, r in pts], "^:",
                      label="frontend")
            ax.loglog(ns, [r[2] / 1e3 for _, r in pts], "v:", label="passes")
    ns = LADDER_JIT
    ax.loglog(ns, [0.2e-3 * n for n in ns], "k-", lw=0.8,
              label="target 0.2 ms per section")
    ax.loglog(ns, [5.4e-3 * n for n in ns], "k:", lw=0.8,
              label="Dymola, about 5.4 ms per element")
    ax.set_xlabel("RC ladder sections N")
    ax.set_ylabel("parse to ready to integrate (s)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ldaec = os.path.abspath(sys.argv[1])
    rob = robertson(ldaec)
    print("robertson", rob)
    pend = pendulum(ldaec)
    print("pendulum %.3f s" % pend)
    rows = []
    for jit, ns in ((True, LADDER_JIT), (False, LADDER_INTERP)):
        for n in ns:
            reps = 3 if n < 1000 else 1
            r = ladder(ldaec, n, jit, reps)
            print("ladder N=%d jit=%s %s" % (n, jit, r), flush=True)
            rows.append((n, jit, r))
    # The chart is a tracked file: written only with --doc (run_e2e.sh).
    if os.environ.get("LDAE_BENCH_DOC") == "1":
        chart(rows, os.path.join(DOCS, "e2e_compile_time.png"))
    write_e2e_section(rob, pend, rows)


def ladder_findings(rows):
    """Per-section cost, growth per 10x and the largest stage, from the JIT
    rows."""
    jit = sorted((n, r) for n, j, r in rows if j)
    lines = []
    for (n0, r0), (n1, r1) in zip(jit, jit[1:]):
        lines.append("N = %d -> %d: total %.1fx (frontend %.1fx, passes "
                     "%.1fx, codegen %.1fx)" % (n0, n1, r1[0] / r0[0],
                                               r1[1] / r0[1], r1[2] / r0[2],
                                               r1[3] / r0[3]))
    n, r = jit[-1]
    stages = {"frontend": r[1], "passes": r[2], "codegen": r[3]}
    worst = max(stages, key=stages.get)
    per = r[0] / n
    verdict = "met" if per <= 0.2 and all(
        r1[0] / r0[0] <= 12 * n1 / n0 / 10 for (n0, r0), (n1, r1) in
        zip(jit, jit[1:]) if n0 >= 1000) else "not met"
    return ("With the JIT at N = %d: %.3f ms per section in total "
            "(frontend %.3f, passes %.3f, codegen %.3f ms); the largest "
            "stage is %s. Target (at most 0.2 ms per section, linear): "
            "**%s**.\n\nGrowth (process wall time, then per stage):\n%s" %
            (n, per, r[1] / n, r[2] / n, r[3] / n, worst, verdict,
             "\n".join("- " + l for l in lines)))


def write_e2e_section(rob, pend, rows):
    stepdiff = 100.0 * (rob["steps"] - rob["their_steps"]) / rob["their_steps"]
    ratio = rob["us"] / rob["their_us"]
    table = "\n".join(
        "| %d | %s | %.1f | %.1f | %.1f | %.1f | %.3f |" %
        (n, "JIT" if j else "interpreter", r[0], r[1], r[2], r[3],
         r[0] / n) for n, j, r in rows)
    findings = ladder_findings(rows)
    section = f"""## End to end

`bench/run_e2e.sh` (the real `ldaec` binary; minimum of repeated runs;
{time.strftime('%Y-%m-%d', time.gmtime())}).

**Robertson vs SUNDIALS.** `tests/models/robertson_sundials.lsd` at
`idaRoberts_dns.c`'s settings (rtol 1e-4, atol 1e-8/1e-6/1e-6 through
`--atol 1e-6` and nominal 1e-2 on y1, `--algebraic-error-test`, outputs at
0.4·10^k to 4e10) vs the example compiled with -O2 (its `main` in a loop,
printing to /dev/null). ldaec's time is the `--stats` wall time
(initialization + integration, compilation excluded).

| | steps | integration | compile |
|---|---:|---:|---:|
| ldaec | {rob['steps']} | {rob['us']:.0f} µs | {rob['compile_ms']:.1f} ms |
| idaRoberts_dns.c | {rob['their_steps']} | {rob['their_us']:.0f} µs | (cc, offline) |
| ratio | {stepdiff:+.1f} % | {ratio:.2f}x | targets: steps within 10 %, time ≤ 1.2x |

**Pendulum, parse to CSV.** `ldaec examples/pendulum.lsd --simulate -o
/dev/null` (10 s, 500 output rows): {pend * 1e3:.0f} ms process wall time
(target < 300 ms).

**Compile time of an RC ladder.** `examples/rc_ladder.lsd --param N=...
--simulate --compile-only --time-passes`: parse to a model ready to
integrate (JIT-compiled, or the interpreter's tables with `--jit off`). Times
in ms; the last column is the total per section (target ≤ 0.2 ms; a
published figure for Dymola is about 5.4 ms per element).

| N | codegen | total | frontend | passes | codegen | total per section |
|---:|---|---:|---:|---:|---:|---:|
{table}

![compile time](e2e_compile_time.png)

{findings}

The Robertson comparison is favourable because the example's run also
creates its SUNContext, evaluates two root functions (404 evaluations) and
prints; ldaec's figure excludes process start-up and compilation.

Work-precision charts (`bench/work_precision.py` on the real driver):
[pendulum](work_precision_pendulum.png)
([table](work_precision_pendulum.csv)),
[Robertson](work_precision_robertson.png)
([table](work_precision_robertson.csv)).
"""
    doc = os.path.join(DOCS, "benchmarks.md")
    write_section(doc, "End to end", section)


if __name__ == "__main__":
    main()
