"""Compiling from Python: the model's tables, the analysis report (the
same dict as `ldaec --analyze --json`), errors as exceptions carrying the
command's diagnostics."""
import json
import os
import re
import subprocess

import pytest

import ldaec
from conftest import PENDULUM, RC, model


def test_compile_tables(rc):
    assert rc.name == "RCCircuit"
    assert rc.parameters["R"] == 100
    assert rc.parameters["C"] == 1e-3
    assert rc.parameters["V"] == 2
    assert rc.structural == []
    assert "capacitor.v" in rc.output_names
    assert rc.compile_count == 1


def test_structural_parameter_named():
    m = ldaec.compile(model("decay_chain.lsd"), cache=False)
    assert "k" in m.parameters
    # n sizes x[]: either kept and marked structural, or folded away; it is
    # never a run-time parameter.
    assert "n" in m.structural or "n" not in m.parameters
    assert sorted(n for n in m.unknowns if n.startswith("x[")) == \
        ["x[1]", "x[2]"]


def test_analyze_is_the_commands_json():
    m = ldaec.compile(PENDULUM, cache=False)
    report = m.analyze()
    assert report["model"] == "Pendulum"
    assert report["structural_index"] == 3
    assert report["differentiation_index"] == 3
    assert {"states", "dummies", "differentiated", "blt", "init",
            "state_sets"} <= set(report)
    assert len(report["differentiated"]) > 0
    ldaec_bin = os.environ.get("LDAEC_BINARY")
    if ldaec_bin:
        out = subprocess.run([ldaec_bin, PENDULUM, "--analyze", "--json"],
                             capture_output=True, text=True, check=True)
        assert report == json.loads(out.stdout)


DIAGNOSTIC = re.compile(r"^\S+\.lsd:\d+:\d+: error: ", re.M)


def test_model_error_carries_diagnostics():
    path = model("undeclared.lsd")
    with pytest.raises(ldaec.ModelError) as info:
        ldaec.compile(path, cache=False)
    e = info.value
    assert e.exit_code == 1
    assert DIAGNOSTIC.search(e.diagnostics), e.diagnostics
    assert "'y'" in e.diagnostics
    assert "^" in e.diagnostics  # the caret under the source line
    assert str(e) == e.diagnostics


def test_command_gives_the_same_text():
    ldaec_bin = os.environ.get("LDAEC_BINARY")
    if not ldaec_bin:
        pytest.skip("LDAEC_BINARY not set (ctest sets it)")
    path = model("undeclared.lsd")
    with pytest.raises(ldaec.ModelError) as info:
        ldaec.compile(path, cache=False)
    out = subprocess.run([ldaec_bin, path, "--simulate", "--no-cache"],
                         capture_output=True, text=True)
    assert out.returncode == info.value.exit_code
    assert out.stderr == info.value.diagnostics


def test_usage_errors():
    with pytest.raises(ldaec.UsageError) as info:
        ldaec.compile(RC, outputs=["capacitor.vv"], cache=False)
    assert "capacitor.vv" in str(info.value)
    assert info.value.exit_code == 2
    with pytest.raises(ldaec.UsageError):
        ldaec.compile(RC, model="NoSuchModel", cache=False)
    with pytest.raises(ldaec.UsageError):
        ldaec.compile(RC, method="fast", cache=False)
    with pytest.raises(ldaec.UsageError):
        ldaec.compile(RC, jit="maybe", cache=False)


def test_run_option_errors(rc):
    with pytest.raises(ldaec.UsageError) as info:
        rc.simulate(t0=1, stop=0.5)
    assert "error: the stop time 0.5 is before the start time 1" in \
        str(info.value)
    with pytest.raises(ldaec.UsageError) as info:
        rc.simulate(params={"RR": 1})
    assert "RR" in str(info.value) and "'R'" in str(info.value)
    with pytest.raises(ldaec.UsageError):
        rc.simulate(start=0.5)  # a start time is t0=, start= is values


def test_pattern_outputs_compile_time():
    m = ldaec.compile(RC, outputs=["capacitor.*"], cache=False)
    r = m.simulate()
    assert r.names and all(n.startswith("capacitor.") for n in r.names)
    assert "capacitor.v" in r.names


def test_analyze_a_model_that_does_not_compile(tmp_path):
    path = tmp_path / "conflict.lsd"
    path.write_text("model Conflict\n  Real x(start = 1, fixed = true);\n"
                    "equation\n  der(x) = -x;\n  x = 2 * x + 1;\n"
                    "end Conflict;\n")
    with pytest.raises(ldaec.ModelError) as info:
        ldaec.compile(path, cache=False)
    assert "error: the model has no solution" in str(info.value)
    with pytest.raises(ldaec.ModelError) as info:
        ldaec.analyze(path)
    assert info.value.report["model"] == "Conflict"
    assert "error: the model has no solution" in info.value.diagnostics


def test_bad_values_refused_as_on_the_command_line():
    """NaN and inf parameters, start values and options, and a NUL in a
    path, are refused with the command line's messages (issue 28: they ran,
    and compile('osc.lsd\\0junk') compiled osc.lsd)."""
    import math
    m = ldaec.compile(PENDULUM, cache=False)
    cases = [
        (dict(params={"g": math.nan}),
         "invalid parameter override 'g=nan': 'nan' is not a number"),
        (dict(params={"g": math.inf}),
         "invalid parameter override 'g=inf': 'inf' is not a number"),
        (dict(start={"x": math.nan}),
         "invalid start value override 'x=nan': 'nan' is not a number"),
        (dict(stop=math.inf), "invalid stop 'inf': not a finite number"),
        (dict(rtol=math.nan), "invalid rtol 'nan': not a finite number"),
    ]
    for kwargs, message in cases:
        with pytest.raises(ldaec.UsageError, match=re.escape(message)):
            m.simulate(**kwargs)
    with pytest.raises(ldaec.UsageError, match="the path contains a NUL"):
        ldaec.compile(PENDULUM + "\0junk")
    from ldaec.sweep import members_of
    with pytest.raises(ldaec.UsageError, match="'g=nan': 'nan' is not a number"):
        members_of({"g": [1.0, math.nan]})
