#!/usr/bin/env python3
"""The conformance suite: models from public Modelica test suites, checked
against values that do not come from ldaec (docs/conformance.md).

usage: run.py LDAEC [NAME ...] [--verbose]

Every entry of manifest.json is simulated with ldaec (one run at a time,
CPU time limited) and its checks compared. Each entry ends as one of
  PASS     ldaec ran and every check holds
  REFUSED  ldaec exited 1 with a located diagnostic (file:line:col: error:)
  WRONG    ldaec exited 0 but a value is wrong (the worst outcome)
  FAILS    anything else: numerical failure (exit 3), a crash, a CPU time
           out, a refusal without a location, a missing column or row
An entry with "expect": "error" is a model the source says cannot be
simulated; it passes when ldaec stops with an error (exit 1 or 3) and is
WRONG when ldaec exits 0.
An entry whose outcome is not PASS must be listed with
"known": {"status": "wrong"|"refused"|"fails", ...}; any outcome other
than the expected one (a known failure that now passes, or fails
differently) is unexpected and makes the run fail: update the manifest.
"""
import csv
import json
import math
import os
import re
import resource
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
CPU_SECONDS = 60
LOCATED = re.compile(r"^[^\s:][^:]*:\d+:\d+: error: ")


def limit_cpu():
    resource.setrlimit(resource.RLIMIT_CPU, (CPU_SECONDS, CPU_SECONDS + 5))


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return [], []
    header = rows[0]
    data = []
    for r in rows[1:]:
        if len(r) != len(header):
            continue
        try:
            data.append([float(v) for v in r])
        except ValueError:
            continue
    return header, data


def pick(header, data, variable, time, side):
    """The value of variable at time: of the rows at that time (within
    1e-9, relative), the last one (the value after events at that instant)
    or, with side "left", the first one. At the start time the default is
    the first row: the initial values (what OpenModelica's val(x, 0) reads),
    not those after an event just after the start."""
    if side is None and data and time <= data[0][0]:
        side = "left"
    if variable not in header:
        return None, "no column '%s'" % variable
    col = header.index(variable)
    eps = 1e-9 * max(1.0, abs(time))
    rows = [r for r in data if abs(r[0] - time) <= eps]
    if not rows:
        return None, "no row at time %g" % time
    row = rows[0] if side == "left" else rows[-1]
    return row[col], None


def first_error(text):
    for line in text.splitlines():
        if LOCATED.match(line):
            return line.strip()
    for line in text.splitlines():
        if "error" in line.lower():
            return line.strip()
    lines = [l for l in text.splitlines() if l.strip()]
    return lines[-1].strip() if lines else ""


def run_entry(ldaec, entry, workdir, verbose):
    """Returns (status, detail): status in pass, refused, wrong, fails."""
    model = os.path.join(HERE, entry["file"])
    out = os.path.join(workdir, entry["name"] + ".csv")
    if os.path.exists(out):
        os.remove(out)
    sim = entry.get("simulation", {})
    cmd = [ldaec, model, "--simulate", "-o", out]
    if entry.get("model"):
        cmd += ["--model", entry["model"]]
    if "start" in sim:
        cmd += ["--start", repr(float(sim["start"]))]
    if "stop" in sim:
        cmd += ["--stop", repr(float(sim["stop"]))]
    if "tolerance" in sim:
        cmd += ["--rtol", repr(float(sim["tolerance"]))]
    # The start row is always written; --output-times takes (start, stop].
    start = float(sim.get("start", 0.0))
    times = sorted({float(c["time"]) for c in entry.get("checks", [])
                    if float(c["time"]) > start})
    if sim.get("interval"):
        cmd += ["--interval", repr(float(sim["interval"]))]
    elif times:
        # The stop time is always an output time: ldaec 2025-11 fails at the
        # stop time (CVodeGetDky flag -25) when the last output time is
        # before it (docs/conformance.md), which is not what these models test.
        if "stop" in sim and float(sim["stop"]) > start and float(sim["stop"]) not in times:
            times.append(float(sim["stop"]))
        cmd += ["--output-times", ",".join(repr(t) for t in times)]
    cmd += sim.get("extra_args", [])
    if verbose:
        print("  $ " + " ".join(cmd))
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           preexec_fn=limit_cpu, text=True, errors="replace")
    except OSError as e:
        return "fails", "cannot run ldaec: %s" % e
    text = p.stderr + p.stdout
    rc = p.returncode
    if entry.get("expect") == "error":
        if rc in (1, 3):
            return "pass", "stopped as expected (exit %d): %s" % (rc, first_error(text))
        if rc == 0:
            return "wrong", "exit 0, but the source says the run cannot succeed"
        return "fails", "exit %d: %s" % (rc, first_error(text))
    if rc == 1:
        err = first_error(text)
        if LOCATED.match(err):
            return "refused", err
        return "fails", "exit 1 without a located diagnostic: %s" % err
    if rc < 0:
        return "fails", "killed by signal %d (CPU limit %d s?)" % (-rc, CPU_SECONDS)
    if rc != 0:
        return "fails", "exit %d: %s" % (rc, first_error(text))
    if not os.path.exists(out):
        return "fails", "exit 0 but no result file"
    header, data = read_csv(out)
    bad = []
    missing = []
    for c in entry["checks"]:
        got, why = pick(header, data, c["variable"], float(c["time"]), c.get("side"))
        if why:
            missing.append("%s at %g: %s" % (c["variable"], c["time"], why))
            continue
        exp = float(c["expected"])
        if not (math.isfinite(got) and abs(got - exp) <= float(c["tol"])):
            bad.append("%s(%g) expected %.10g got %.10g (tol %g)"
                       % (c["variable"], c["time"], exp, got, c["tol"]))
    if missing:
        return "fails", "; ".join(missing + bad)
    if bad:
        return "wrong", "; ".join(bad)
    return "pass", "%d checks" % len(entry["checks"])


def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    verbose = "--verbose" in argv
    if not args:
        print(__doc__)
        return 2
    ldaec = os.path.abspath(args[0])
    only = set(args[1:])
    with open(os.path.join(HERE, "manifest.json")) as f:
        manifest = json.load(f)
    entries = [e for e in manifest["models"] if not only or e["name"] in only]
    counts = {"pass": 0, "refused": 0, "wrong": 0, "fails": 0}
    unexpected = []
    with tempfile.TemporaryDirectory(prefix="ldaec-conformance-") as work:
        for e in entries:
            status, detail = run_entry(ldaec, e, work, verbose)
            counts[status] += 1
            known = e.get("known", {}).get("status")
            want = known or "pass"
            label = {"pass": "PASS", "refused": "REFUSED", "wrong": "WRONG",
                     "fails": "FAILS"}[status]
            note = ""
            if status != want:
                unexpected.append(e["name"])
                if known and status == "pass":
                    note = "  [UNEXPECTED: known as %s but now passes: update manifest.json]" % known
                elif known:
                    note = "  [UNEXPECTED: known as %s: update manifest.json or fix ldaec]" % known
                else:
                    note = "  [UNEXPECTED]"
            elif known:
                note = "  [known: %s]" % e["known"].get("issue", "")
            print("%-8s %-32s %s%s" % (label, e["name"], detail, note), flush=True)
    print("summary: %d models: %d pass, %d refused, %d wrong, %d fails"
          % (len(entries), counts["pass"], counts["refused"], counts["wrong"], counts["fails"]))
    ok = len(entries) - len(unexpected)
    print("conformance: %d passed, %d failed" % (ok, len(unexpected)))
    return 1 if unexpected else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
