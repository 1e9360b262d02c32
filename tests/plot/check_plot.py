#!/usr/bin/python3
"""ldaec --plot end to end on an RLC circuit (tests/plot/rlc_circuit.lsd).

The circuit has 26 unknowns and 7 parameters. The gnuplot script ldaec
writes beside the picture must draw panels by unit (volts and amperes
apart), labelled with units, at most 8 curves a panel and 6 panels, no
parameter and no derivative, with the model's name as title; the PNG, SVG
and PDF must exist and start with their formats' magic bytes. With
--outputs, exactly the named curves are drawn.

usage: check_plot.py LDAEC MODEL
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

MAGIC = {".png": b"\x89PNG\r\n\x1a\n", ".pdf": b"%PDF-", ".svg": b"<?xml"}
PARAMETERS = {"source.V", "source.f", "source.phase", "source.offset",
              "resistor.R", "inductor.L", "capacitor.C"}


def plot(ldaec, model, path, *args):
    p = subprocess.run([ldaec, model, "--simulate", "--no-progress", "-o",
                        path + ".csv", "--plot", path, *args],
                       capture_output=True, text=True, timeout=100)
    assert p.returncode == 0, (p.returncode, p.stderr)
    return p.stderr


def panels(script):
    """[(ylabel, [curve titles])] from a script ldaec wrote."""
    out = []
    label = None
    for block in re.split(r"\n(?=set |plot |unset )", script):
        m = re.match(r"set ylabel '((?:[^']|'')*)'", block)
        if m:
            label = m.group(1).replace("''", "'")
        if block.startswith("plot "):
            titles = [t.replace("''", "'") for t in
                      re.findall(r"title '((?:[^']|'')*)'", block)]
            out.append((label, titles))
    return out


def header(csv_path):
    with open(csv_path) as f:
        return f.readline().strip().split(",")


def check_default(ldaec, model, d):
    for ext in (".png", ".svg", ".pdf"):
        path = os.path.join(d, "rlc" + ext)
        notes = plot(ldaec, model, path)
        with open(path, "rb") as f:
            start = f.read(16)
        assert start.startswith(MAGIC[ext]), (ext, start)
    columns = header(os.path.join(d, "rlc.png.csv"))
    assert len(columns) == 1 + 26 + 7, (len(columns), columns)
    with open(os.path.join(d, "rlc.png.gp")) as f:
        script = f.read()
    assert "set multiplot layout" in script and "title 'RLCCircuit'" in script
    assert "set xlabel 'time [s]'" in script
    drawn = panels(script)
    assert 1 <= len(drawn) <= 6, drawn
    curves = [c for _, titles in drawn for c in titles]
    for label, titles in drawn:
        assert 1 <= len(titles) <= 8, (label, titles)
        unit = re.search(r"\[(.*)\]$", label).group(1)
        assert unit in ("V", "A"), label
        suffix = {"V": "v", "A": "i"}[unit]
        for t in titles:
            assert t.split(".")[-1] == suffix, (label, t)
    assert not PARAMETERS & set(curves), curves
    assert not any(c.startswith("der(") for c in curves), curves
    assert len(set(curves)) == len(curves), curves
    # The expected panels: the voltages that vary (one of each set of
    # aliases, model order), then the one current; the potentials tied to
    # the ground and the ground's current stay 0 and are named instead.
    assert drawn == [("v [V]", ["source.v", "resistor.v", "inductor.p.v",
                                "inductor.v", "capacitor.v"]),
                     ("inductor.i [A]", ["inductor.i"])], drawn
    assert ("the plot leaves out 4 curves that stay constant: source.n.v, "
            "capacitor.n.v, ground.p.v, ground.p.i") in notes, notes
    print("default: %d curves of %d columns in %d panels: %s" %
          (len(curves), len(columns) - 1, len(drawn),
           "; ".join("%s: %s" % (l, ", ".join(t)) for l, t in drawn)))
    if notes:
        print("notes:", notes.strip())


def check_outputs(ldaec, model, d):
    path = os.path.join(d, "some.svg")
    plot(ldaec, model, path, "--outputs", "capacitor.v,inductor.i,resistor.R")
    with open(path + ".gp") as f:
        drawn = panels(f.read())
    # One panel a unit, in model order; the parameter too, since it was
    # asked for.
    assert sorted(drawn) == [("capacitor.v [V]", ["capacitor.v"]),
                             ("inductor.i [A]", ["inductor.i"]),
                             ("resistor.R [Ohm]", ["resistor.R"])], drawn
    assert drawn.index(("inductor.i [A]", ["inductor.i"])) < \
        drawn.index(("capacitor.v [V]", ["capacitor.v"])), drawn
    print("--outputs: %s" % drawn)


def main():
    ldaec, model = sys.argv[1], sys.argv[2]
    if shutil.which("gnuplot") is None:
        print("no gnuplot")
        return 77
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as d:
        check_default(ldaec, model, d)
        check_outputs(ldaec, model, d)
    return 0


if __name__ == "__main__":
    sys.exit(main())
