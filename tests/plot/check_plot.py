#!/usr/bin/python3
"""ldaec --plot end to end on an RLC circuit (tests/plot/rlc_circuit.lsd).

The circuit has 26 variables and 7 parameters. The gnuplot script ldaec
writes beside the picture must draw, by default, the two states in a
panel each (volts and amperes apart), labelled with units, with the
model's name as title; the PNG, SVG and PDF must exist and start with
their formats' magic bytes. With --outputs, exactly the named curves are
drawn, at most 8 a panel and 6 panels, the rest named on stderr.

usage: check_plot.py LDAEC MODEL
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

MAGIC = {".png": b"\x89PNG\r\n\x1a\n", ".pdf": b"%PDF-", ".svg": b"<?xml"}


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
        plot(ldaec, model, path)
        with open(path, "rb") as f:
            start = f.read(16)
        assert start.startswith(MAGIC[ext]), (ext, start)
    columns = header(os.path.join(d, "rlc.png.csv"))
    assert len(columns) == 1 + 26 + 7, (len(columns), columns)
    with open(os.path.join(d, "rlc.png.gp")) as f:
        script = f.read()
    assert "set multiplot layout 2,1 title 'RLCCircuit'" in script, script
    assert "set xlabel 'time [s]'" in script
    # By default the states, one panel a unit (model order), labelled
    # with it.
    drawn = panels(script)
    assert drawn == [("inductor.i [A]", ["inductor.i"]),
                     ("capacitor.v [V]", ["capacitor.v"])], drawn
    print("default: %d of %d columns: %s" % (
        2, len(columns) - 1, drawn))


def check_caps(ldaec, model, d):
    # Every column named ('*': 35 with the derivatives and parameters):
    # panels by unit and scale, at most 8 curves each and 6 in all; the
    # rest named on stderr with how to see them.
    path = os.path.join(d, "all.svg")
    notes = plot(ldaec, model, path, "--outputs", "*")
    named = header(path + ".csv")[1:]
    assert len(named) == 35, named
    with open(path + ".gp") as f:
        drawn = panels(f.read())
    assert len(drawn) == 6, drawn
    curves = [c for _, titles in drawn for c in titles]
    assert len(set(curves)) == len(curves), curves
    for label, titles in drawn:
        assert 1 <= len(titles) <= 8, (label, titles)
    for label, titles in drawn:
        # "name [unit]" of one curve, "v [V]" when all names end in .v,
        # else "[unit]".
        quantity = re.match(r"(.*?)(?: ?\[[^]]*\])?$", label).group(1)
        if len(titles) == 1:
            assert quantity == titles[0], (label, titles)
        elif quantity:
            assert all(t.split(".")[-1] == quantity for t in titles), \
                (label, titles)
        else:
            assert len({t.split(".")[-1] for t in titles}) > 1, \
                (label, titles)
    m = re.search(r"note: the plot leaves out (\d+) curves \(8 at most per "
                  r"panel, 6 panels\): (.*); name the curves to plot "
                  r"\(--outputs\) to see them", notes)
    assert m, notes
    assert int(m.group(1)) + len(curves) == 35, (m.group(1), len(curves))
    left = [n for n in named if n not in curves]
    assert m.group(2).startswith(", ".join(left[:10])), (m.group(2), left)
    print("--outputs '*': %d curves in %d panels, %s left out" %
          (len(curves), len(drawn), m.group(1)))


def check_outputs(ldaec, model, d):
    path = os.path.join(d, "some.svg")
    plot(ldaec, model, path, "--outputs", "capacitor.v,inductor.i,resistor.R")
    with open(path + ".gp") as f:
        drawn = panels(f.read())
    # Exactly the named curves, any kind (the parameter too), one panel a
    # unit in model order.
    assert drawn == [("inductor.i [A]", ["inductor.i"]),
                     ("capacitor.v [V]", ["capacitor.v"]),
                     ("resistor.R [Ohm]", ["resistor.R"])], drawn
    print("--outputs: %s" % drawn)


def main():
    ldaec, model = sys.argv[1], sys.argv[2]
    if shutil.which("gnuplot") is None:
        print("no gnuplot")
        return 77
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as d:
        check_default(ldaec, model, d)
        check_outputs(ldaec, model, d)
        check_caps(ldaec, model, d)
    return 0


if __name__ == "__main__":
    sys.exit(main())
