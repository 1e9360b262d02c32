#!/usr/bin/python3
"""The SGA's cost (issue 14): the "sga" pass of `ldaec --analyze --method
sga --time-passes` on the Cartesian pendulum and on planar pendulum chains
of N bodies (5N unknowns, 3N constraints in 3 generations, dim P_f = 2N),
against structural index reduction of the same model in the same run of the
default method (passes pantelides, dummy-derivatives and build-system), as
a ratio. Best of --repeat runs each. Then each chain simulated for --stop
seconds with `--method sga` at --rtol (CVODE on the vector field of P_f,
projected onto the constraints after every step): wall time, steps, the
largest constraint residual of the run (--stats) and the time of the sga
pass in that run.

Usage: bench/run_sga.py [--ldaec build/compiler/driver/ldaec] [--sizes 10,25,50]
                        [--repeat 3] [--stop 10] [--rtol 1e-8]
Prints two tables; writes nothing tracked.
"""
import argparse
import os
import re
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def chain(n):
    """A planar chain of n unit links with unit masses hanging from the
    origin, straight at the start, in Cartesian coordinates with one
    tension per link: link i pulls mass i towards mass i - 1 and mass
    i - 1 towards mass i (equal and opposite), so the multipliers' matrix
    G G^T is nonsingular everywhere. (With the pull on mass i - 1 reversed,
    as this function once wrote it, that matrix is singular wherever two
    links are perpendicular: the 3-link chain stopped at t = 0.97.)"""
    lines = ["model Chain", "  parameter Real L = 1;", "  parameter Real g = 9.81;"]
    for i in range(1, n + 1):
        lines.append(f"  Real x{i}(start = {0.6 * i:.3f}), y{i}(start = {-0.8 * i:.3f}),"
                     f" u{i}(start = 0), v{i}(start = 0), lam{i}(start = 1);")
    lines.append("equation")
    for i in range(1, n + 1):
        px = "0" if i == 1 else f"x{i - 1}"
        py = "0" if i == 1 else f"y{i - 1}"
        nx = f" + lam{i + 1} * (x{i + 1} - x{i})" if i < n else ""
        ny = f" + lam{i + 1} * (y{i + 1} - y{i})" if i < n else ""
        lines += [f"  der(x{i}) = u{i};", f"  der(y{i}) = v{i};",
                  f"  der(u{i}) = -lam{i} * (x{i} - {px}){nx};",
                  f"  der(v{i}) = -lam{i} * (y{i} - {py}){ny} - g;",
                  f"  (x{i} - {px})^2 + (y{i} - {py})^2 = L^2;"]
    lines.append("end Chain;")
    return "\n".join(lines) + "\n"


def pass_times(cmd, names, repeat):
    """Best over `repeat` runs of the summed --time-passes seconds of
    `names`, and the report of the last run."""
    best, out = None, ""
    for _ in range(repeat):
        p = subprocess.run(cmd + ["--time-passes"], capture_output=True, text=True)
        out = p.stdout
        t = sum(float(m.group(1)) for m in
                re.finditer(r"^\s*([0-9.]+) s  (\S+)$", p.stderr, re.M)
                if m.group(2) in names)
        best = t if best is None else min(best, t)
    return best, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ldaec", default=os.path.join(ROOT, "build", "compiler", "driver", "ldaec"))
    ap.add_argument("--sizes", default="10,25,50")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--stop", default="10")
    ap.add_argument("--rtol", default="1e-8")
    args = ap.parse_args()
    models = [("pendulum", os.path.join(ROOT, "examples", "pendulum.lsd"))]
    tmp = tempfile.mkdtemp(prefix="ldaec-sga-")
    for n in (int(s) for s in args.sizes.split(",")):
        path = os.path.join(tmp, f"chain{n}.lsd")
        with open(path, "w") as f:
            f.write(chain(n))
        models.append((f"chain N={n}", path))
    print("| model | SGA (s) | structural reduction (s) | ratio | SGA verdict |")
    print("|---|---|---|---|---|")
    structural = {"pantelides", "dummy-derivatives", "build-system"}
    for name, path in models:
        t_sga, out = pass_times([args.ldaec, path, "--analyze", "--method", "sga"],
                                {"sga"}, args.repeat)
        t_dd, _ = pass_times([args.ldaec, path, "--analyze"], structural, args.repeat)
        m = re.search(r"geometric algorithm:\s+(.*)", out)
        ratio = f"{t_sga / t_dd:.1f}" if t_dd > 0 else "n/a (below 0.1 ms)"
        print(f"| {name} | {t_sga:.4f} | {t_dd:.4f} | {ratio} | "
              f"{m.group(1) if m else '?'} |")
    print()
    print(f"| model | --simulate --method sga, {args.stop} s, rtol {args.rtol}: "
          "wall (s) | steps | largest drift | sga pass (s) | exit |")
    print("|---|---|---|---|---|---|")
    for name, path in models[1:]:
        simulate(args, name, path)


def simulate(args, name, path):
    cmd = [args.ldaec, path, "--simulate", "--method", "sga", "--stop",
           args.stop, "--rtol", args.rtol, "--stats", "--no-progress",
           "--time-passes", "-o", os.devnull]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0

    def stat(key):
        m = re.search(r"^%s\s+(\S+)" % key, p.stderr, re.M)
        return m.group(1) if m else "?"

    m = re.search(r"^\s*([0-9.]+) s  sga$", p.stderr, re.M)
    print(f"| {name} | {wall:.2f} | {stat('steps')} | "
          f"{stat('largest drift residual')} | {m.group(1) if m else '?'} | "
          f"{p.returncode} |")


if __name__ == "__main__":
    main()
