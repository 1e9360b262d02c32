#!/usr/bin/python3
"""The SGA's cost (issue 14): the "sga" pass of `ldaec --analyze --method
sga --time-passes` on the Cartesian pendulum and on planar pendulum chains
of N bodies (5N unknowns, 3N constraints in 3 generations, dim P_f = 2N),
against structural index reduction of the same model in the same run of the
default method (passes pantelides, dummy-derivatives and build-system), as
a ratio. Best of --repeat runs each.

Usage: bench/run_sga.py [--ldaec build/compiler/driver/ldaec] [--sizes 10,25,50]
                        [--repeat 3]
Prints a table; writes nothing tracked.
"""
import argparse
import os
import re
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def chain(n):
    """A planar chain of n unit links hanging from the origin, straight at
    the start, in Cartesian coordinates with one tension per link."""
    lines = ["model Chain", "  parameter Real L = 1;", "  parameter Real g = 9.81;"]
    for i in range(1, n + 1):
        lines.append(f"  Real x{i}(start = {0.6 * i:.3f}), y{i}(start = {-0.8 * i:.3f}),"
                     f" u{i}(start = 0), v{i}(start = 0), lam{i}(start = 1);")
    lines.append("equation")
    for i in range(1, n + 1):
        px = "0" if i == 1 else f"x{i - 1}"
        py = "0" if i == 1 else f"y{i - 1}"
        nx = f" - lam{i + 1} * (x{i + 1} - x{i})" if i < n else ""
        ny = f" - lam{i + 1} * (y{i + 1} - y{i})" if i < n else ""
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


if __name__ == "__main__":
    main()
