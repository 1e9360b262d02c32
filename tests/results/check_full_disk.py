#!/usr/bin/env python3
"""Results on a full filesystem (issue 28): a 16 KiB tmpfs takes part of a
result, and every writer must say so (exit 1, the file and the reason) and
leave no partial file passed off as whole: the CSV, the .mat file, the
--plot files and a sweep's .mat files. Mounting needs root (CI runs as
root); without it the test is skipped (exit 77).

Usage: check_full_disk.py LDAEC MODEL WORKDIR. Standard library only.
"""
import os
import resource
import subprocess
import sys

LDAEC, MODEL, WORK = sys.argv[1:4]
full = os.path.join(WORK, "full")
os.makedirs(full, exist_ok=True)
subprocess.run(["umount", full], capture_output=True)
if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=16k", "tmpfs", full],
                  capture_output=True).returncode != 0:
    print("skip: cannot mount a tmpfs here (needs root)")
    sys.exit(77)
failures = []


def check(ok, what):
    print(("ok:   " if ok else "FAIL: ") + what)
    if not ok:
        failures.append(what)


def cpu_limit():
    resource.setrlimit(resource.RLIMIT_CPU, (120, 125))


def run(args):
    p = subprocess.run([LDAEC, MODEL, "--simulate", "--stop", "10",
                        "--interval", "0.001", "--no-progress", *args],
                       capture_output=True, text=True, preexec_fn=cpu_limit,
                       timeout=600)
    return p.returncode, p.stderr


try:
    for name, args, says in [
            ("CSV", ["-o", os.path.join(full, "r.csv")],
             "cannot write '%s': No space left on device (the partial file "
             "was removed)" % os.path.join(full, "r.csv")),
            (".mat", ["-o", os.path.join(full, "r.mat")],
             "cannot write '%s': No space left on device (the partial file "
             "was removed)" % os.path.join(full, "r.mat")),
            ("--plot", ["--plot", os.path.join(full, "r.svg"), "-o",
                        os.devnull],
             "No space left on device"),
            ("sweep .mat", ["--sweep", "L=1:2:3", "-o",
                            os.path.join(full, "s.mat")],
             "cannot write '%s': No space left on device (the partial "
             "file was removed)" % os.path.join(full, "s.mat"))]:
        rc, err = run(args)
        check(rc == 1 and says in err,
              "%s on a full disk: exit 1 and the reason (exit %d: %s)"
              % (name, rc, err.strip().splitlines()[-1:] or ""))
        left = os.listdir(full)
        check(not left, "%s: no partial file left (%s)" % (name, left))
        for f in left:
            os.remove(os.path.join(full, f))
finally:
    subprocess.run(["umount", full], capture_output=True)

print("all passed" if not failures else "%d failed" % len(failures))
sys.exit(1 if failures else 0)
