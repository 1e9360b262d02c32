#!/usr/bin/env python3
"""What the -O2 SUNDIALS of scripts/build-sundials.sh gains over Debian's
-O0 libsundials-dev (docs/sundials.md), the same 6.4.1 source both ways:

1. Vector kernels: bench/sundials_kernels.c compiled twice, against the
   static -O2 libraries in the build's LDAEC_SUNDIALS_PREFIX and against
   Debian's shared libraries in /usr/lib; nanoseconds per element.
2. ldaec: the build's ldaec, and the same objects relinked against
   Debian's shared libraries (compiler/driver/ldaec-debian-sundials, the
   build's own link command with the SUNDIALS archives swapped), so only
   the SUNDIALS code differs. Integration time (--stats wall time less the
   consistent initialization) on CascadedFirstOrder
   (tests/models/cascaded_first_order.lsd) and the SciMLBenchmarks RC
   circuit (tests/models/rc_circuit_sciml.lsd), runs interleaved, median.

Usage: run_sundials.py [--build DIR] [--repeat 3] [--quick] [--doc]
  --build  the build directory (default: build)
  --quick  smaller models and shorter kernel timings (a check that it runs)
  --doc    writes the tables into docs/benchmarks.md ("SUNDIALS build").
Standard library only.
"""
import argparse
import os
import re
import shlex
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DOC = os.path.join(ROOT, "docs", "benchmarks.md")
DEBIAN_LIB = "/usr/lib/x86_64-linux-gnu"
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402
from benchrun import integration_time, machine, median, run, stat, word  # noqa: E402

KERNEL_SIZES = [1000, 25600, 1000000]
MODELS = [  # (label, model file, N)
    ("CascadedFirstOrder", "cascaded_first_order.lsd", 6400),
    ("CascadedFirstOrder", "cascaded_first_order.lsd", 25600),
    ("RC circuit (SciML)", "rc_circuit_sciml.lsd", 1000),
]
QUICK_MODELS = [("CascadedFirstOrder", "cascaded_first_order.lsd", 400)]


def cache_value(build, name):
    with open(os.path.join(build, "CMakeCache.txt")) as f:
        for line in f:
            if line.startswith(name + ":"):
                return line.split("=", 1)[1].strip()
    raise RuntimeError("no %s in %s/CMakeCache.txt" % (name, build))


def build_kernels(prefix, tmp):
    """(optimized, debian) kernel benchmark executables."""
    src = os.path.join(HERE, "sundials_kernels.c")
    opt = os.path.join(tmp, "kernels-O2")
    deb = os.path.join(tmp, "kernels-debian")
    lib = os.path.join(prefix, "lib")
    run(["cc", "-O2", "-I" + os.path.join(prefix, "include"), src,
         os.path.join(lib, "libsundials_nvecserial.a"),
         os.path.join(lib, "libsundials_generic.a"), "-lm", "-o", opt])
    run(["cc", "-O2", src, "-L" + DEBIAN_LIB, "-lsundials_nvecserial",
         "-lm", "-o", deb])
    return opt, deb


def kernel_times(exe, n, seconds):
    """{kernel: ns per element}."""
    out, _, _ = run([exe, str(n), str(seconds)])
    return {name: float(ns) for name, _, ns in
            (line.rsplit(" ", 2) for line in out.splitlines())}


def relink_with_debian(build, prefix):
    """The build's ldaec link command with every SUNDIALS archive of the
    prefix replaced by Debian's shared library of the same name."""
    subprocess.run(["ninja", "-C", build, "ldaec"], check=True,
                   stdout=subprocess.DEVNULL)
    commands = subprocess.run(
        ["ninja", "-C", build, "-t", "commands", "compiler/driver/ldaec"],
        check=True, capture_output=True, text=True).stdout.splitlines()
    link = commands[-1]
    archive = re.compile(re.escape(os.path.join(prefix, "lib")) +
                         r"/libsundials_(\w+)\.a")
    if not archive.search(link):
        raise RuntimeError("ldaec's link command names no archive of " + prefix)
    link = archive.sub(lambda m: "%s/libsundials_%s.so" % (DEBIAN_LIB, m.group(1)),
                       link)
    out = "compiler/driver/ldaec-debian-sundials"
    link, count = re.subn(r"-o compiler/driver/ldaec(?=\s)", "-o " + out, link)
    if count != 1:
        raise RuntimeError("no '-o compiler/driver/ldaec' in: " + link)
    subprocess.run(link, shell=True, cwd=build, check=True)
    return os.path.join(build, out)


def simulate(ldaec, model, n):
    """(integration seconds, steps, integrator)."""
    _, err, _ = run([ldaec, "--no-progress", os.path.join(ROOT, "tests", "models", model),
                     "--simulate", "--stats", "--param", "N=%d" % n, "-o", os.devnull])
    return integration_time(err), int(stat(err, "steps")), word(err, "integrator")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--doc", action="store_true")
    args = ap.parse_args()
    if args.doc:
        os.environ["LDAE_BENCH_DOC"] = "1"
    build = os.path.abspath(args.build)
    prefix = cache_value(build, "LDAEC_SUNDIALS_PREFIX")
    seconds = 0.05 if args.quick else 0.3

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        opt, deb = build_kernels(prefix, tmp)
        for n in KERNEL_SIZES:
            fast, slow = kernel_times(opt, n, seconds), kernel_times(deb, n, seconds)
            for name in fast:
                rows.append("| %s | %d | %.2f | %.2f | %.1f |" % (
                    name, n, slow[name], fast[name], slow[name] / fast[name]))
    kernels = "\n".join(rows)

    ours = os.path.join(build, "compiler", "driver", "ldaec")
    theirs = relink_with_debian(build, prefix)
    rows = []
    for label, model, n in (QUICK_MODELS if args.quick else MODELS):
        times = {ours: [], theirs: []}
        steps, integrator = {}, {}
        for _ in range(args.repeat):
            for exe in (theirs, ours):
                t, steps[exe], integrator[exe] = simulate(exe, model, n)
                times[exe].append(t)
        slow, fast = median(times[theirs]), median(times[ours])
        if steps[ours] != steps[theirs]:
            print("note: %s N=%d: %d steps with -O2, %d with Debian's" % (
                label, n, steps[ours], steps[theirs]))
        rows.append("| %s | %d | %s | %d | %.3f | %.3f | %.2f |" % (
            label, n, integrator[ours], steps[ours], slow, fast, slow / fast))
    models = "\n".join(rows)

    section = """## SUNDIALS build

`bench/run_sundials.py` (%s): SUNDIALS 6.4.1 from Debian's source package built with -O2 by `scripts/build-sundials.sh` against Debian's libsundials-dev of the same version (-O0: its `debian/rules` replaces the compiler flags); docs/sundials.md.

Serial vector kernels (`bench/sundials_kernels.c`, the generic `N_V*` calls with fused operations on, best timing), nanoseconds per element:

| kernel | n | Debian -O0 | -O2 | speedup |
|---|---:|---:|---:|---:|
%s

ldaec's integration time (wall time less consistent initialization, median of %d interleaved runs): the build's `ldaec` against the same objects linked with Debian's shared libraries:

| model | N | integrator | steps | Debian -O0 s | -O2 s | speedup |
|---|---:|---|---:|---:|---:|---:|
%s
""" % (machine(), kernels, args.repeat, models)
    write_section(DOC, "SUNDIALS build", section)


if __name__ == "__main__":
    main()
