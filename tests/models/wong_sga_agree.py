#!/usr/bin/env python3
"""Issue 14: "Wong and SGA agree (dim V = dim P_f) on every linear example
and test model". Runs `ldaec FILE --analyze --json` on every .lsd under
examples/ and tests/ and, for each model the linear pass recognizes as
E x' = F x + f(t) and the SGA decides, checks that the two analyses agree:

- unique: the pencil is regular and dim V (the limit of the first Wong
  sequence) = dim P_f;
- not unique: the pencil is singular and has free directions;
- no solution (P_f empty, no dimension): the pencil is singular and Wong
  names the conflict the inputs make (a left-kernel polynomial vector).

At least MIN_MODELS models must be compared, so a change that stops the
linear pass or the SGA from reporting cannot pass unnoticed.

Usage: wong_sga_agree.py LDAEC. Standard library only.
"""
import glob
import json
import os
import resource
import subprocess
import sys

from check_e2e import ROOT, check, finish

MIN_MODELS = 60


def cpu_limit(seconds):
    def apply():
        resource.setrlimit(resource.RLIMIT_CPU, (seconds, seconds + 5))
    return apply


def verdicts(ldaec, path):
    """The --analyze --json reports of the models in `path` (none when the
    file is not meant to analyze: a syntax error test, a library)."""
    # A CPU-time limit, not a wall-time one: out_of_memory.lsd's 400,000
    # unknowns take 18 s idle and over 60 s of wall time on a busy machine.
    proc = subprocess.run([ldaec, path, "--analyze", "--json"],
                          capture_output=True, text=True,
                          preexec_fn=cpu_limit(120))
    try:
        doc = json.loads(proc.stdout)
    except ValueError:
        return []
    return doc if isinstance(doc, list) else [doc]


def agree(report):
    linear, outcome, dof = report["linear"], report["outcome"], report["dof"]
    if outcome == "unique":
        return linear.get("regular") is True and linear.get("dim_V") == dof
    if outcome == "not_unique":
        return (linear.get("regular") is False and
                bool(linear.get("free_directions")))
    if outcome == "no_solution":
        return linear.get("regular") is False and bool(linear.get("conflict"))
    return False


def main():
    ldaec = sys.argv[1]
    files = sorted(set(glob.glob(os.path.join(ROOT, "examples", "*.lsd")) +
                       glob.glob(os.path.join(ROOT, "tests", "**", "*.lsd"),
                                 recursive=True)))
    compared = 0
    for path in files:
        for report in verdicts(ldaec, path):
            if not report.get("linear") or report.get("outcome") in (
                    None, "undecided"):
                continue
            compared += 1
            name = "%s (%s)" % (os.path.relpath(path, ROOT),
                                report.get("model"))
            ok = agree(report)
            if not ok:
                check(False, "%s: SGA %s, dim P_f %s; Wong %s" % (
                    name, report["outcome"], report["dof"],
                    json.dumps(report["linear"])))
    check(compared >= MIN_MODELS, "Wong and the SGA agree on all %d linear "
          "models of examples/ and tests/ (at least %d)" % (compared,
                                                            MIN_MODELS))
    finish()


if __name__ == "__main__":
    main()
