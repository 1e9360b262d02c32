"""The .mat result of ldaec read by two readers (docs/results.md):
scipy.io.loadmat as DyMat uses it (a variable's values are row
`abs(index) - 1` of data_1 or data_2), and a reader written here from
OpenModelica's result layout ("The MATv4 Result File Format" of its user's
guide) with the orientation OpenModelica's own reader (read_matlab4.c)
takes for "binTrans" (name, description and dataInfo one variable per
column; data_1 parameters x 2; data_2 variables x time points), on a MATLAB
v4 parser of a few lines of numpy. Both must give the CSV of the
same run, exactly, and the analytic values of the models. The JIT, the
interpreter and the program --emit c --main writes give the same bytes.

Usage: check_mat.py LDAEC MODEL_DIR WORK_DIR
"""
import math
import os
import re
import shlex
import shutil
import subprocess
import sys

import numpy as np
import scipy.io

ldaec, model_dir, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
failures = []
# The run of every check, also of the emitted program.
RUN_OPTIONS = ["--stop", "1", "--interval", "0.25", "--rtol", "1e-10",
               "--atol", "1e-12", "--no-progress"]


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def run(model, out, *extra):
    cmd = [ldaec, os.path.join(model_dir, model), "--simulate", *RUN_OPTIONS,
           "-o", out, *extra]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit("%s failed (%d): %s" % (" ".join(cmd), proc.returncode,
                                         proc.stderr))


def read_csv(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
        rows = [[float(v) for v in line.split(",")] for line in f if line.strip()]
    return header, np.array(rows)


# ---- Reader 1: scipy.io.loadmat ------------------------------------------
def scipy_reader(path):
    """name -> (values over time or a constant, description)."""
    m = scipy.io.loadmat(path, chars_as_strings=False)
    aclass = ["".join(r).rstrip() for r in m["Aclass"]]
    check(aclass == ["Atrajectory", "1.1", "", "binTrans"], "Aclass %r" % aclass)
    # binTrans: one name per column.
    names = ["".join(c).rstrip() for c in m["name"].T]
    descs = ["".join(c).rstrip() for c in m["description"].T]
    info = m["dataInfo"].T.astype(int)  # one row per variable
    data = {1: m["data_1"], 2: m["data_2"]}  # one row per variable
    out = {}
    for name, desc, (block, index, _, _) in zip(names, descs, info):
        if block == 0:
            out[name] = (data[2][0], desc)
            continue
        row = data[block][abs(index) - 1]
        value = row if block == 2 else row[0]
        out[name] = (math.copysign(1, index) * value, desc)
    return out


# ---- Reader 2: from the documented layout, raw bytes -----------------------
def read_mat4(path):
    """The matrices of a MATLAB v4 file as numpy arrays (little-endian
    doubles and text, the types OpenModelica writes)."""
    raw = open(path, "rb").read()
    pos, out = 0, {}
    while pos < len(raw):
        mopt, mrows, ncols, imagf, namlen = np.frombuffer(raw, "<i4", 5, pos)
        pos += 20
        name = raw[pos:pos + namlen - 1].decode()
        pos += namlen
        # MOPT = 1000*M + 100*O + 10*P + T: P 0 double, 5 uint8; T 1 text.
        p = (mopt // 10) % 10
        dtype = {0: "<f8", 5: "u1"}[p]
        count = int(mrows) * int(ncols)
        values = np.frombuffer(raw, dtype, count, pos)
        pos += count * np.dtype(dtype).itemsize
        # Stored column by column.
        out[name] = values.reshape((ncols, mrows)).T
    return out


def layout_reader(path):
    m = read_mat4(path)
    text = lambda a: ["".join(map(chr, r)).rstrip(" \0") for r in a]
    check(text(m["Aclass"])[3] == "binTrans", "Aclass(4,:) binTrans")
    trans = text(m["Aclass"])[3] == "binTrans"
    t = (lambda a: a.T) if trans else (lambda a: a)
    names, descs = text(t(m["name"])), text(t(m["description"]))
    # OpenModelica's reader: under binTrans data_1 has one or two columns
    # (start and stop values) and a row per parameter, and data_2 a row
    # per stored variable and a column per time point.
    info, d1, d2 = t(m["dataInfo"]), m["data_1"], m["data_2"]
    check(d1.shape[1] in (1, 2), "data_1 has 1 or 2 columns: %r" % (d1.shape,))
    out = {}
    for i, name in enumerate(names):
        block, index = int(info[i, 0]), int(info[i, 1])
        if block == 0:  # the abscissa, time, is row 1 of data_2
            out[name] = (d2[0], descs[i])
        elif block == 1:  # parameters: start and stop value
            check(d1[abs(index) - 1, 0] == d1[abs(index) - 1, 1],
                  "%s constant over the run" % name)
            out[name] = (np.sign(index) * d1[abs(index) - 1, 0], descs[i])
        else:
            out[name] = (np.sign(index) * d2[abs(index) - 1], descs[i])
    return out


def compare(model, expect):
    csv_path = os.path.join(work, model + ".csv")
    mat_path = os.path.join(work, model + ".mat")
    run(model + ".lsd", csv_path)
    run(model + ".lsd", mat_path)
    header, rows = read_csv(csv_path)
    readers = {"scipy": scipy_reader(mat_path),
               "layout": layout_reader(mat_path)}
    for rname, got in readers.items():
        check(list(got)[:len(header)] == header,
              "%s: names in the CSV's order" % rname)
        for c, name in enumerate(header):
            if name not in got:
                check(False, "%s: %s missing" % (rname, name))
                continue
            value = np.broadcast_to(got[name][0], rows[:, c].shape)
            check(np.array_equal(value, rows[:, c]),
                  "%s: %s equals the CSV column" % (rname, name))
        expect(rname, got, rows[:, 0])
    # The two readers agree on every variable (also parameters the
    # columns leave out).
    a, b = readers["scipy"], readers["layout"]
    check(sorted(a) == sorted(b), "both readers list the same names")
    return mat_path, readers


def expect_rc(rname, got, t):
    v = got["c1.v"][0]
    check(np.allclose(v, 2 * (1 - np.exp(-t)), atol=1e-7),
          "%s: c1.v = 2 (1 - exp(-t))" % rname)
    check(got["r1.R"][0] == 1000 and got["c1.C"][0] == 1e-3
          and got["src.V"][0] == 2, "%s: parameter values" % rname)
    check(got["c1.C"][1] == "capacitance [F]", "%s: c1.C description %r"
          % (rname, got["c1.C"][1]))
    check(got["p"][1] == "power into the capacitor [W]",
          "%s: p description %r" % (rname, got["p"][1]))
    check(got["w"][1] == "no unit given", "%s: w description %r"
          % (rname, got["w"][1]))
    check(got["time"][1] == "Simulation time [s]", "%s: time description"
          % rname)


def expect_heat(rname, got, t):
    check(np.allclose(got["T[1]"][0], 1 - np.exp(-2 * t), atol=1e-7),
          "%s: T[1] = 1 - exp(-2 t)" % rname)
    check(got["k"][0] == 2 and got["N"][0] == 12, "%s: k and N" % rname)
    check(got["T[3]"][1] == "temperature [K]", "%s: T[3] description %r"
          % (rname, got["T[3]"][1]))
    names = [n for n in got if n.startswith("T[")]
    check(names == ["T[%d]" % i for i in range(1, 13)],
          "%s: T[1]..T[12] in numeric order: %s" % (rname, names))


rc_path, rc = compare("rc_described", expect_rc)
# Aliases: stored once, referred to with sign; at least one negated.
m = scipy.io.loadmat(rc_path)
info = m["dataInfo"].T.astype(int)
trajectories = info[info[:, 0] == 2]
check((trajectories[:, 1] < 0).any(), "a negated alias in dataInfo")
check(m["data_2"].shape[0] < len(trajectories) + 1,
      "aliases stored once: %d rows for %d trajectories"
      % (m["data_2"].shape[0], len(trajectories)))
check(np.array_equal(rc["scipy"]["w"][0], -rc["scipy"]["r1.v"][0]),
      "w = -r1.v read through its alias")

heat_path, heat = compare("heat_chain", expect_heat)
# --outputs keeps every parameter in data_1 but only the asked trajectories.
sel = os.path.join(work, "heat_sel.mat")
run("heat_chain.lsd", sel, "--outputs", "T[1?]")
got = layout_reader(sel)
check(list(got) == ["time", "T[10]", "T[11]", "T[12]", "N", "k"],
      "--outputs T[1?]: %s" % list(got))

# The same file, byte for byte, from the interpreter, the JIT and the
# program --emit c --main writes (when there is a C compiler).
def same_bytes(a, b):
    with open(a, "rb") as fa, open(b, "rb") as fb:
        return fa.read() == fb.read()


for jit in ("on", "off"):
    other = os.path.join(work, "rc_jit_%s.mat" % jit)
    run("rc_described.lsd", other, "--jit", jit)
    check(same_bytes(rc_path, other), "--jit %s writes the same .mat" % jit)
src = os.path.join(work, "rc_emitted.c")
emit = subprocess.run([ldaec, os.path.join(model_dir, "rc_described.lsd"),
                       "--emit", "c", "--main", "-o", src],
                      capture_output=True, text=True)
check(emit.returncode == 0, "--emit c --main: " + emit.stderr[-500:])
header = open(src).read(4000) if emit.returncode == 0 else ""
command = re.search(r"Compile \(docs/embedding-c\.md\):\n\s*(cc .*)\n", header)
if command and shutil.which("cc"):
    exe = os.path.join(work, "rc_emitted")
    words = [src if w.endswith(".c") else w for w in shlex.split(command.group(1))]
    words[words.index("-o") + 1] = exe
    built = subprocess.run(words, capture_output=True, text=True)
    check(built.returncode == 0, "the emitted program builds: " + built.stderr[-500:])
    prog_mat = os.path.join(work, "rc_emitted.mat")
    ran = subprocess.run([exe, *RUN_OPTIONS, "-o", prog_mat],
                         capture_output=True, text=True)
    check(ran.returncode == 0, "the emitted program runs: " + ran.stderr[-500:])
    check(ran.returncode == 0 and same_bytes(rc_path, prog_mat),
          "the emitted program writes the same .mat")
else:
    print("note: no C compiler; the emitted program's .mat is not checked")

if failures:
    sys.exit("%d checks failed" % len(failures))
print("all .mat checks passed")
