#!/usr/bin/python3
"""ldaec --sweep end to end on an RC circuit (tests/sweep/rc_sweep.lsd).

Every member's capacitor voltage against the closed form
v(t) = V (1 - exp(-t / (R C))), read back from the .mat file with
scipy.io.loadmat and from the long CSV table; a member that fails keeps
its parameters and status and does not lose the others.

usage: check_sweep.py LDAEC MODEL
"""
import csv
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import scipy.io

TOL = 1e-5  # the runs use rtol 1e-8, atol 1e-10; v is at most 2 V


def run(ldaec, model, *args):
    cmd = [ldaec, model, "--simulate", "--rtol", "1e-8", "--atol", "1e-10",
           *args]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=100)
    return p.returncode, p.stdout, p.stderr


def strings(a):
    """A char matrix from loadmat: one string a row, padding stripped."""
    return [str(s).rstrip() for s in np.atleast_1d(a)]


def closed_form(t, R, C=1e-3, V=2.0):
    return V * (1 - np.exp(-t / (R * C)))


def check_mat(ldaec, model, d, jit):
    # Two threads over one compiled model: the interpreter's (--jit off)
    # and the JIT's code.
    path = os.path.join(d, "sweep.mat")
    rc, _, err = run(ldaec, model, "--sweep", "R=50:200:4", "--jobs", "2",
                     "-o", path, "--jit", jit)
    assert rc == 0, (rc, err)
    # One progress line per member.
    lines = [l for l in err.splitlines() if l.startswith("sweep: ")]
    assert len(lines) == 4, err
    assert any("member 2 (R=100) ok" in l for l in lines), err
    m = scipy.io.loadmat(path)
    assert strings(m["sweep_names"]) == ["R"], m["sweep_names"]
    np.testing.assert_array_equal(m["sweep_values"],
                                  [[50.0], [100.0], [150.0], [200.0]])
    np.testing.assert_array_equal(m["status"], [[0], [0], [0], [0]])
    names = strings(m["name"])
    assert names[0] == "time", names
    v = names.index("capacitor.v")
    for k, R in enumerate([50.0, 100.0, 150.0, 200.0], start=1):
        data = m["member_%d" % k]
        assert data.shape == (101, len(names)), data.shape
        t = data[:, 0]
        assert t[0] == 0 and abs(t[-1] - 0.5) < 1e-12, t
        err = np.max(np.abs(data[:, v] - closed_form(t, R)))
        assert err < TOL, (R, err)
    print("mat (--jit %s): 4 members, max |v - closed form| < %g" %
          (jit, TOL))


def check_csv_two_axes(ldaec, model, d):
    path = os.path.join(d, "sweep.csv")
    rc, _, err = run(ldaec, model, "--sweep", "R=50,100", "--sweep",
                     "C=1e-3,2e-3", "-o", path, "--no-progress")
    assert rc == 0, (rc, err)
    assert "sweep: " not in err, err
    with open(path) as f:
        rows = list(csv.reader(f))
    header = rows[0]
    # The swept names sorted, then the result's columns, the swept
    # parameters' own columns not twice.
    assert header[:4] == ["member", "C", "R", "time"], header
    assert len(set(header)) == len(header), header
    assert "V" in header, header
    v = header.index("capacitor.v")
    members = {}
    for row in rows[1:]:
        members.setdefault(int(row[0]), []).append([float(x) for x in row])
    assert sorted(members) == [1, 2, 3, 4], sorted(members)
    # The first axis (R) varies slowest.
    expect = {1: (50, 1e-3), 2: (50, 2e-3), 3: (100, 1e-3), 4: (100, 2e-3)}
    for k, (R, C) in expect.items():
        table = np.array(members[k])
        assert np.all(table[:, 1] == C) and np.all(table[:, 2] == R), k
        t = table[:, 3]
        err = np.max(np.abs(table[:, v] - closed_form(t, R, C)))
        assert err < TOL, (k, err)
    print("csv: 4 members on two axes, max |v - closed form| < %g" % TOL)


def check_failing_member(ldaec, model, d):
    # R = 0 ties the capacitor to the source: its fixed start 0 V cannot
    # hold (v = V at once), so that member fails; the others run.
    path = os.path.join(d, "failing.mat")
    rc, _, err = run(ldaec, model, "--sweep", "R=100,0,200", "-o", path)
    assert rc == 3, (rc, err)
    assert "1 of 3 members failed" in err, err
    m = scipy.io.loadmat(path)
    status = m["status"].ravel().tolist()
    assert status[0] == 0 and status[2] == 0 and status[1] in (2, 3), status
    failure = strings(m["failure"])
    assert failure[0] == "" and failure[2] == "" and failure[1] != "", failure
    np.testing.assert_array_equal(m["sweep_values"].ravel(), [100, 0, 200])
    names = strings(m["name"])
    v = names.index("capacitor.v")
    for k, R in ((1, 100.0), (3, 200.0)):
        data = m["member_%d" % k]
        assert np.max(np.abs(data[:, v] - closed_form(data[:, 0], R))) < TOL
    print("failing member: status %d (%s); the others ran" %
          (status[1], failure[1][:60]))


def main():
    ldaec, model = sys.argv[1], sys.argv[2]
    helptext = subprocess.run([ldaec, "--help"], capture_output=True,
                              text=True).stdout
    if "--sweep" not in helptext:
        print("ldaec has no --sweep yet")
        return 77
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as d:
        for jit in ("off", "on"):
            check_mat(ldaec, model, d, jit)
        check_csv_two_axes(ldaec, model, d)
        check_failing_member(ldaec, model, d)
    return 0


if __name__ == "__main__":
    sys.exit(main())
