"""Sweeps on a local Dask cluster of two worker processes: a grid with a
member that fails (reported with its parameters and diagnostics, the
others kept), the model compiled once per worker, results stacked over
members, result files per member; samples; the serial scheduler."""
import csv
import os

import numpy as np
import pytest

import ldaec
from conftest import RC, model

distributed = pytest.importorskip("distributed")

BLOWUP = model("blowup.lsd")
X0 = [0.2, 0.5, 2.0, 0.8, 0.1, 0.4]  # 2.0 blows up at t = 0.5 < stop = 1


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1,
                                  processes=True, dashboard_address=None) as c:
        yield c


def check_blowup(result):
    assert len(result) == len(X0)
    np.testing.assert_array_equal(result.params["x0"], X0)
    assert list(result.status) == [0, 0, 3, 0, 0, 0]
    [bad] = result.failed
    assert bad["params"] == {"x0": 2.0} and bad["index"] == 2
    assert "error: " in bad["diagnostics"]
    assert "x0=2.0" in result.summary()
    t = result.time
    assert t[0] == 0 and t[-1] == pytest.approx(1)
    x = result["x"]
    assert x.shape == (len(X0), len(t))
    for k, x0 in enumerate(X0):
        if x0 < 1:
            np.testing.assert_allclose(x[k], x0 / (1 - x0 * t), rtol=1e-5)
    assert np.isnan(x[2, -1]) and not np.isnan(x[2, 0])


def test_grid_on_two_workers(cluster, capsys):
    result = ldaec.sweep(BLOWUP, {"x0": X0},
                         scheduler=cluster.scheduler_address, cache=False)
    check_blowup(result)
    assert "ldaec.sweep: 6/6 members (1 failed)" in capsys.readouterr().err
    with distributed.Client(cluster) as client:
        counts = client.run(ldaec.sweep_compile_count)
    # Compiled once per worker that ran a chunk, not once per member.
    assert len(counts) == 2
    assert all(c <= 1 for c in counts.values()) and sum(counts.values()) >= 1


def test_samples_and_files(cluster, tmp_path):
    samples = [{"x0": x0} for x0 in X0]
    with distributed.Client(cluster) as client:
        result = ldaec.sweep(BLOWUP, samples, client=client, cache=False,
                             chunk_size=1, write_dir=tmp_path,
                             write_format="csv", progress=False)
        counts = client.run(ldaec.sweep_compile_count)
    check_blowup(result)
    # The same model and options as the test above: nothing compiled again.
    assert all(c <= 1 for c in counts.values())
    rows = list(csv.DictReader(open(tmp_path / "members.csv")))
    assert [float(r["x0"]) for r in rows] == X0
    assert [r["status"] for r in rows] == ["0", "0", "3", "0", "0", "0"]
    header = (tmp_path / "member_000000.csv").read_text().splitlines()[0]
    assert header.startswith("time,")


def test_grid_of_two_parameters_serial():
    result = ldaec.sweep(RC, {"R": [50, 100], "C": [1e-3, 2e-3, 4e-3]},
                         scheduler="serial", cache=False, progress=False,
                         rtol=1e-8, atol=1e-10)
    assert len(result) == 6 and not result.failed
    # The first name varies slowest, as `ldaec --sweep`.
    assert list(result.params["R"]) == [50, 50, 50, 100, 100, 100]
    v = result["capacitor.v"]
    for k in range(6):
        rc = result.params["R"][k] * result.params["C"][k]
        np.testing.assert_allclose(v[k], 2 * (1 - np.exp(-result.time / rc)),
                                   atol=1e-6)


def test_default_local_cluster():
    result = ldaec.sweep(BLOWUP, {"x0": [0.5, 2.0]}, n_workers=2,
                         cache=False, progress=False)
    assert list(result.status) == [0, 3]
    assert result.setup_seconds > 0


def test_a_member_that_kills_its_worker(tmp_path, monkeypatch):
    """A member whose worker process dies (issue 28: the whole sweep was
    lost to KilledWorker, members.csv too): every other member's result is
    kept, the dead one is named with its parameters, status -1."""
    monkeypatch.setenv("LDAEC_SWEEP_ABORT_MEMBER", "3")
    x0 = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8]
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1,
                                  processes=True,
                                  dashboard_address=None) as c:
        result = ldaec.sweep(BLOWUP, {"x0": x0}, scheduler=c.scheduler_address,
                             cache=False, chunk_size=4, progress=False,
                             write_dir=tmp_path, write_format="csv")
    assert list(result.status) == [0, 0, 0, -1, 0, 0, 0, 0]
    [dead] = result.failed
    assert dead["index"] == 3 and dead["params"] == {"x0": 0.4}
    assert ("member 3 (x0=0.4): the worker process running it died"
            in dead["diagnostics"])
    for k, v in enumerate(x0):
        if k != 3:
            np.testing.assert_allclose(result["x"][k], v / (1 - v * result.time),
                                       rtol=1e-5)
    rows = list(csv.DictReader(open(tmp_path / "members.csv")))
    assert [r["status"] for r in rows] == ["0", "0", "0", "-1", "0", "0", "0", "0"]


def test_workers_gone_for_good(monkeypatch):
    """A worker without a nanny that dies is not restarted: the scheduler
    waited for ever with the tasks left (issue 28, a sweep hung 10
    minutes). The watchdog reports the members no worker was left to run,
    with their parameters, and the sweep returns the others."""
    import subprocess
    import sys
    monkeypatch.setenv("LDAEC_SWEEP_NO_WORKER_GRACE", "2")
    env = dict(os.environ, LDAEC_SWEEP_ABORT_MEMBER="2")
    x0 = [0.1, 0.2, 0.3, 0.4]
    with distributed.LocalCluster(n_workers=0, dashboard_address=None) as c:
        worker = subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_worker",
             c.scheduler_address, "--no-nanny", "--nthreads", "1",
             "--no-dashboard"], env=env, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL)
        try:
            with distributed.Client(c) as client:
                client.wait_for_workers(1, timeout=60)
                result = ldaec.sweep(BLOWUP, {"x0": x0}, client=client,
                                     cache=False, chunk_size=1,
                                     progress=False)
        finally:
            worker.kill()
            worker.wait()
    # Members 0 and 1 ran; their results survive unless the worker died
    # before the client fetched them (then they too count as not run).
    assert list(result.status[2:]) == [-1, -1]
    for r in result.members:
        k = r["index"]
        if r["status"] == 0:
            np.testing.assert_allclose(r["values"][:, r["names"].index("x")],
                                       x0[k] / (1 - x0[k] * r["time"]),
                                       rtol=1e-5)
        else:
            assert r["status"] == -1
            assert "member %d (x0=%s)" % (k, x0[k]) in r["diagnostics"]
    last = result.failed[-1]
    assert last["index"] == 3 and last["params"] == {"x0": 0.4}
    assert "no worker was left to run it" in last["diagnostics"]


def test_unwritable_write_dir_refused_first(tmp_path):
    """write_dir is checked before any member runs (it raised only after
    every member ran)."""
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    with pytest.raises(ldaec.UsageError, match="cannot create write_dir"):
        ldaec.sweep(BLOWUP, {"x0": X0}, scheduler="serial", cache=False,
                    progress=False, write_dir=blocker / "sub")
