"""Runs from Python: the RC circuit against its closed form, new parameter
and start values without recompiling (the compile counter stays put), a
structural parameter that recompiles, the result's conversions, and the
GIL released while integrating."""
import math
import os
import threading
import time

import numpy as np
import pytest

import ldaec
from conftest import PENDULUM, RC, model


def closed_form(t, V=2.0, R=100.0, C=1e-3, v0=0.0):
    return V + (v0 - V) * np.exp(-t / (R * C))


def test_rc_closed_form(rc):
    r = rc.simulate(rtol=1e-8, atol=1e-10)
    assert r.status == 0 and not r.recompiled
    assert r.time[0] == 0 and r.time[-1] == pytest.approx(0.5)
    assert len(r.time) == 101  # the experiment's Interval = 0.005
    err = np.max(np.abs(r["capacitor.v"] - closed_form(r.time)))
    assert err < 1e-6
    assert r.params["R"] == 100 and r.params["V"] == 2


def test_new_parameters_without_recompiling(rc):
    first = rc.simulate(rtol=1e-8, atol=1e-10)
    assert rc.compile_count == 1
    second = rc.simulate(rtol=1e-8, atol=1e-10, params={"R": 20, "V": 3})
    # The second run generated no code: same compiled model.
    assert rc.compile_count == 1
    assert not second.recompiled
    assert second.params["R"] == 20 and second.params["V"] == 3
    expect = closed_form(second.time, V=3, R=20)
    assert np.max(np.abs(second["capacitor.v"] - expect)) < 1e-6
    # ... and the default values again.
    third = rc.simulate(rtol=1e-8, atol=1e-10)
    np.testing.assert_array_equal(third["capacitor.v"], first["capacitor.v"])
    assert rc.compile_count == 1


def test_new_start_values_without_recompiling(rc):
    r = rc.simulate(rtol=1e-8, atol=1e-10, start={"capacitor.v": 1.5})
    assert rc.compile_count == 1 and not r.recompiled
    assert r["capacitor.v"][0] == 1.5
    expect = closed_form(r.time, v0=1.5)
    assert np.max(np.abs(r["capacitor.v"] - expect)) < 1e-6


def test_structural_parameter_recompiles():
    m = ldaec.compile(model("decay_chain.lsd"), cache=False)
    tight = dict(rtol=1e-9, atol=1e-12)
    r = m.simulate(params={"k": 2.0}, **tight)
    assert not r.recompiled and m.compile_count == 1
    assert r.names[:2] == ["x[1]", "x[2]"] or {"x[1]", "x[2]"} <= set(r.names)
    np.testing.assert_allclose(r["x[2]"], np.exp(-4 * r.time), rtol=1e-6)
    big = m.simulate(params={"n": 3, "k": 2.0}, **tight)
    assert big.recompiled and m.compile_count == 2
    np.testing.assert_allclose(big["x[3]"], np.exp(-6 * big.time), rtol=1e-6)
    # The model compiled for n = 3 is kept: other k, no new compile.
    again = m.simulate(params={"n": 3, "k": 1.0}, **tight)
    assert again.recompiled and m.compile_count == 2
    np.testing.assert_allclose(again["x[3]"], np.exp(-3 * again.time),
                               rtol=1e-6)
    # Back to the default structure: the first compiled model.
    assert not m.simulate().recompiled and m.compile_count == 2


def test_start_of_a_computed_variable_recompiles():
    m = ldaec.compile(model("alias_decay.lsd"), cache=False)
    assert list(m.unknowns) == ["x"]
    tight = dict(rtol=1e-9, atol=1e-12)
    fast = m.simulate(start={"x": 3}, **tight)
    assert not fast.recompiled and m.compile_count == 1
    np.testing.assert_allclose(fast["z"], -3 * np.exp(-fast.time), rtol=1e-7)
    slow = m.simulate(start={"y": 3}, **tight)
    assert slow.recompiled and m.compile_count == 2
    # y's start is a guess; x's fixed start decides.
    np.testing.assert_allclose(slow["y"], np.exp(-slow.time), rtol=1e-7)


def test_unknown_override_name_is_a_usage_error():
    m = ldaec.compile(model("decay_chain.lsd"), cache=False)
    with pytest.raises(ldaec.UsageError) as info:
        m.simulate(start={"nosuch": 1})
    assert "nosuch" in str(info.value)


def test_failure_returns_partial_rows():
    m = ldaec.compile(model("blowup.lsd"), cache=False)
    ok = m.simulate(params={"x0": 0.5})
    assert ok.status == 0
    np.testing.assert_allclose(ok["x"], 0.5 / (1 - 0.5 * ok.time), rtol=1e-5)
    bad = m.simulate(params={"x0": 2.0})
    assert bad.status == 3 and bad.failure
    assert "error: " in bad.diagnostics
    assert 0 < len(bad.time) < len(ok.time)
    assert bad.time[-1] <= 0.5 + 1e-9  # blows up at 1 / x0
    with pytest.raises(ldaec.SimulationError) as info:
        m.simulate(params={"x0": 2.0}, check=True)
    assert info.value.exit_code == 3
    assert info.value.result.status == 3
    assert str(info.value) == bad.diagnostics


def test_outputs_at_run_time(rc):
    r = rc.simulate(outputs=["capacitor.v", "resistor.*"])
    assert r.names[0] == "capacitor.v"
    assert all(n.startswith("resistor.") for n in r.names[1:])
    assert len(r.names) > 1
    with pytest.raises(KeyError) as info:
        r["capacitor.vv"]
    assert "capacitor.v" in str(info.value)


def test_result_metadata_and_files(rc, tmp_path):
    r = rc.simulate()
    assert r.model == "RCCircuit"
    assert r.stats["steps"] > 0 and r.stats["integrator"]
    assert set(r.units) >= set(r.names)
    assert r.param_descriptions["R"] == "resistance"
    mat = tmp_path / "run.mat"
    r.write(mat)
    import scipy.io
    data = scipy.io.loadmat(str(mat))
    assert "data_2" in data and "name" in data
    csv = tmp_path / "run.csv"
    r.write(csv)
    header = csv.read_text().splitlines()[0]
    assert header.split(",")[0] == "time"


def test_to_pandas_without_pandas(rc):
    r = rc.simulate()
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError) as info:
            r.to_pandas()
        assert "pandas" in str(info.value) and "numpy" in str(info.value)
    else:
        frame = r.to_pandas()
        assert list(frame.columns) == r.names


def test_plot_one_panel_per_unit(rc, tmp_path):
    r = rc.simulate()
    png = tmp_path / "rc.png"
    fig = r.plot(names=["capacitor.v", "capacitor.i", "resistor.v"], path=png)
    assert png.stat().st_size > 1000
    units = {r.units[n] for n in ["capacitor.v", "capacitor.i", "resistor.v"]}
    assert len(fig.axes) == len(units)
    assert fig._suptitle.get_text() == "RCCircuit"
    # By default the states (all else follows from them): one curve.
    fig = r.plot(path=tmp_path / "rc.svg")
    [ax] = fig.axes
    assert [line.get_label() for line in ax.get_lines()] == ["capacitor.v"]
    assert ax.get_ylabel() == "[V]"


def test_gil_released_while_integrating():
    # A run long enough to see: the pendulum over 2000 s at tight tolerance.
    m = ldaec.compile(PENDULUM, cache=False)
    ticks = []
    done = threading.Event()

    def counter():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    thread = threading.Thread(target=counter)
    thread.start()
    try:
        time.sleep(0.01)
        begin = time.perf_counter()
        r = m.simulate(stop=2000, rtol=1e-10, atol=1e-10)
        end = time.perf_counter()
    finally:
        done.set()
        thread.join()
    assert r.status == 0
    run = end - begin
    assert run > 0.1, f"the run took {run:.3f} s: too short to tell"
    # Holding the GIL, the counter could not append a single tick between
    # the call's edges (20 ms margins); released, it ticks all along
    # (about once a ms on an idle machine, less under load).
    inside = [t for t in ticks if begin + 0.02 < t < end - 0.02]
    assert len(inside) >= 10, (len(inside), run)


def test_threads_share_one_compiled_model(rc):
    from concurrent.futures import ThreadPoolExecutor
    values = [20.0, 50.0, 100.0, 200.0]
    with ThreadPoolExecutor(4) as pool:
        results = list(pool.map(
            lambda R: rc.simulate(params={"R": R}, rtol=1e-8, atol=1e-10),
            values))
    assert rc.compile_count == 1
    for R, r in zip(values, results):
        assert r.params["R"] == R
        expect = closed_form(r.time, R=R)
        assert np.max(np.abs(r["capacitor.v"] - expect)) < 1e-6
