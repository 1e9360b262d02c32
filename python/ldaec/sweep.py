"""Parameter sweeps and Monte Carlo ensembles on Dask (docs/python.md,
"Sweeps").

The members go to the workers in chunks (one task per chunk, not per
member); each worker process compiles the model once, on its first chunk,
and keeps it in a per-process cache keyed by the file's path, a hash of
its content and the compile options, so later chunks (and later sweeps on
the same cluster) only run it. A member that fails (a numerical failure,
a bad value) is reported with its parameters and the command's
diagnostics; the others are kept. Results come back as numpy arrays,
stacked over members when the output grids agree.
"""
import asyncio
import hashlib
import itertools
import math
import os
import sys
import tempfile
import threading
import time

import numpy as np

from .errors import LdaecError, UsageError
from .model import Model, format_value

# ---- the members ------------------------------------------------------------


def members_of(params):
    """A dict of lists is a grid (every combination, the first name varying
    slowest, as ``ldaec --sweep``); a list of dicts is a list of samples
    (Monte Carlo). A scalar in a grid is an axis of one value."""
    if isinstance(params, dict):
        names = list(params)
        axes = [list(np.atleast_1d(params[n]).tolist()) for n in names]
        members = [dict(zip(names, combo))
                   for combo in itertools.product(*axes)]
    else:
        members = list(params)
        if not all(isinstance(m, dict) for m in members):
            raise UsageError("error: params must be a dict of lists (a grid) "
                             "or a list of dicts (samples)\n")
        members = [dict(m) for m in members]
    # As the command line refuses them, before any member runs.
    for m in members:
        for name, value in m.items():
            if not math.isfinite(float(value)):
                raise UsageError(f"error: invalid parameter override "
                                 f"'{name}={value}': '{value}' is not a "
                                 f"number\n")
    return members


def _chunks(items, size):
    return [items[i:i + size] for i in range(0, len(items), size)]


# ---- on a worker --------------------------------------------------------------

_MODELS = {}
_MODELS_LOCK = threading.Lock()


def _source_path(spec):
    """The model file on this machine: the client's path when it holds the
    same text, else a copy of the text (a worker on another machine)."""
    path = spec["path"]
    try:
        with open(path, "rb") as f:
            if hashlib.sha256(f.read()).hexdigest() == spec["hash"]:
                return path
    except OSError:
        pass
    folder = os.path.join(tempfile.gettempdir(), "ldaec-sweep", spec["hash"])
    os.makedirs(folder, exist_ok=True)
    copy = os.path.join(folder, os.path.basename(path))
    if not os.path.exists(copy):
        scratch = copy + f".{os.getpid()}"
        with open(scratch, "wb") as f:
            f.write(spec["source"])
        os.replace(scratch, copy)
    return copy


def worker_model(spec):
    """This process's compiled model for `spec`, compiled on first use."""
    key = (spec["path"], spec["hash"], spec["compile_key"])
    with _MODELS_LOCK:
        model = _MODELS.get(key)
        if model is None:
            model = Model(_source_path(spec), **spec["compile"])
            _MODELS[key] = model
        return model


def compile_count():
    """Compiles done in this process by sweeps (what the tests check)."""
    with _MODELS_LOCK:
        return sum(m.compile_count for m in _MODELS.values())


def _run_member(model, spec, index, member):
    record = {"index": index, "params": member, "status": 0,
              "diagnostics": "", "time": None, "values": None,
              "recompiled": False, "wall_time": 0.0}
    try:
        r = model.simulate(params=member, **spec["run"])
    except LdaecError as e:
        record["status"] = e.exit_code
        record["diagnostics"] = e.diagnostics
        return record
    record.update(status=r.status, diagnostics=r.diagnostics,
                  time=r.time.copy(), values=r.data[:, 1:].copy(),
                  names=r.names, units={n: r.units[n] for n in r.names},
                  recompiled=r.recompiled, wall_time=r.stats["wall_time"])
    if spec["write_dir"]:
        path = os.path.join(spec["write_dir"],
                            f"member_{index:06d}.{spec['write_format']}")
        try:
            r.write(path)
            record["file"] = path
        except LdaecError as e:
            # Its file is not there: the member did not finish.
            record["diagnostics"] += e.diagnostics
            record["status"] = record["status"] or e.exit_code or 1
    return record


#: How often a member that ran alone in a task whose worker died runs
#: again before it counts as the one that kills its worker: never, since
#: it ran with nothing else in flight and Dask itself tried it on three
#: workers (each death of a worker also takes time to recover from).
_MEMBER_TRIES = 0

#: The status of a member whose worker process died running it (a crash
#: in native code, the operating system's out-of-memory killer), or that
#: no worker was left to run.
WORKER_DIED = -1

#: Seconds the sweep waits with tasks pending and no worker at all before
#: it reports the members left as not run (a cluster whose workers died
#: and were not restarted: the scheduler would wait for ever).
#: LDAEC_SWEEP_NO_WORKER_GRACE overrides it (tests).
_NO_WORKER_GRACE = 60.0

#: How often the sweep looks at the cluster while no task ends.
_WATCH_INTERVAL = 1.0

#: What Dask raises when a wait or a result fetch runs out of time.
_TIMEOUTS = (TimeoutError, asyncio.TimeoutError)


def _fault_injection(index):
    """Tests only: LDAEC_SWEEP_ABORT_MEMBER=k makes the worker process
    that runs member k die (what a crash in native code does), so that the
    sweep's recovery can be tested without a crashing model."""
    if os.environ.get("LDAEC_SWEEP_ABORT_MEMBER") == str(index):
        os.abort()


def run_chunk(spec, chunk):
    """Runs the members of one task: [(index, params)] -> [record]."""
    try:
        model = worker_model(spec)
    except LdaecError as e:
        return [{"index": i, "params": m, "status": e.exit_code,
                 "diagnostics": e.diagnostics, "time": None, "values": None,
                 "recompiled": False, "wall_time": 0.0} for i, m in chunk]
    records = []
    for i, m in chunk:
        _fault_injection(i)
        records.append(_run_member(model, spec, i, m))
    return records


# ---- the result ---------------------------------------------------------------


class SweepResult:
    """The members' outcomes.

    ``params[name]`` and ``status`` are arrays over members (in the order
    of the grid or the samples); ``time`` the common output grid and
    ``values[name]`` a (members x times) array when the members' grids
    agree (a member that failed has NaN after its last row), else None
    (each member's own arrays are in ``members``). ``failed`` lists the
    members that did not finish, each with its parameters and the
    command's diagnostics.
    """

    def __init__(self, records, setup_seconds, run_seconds):
        self.members = sorted(records, key=lambda r: r["index"])
        self.setup_seconds = setup_seconds
        self.run_seconds = run_seconds
        names = []
        for r in self.members:
            names += [n for n in r["params"] if n not in names]
        self.params = {n: np.array([r["params"].get(n, np.nan)
                                    for r in self.members], dtype=float)
                       for n in names}
        self.status = np.array([r["status"] for r in self.members], dtype=int)
        self.failed = [r for r in self.members if r["status"] != 0]
        self.time, self.values, self.names, self.units = None, None, [], {}
        self._stack()

    def _stack(self):
        ran = [r for r in self.members if r["time"] is not None]
        if not ran:
            return
        grid = max((r["time"] for r in ran), key=len)
        names = ran[0]["names"]
        if any(r["names"] != names or
               not np.array_equal(r["time"], grid[:len(r["time"])])
               for r in ran):
            return
        self.names, self.units, self.time = names, ran[0]["units"], grid
        cube = np.full((len(self.members), len(grid), len(names)), np.nan)
        for k, r in enumerate(self.members):
            if r["values"] is not None:
                cube[k, :r["values"].shape[0], :] = r["values"]
        self.values = {n: cube[:, :, j] for j, n in enumerate(names)}

    def __getitem__(self, name):
        if self.values is None:
            raise KeyError("the members' output grids differ: use "
                           "result.members[k]['values']")
        return self.values[name]

    def __len__(self):
        return len(self.members)

    def __repr__(self):
        return (f"<ldaec.SweepResult {len(self)} members, "
                f"{len(self.failed)} failed>")

    def summary(self):
        """One line per failed member: its index, parameters, diagnostics."""
        lines = []
        for r in self.failed:
            values = ", ".join(f"{k}={format_value(v)}"
                               for k, v in r["params"].items())
            lines.append(f"member {r['index']} ({values}): status "
                         f"{r['status']}\n{r['diagnostics'].rstrip()}")
        return "\n".join(lines)


# ---- the client ---------------------------------------------------------------


class _Progress:
    """A counter on stderr, rewritten in place on a terminal."""

    def __init__(self, total, enabled):
        self.total, self.done, self.failed = total, 0, 0
        self.enabled = enabled
        self.tty = enabled and sys.stderr.isatty()
        self.last = 0.0

    def add(self, records):
        self.done += len(records)
        self.failed += sum(r["status"] != 0 for r in records)
        now = time.monotonic()
        if not self.enabled or (now - self.last < 0.5 and
                                self.done < self.total):
            return
        self.last = now
        text = f"ldaec.sweep: {self.done}/{self.total} members"
        if self.failed:
            text += f" ({self.failed} failed)"
        end = "\r" if self.tty and self.done < self.total else "\n"
        sys.stderr.write(text + end)
        sys.stderr.flush()


def _spec(model, compile_options, run, write_dir, write_format):
    if isinstance(model, Model):
        path = model.path
        compile_options = dict(model=model.model_name, method=model.method,
                               outputs=model.outputs, jit=model.jit,
                               overrides=model.overrides,
                               cache=model.cache_dir or False)
    else:
        path = os.fspath(model)
    path = os.path.abspath(path)
    try:
        with open(path, "rb") as f:
            source = f.read()
    except OSError as e:
        raise UsageError(f"error: cannot read '{path}': {e.strerror}\n") \
            from None
    if write_dir:
        # Found before any member runs, not after all of them.
        write_dir = os.path.abspath(os.fspath(write_dir))
        try:
            os.makedirs(write_dir, exist_ok=True)
        except OSError as e:
            raise UsageError(f"error: cannot create write_dir '{write_dir}': "
                             f"{e.strerror}\n") from None
        if not os.access(write_dir, os.W_OK | os.X_OK):
            raise UsageError(f"error: cannot write to write_dir "
                             f"'{write_dir}'\n")
    return {"path": path, "source": source,
            "hash": hashlib.sha256(source).hexdigest(),
            "compile": compile_options,
            "compile_key": repr(sorted(compile_options.items())),
            "run": run, "write_dir": write_dir, "write_format": write_format}


def _write_index(write_dir, result):
    """members.csv: index, parameters, status, file of every member."""
    names = list(result.params)
    with open(os.path.join(write_dir, "members.csv"), "w") as f:
        f.write(",".join(["member"] + names + ["status", "file"]) + "\n")
        for r in result.members:
            cells = [str(r["index"])]
            cells += [format_value(r["params"][n]) if n in r["params"] else ""
                      for n in names]
            cells += [str(r["status"]), os.path.basename(r.get("file", ""))]
            f.write(",".join(cells) + "\n")


def sweep(model, params, *, scheduler=None, client=None, n_workers=None,
          chunk_size=None, progress=True, write_dir=None, write_format="mat",
          model_name=None, method="dd", outputs=None, jit="auto",
          overrides=None, cache=True, **run):
    """Runs ``model`` (a .lsd path or an ldaec.Model) once per member of
    ``params`` and returns a SweepResult.

    ``scheduler``: None starts a local cluster of ``n_workers`` processes
    (default: the machine's cores) for this call; ``"tcp://host:8786"``
    uses a running Dask scheduler; ``"serial"`` runs the members one after
    another in this process (no Dask). ``client``: an existing
    distributed.Client (its cluster is kept). ``run`` are Model.simulate's
    arguments (stop, t0, rtol, atol, interval, start, integrator, ...);
    the compile arguments are ldaec.compile's. ``write_dir`` writes each
    member's result file there (``member_000042.mat``, or .csv with
    ``write_format="csv"``) and an index ``members.csv``.
    """
    if "params" in run:
        raise UsageError("error: the swept parameters are sweep's params=\n")
    compile_options = dict(model=model_name, method=method, outputs=outputs,
                           jit=jit, overrides=overrides, cache=cache)
    spec = _spec(model, compile_options, run, write_dir, write_format)
    members = list(enumerate(members_of(params)))
    counter = _Progress(len(members), progress)
    t0 = time.perf_counter()

    if scheduler == "serial":
        setup = time.perf_counter() - t0
        records = []
        for chunk in _chunks(members, 64):
            batch = run_chunk(spec, chunk)
            counter.add(batch)
            records += batch
        result = SweepResult(records, setup, time.perf_counter() - t0 - setup)
    else:
        result = _on_dask(spec, members, scheduler, client, n_workers,
                          chunk_size, counter, t0)
    if spec["write_dir"]:
        _write_index(spec["write_dir"], result)
    return result


def _not_run(index, params, why):
    """The record of a member that has no result of its own: `why` it did
    not run to its end (WORKER_DIED)."""
    values = ", ".join(f"{k}={format_value(v)}" for k, v in params.items())
    return {"index": index, "params": params, "status": WORKER_DIED,
            "diagnostics": f"error: member {index} ({values}): {why}\n",
            "time": None, "values": None, "recompiled": False,
            "wall_time": 0.0}


def _on_dask(spec, members, scheduler, client, n_workers, chunk_size,
             counter, t0):
    import distributed

    owned = []
    try:
        if client is None:
            if scheduler is None:
                cluster = distributed.LocalCluster(
                    n_workers=n_workers or os.cpu_count() or 1,
                    threads_per_worker=1, processes=True,
                    dashboard_address=None)
                owned.append(cluster)
                client = distributed.Client(cluster)
            else:
                client = distributed.Client(scheduler)
            owned.insert(0, client)
        workers = max(1, len(client.scheduler_info()["workers"]))
        setup = time.perf_counter() - t0
        size = chunk_size or max(1, min(256, math.ceil(
            len(members) / (8 * workers))))
        chunk_of, tries = {}, {}
        for chunk in _chunks(members, size):
            chunk_of[client.submit(run_chunk, spec, chunk, pure=False)] = chunk
        records = []
        # Results are fetched by the client's event loop as tasks end, not
        # one blocking round trip per chunk. A task whose worker died (Dask
        # retries it on others, then gives up: KilledWorker) loses no other
        # member: its members become suspects, run again one at a time
        # once nothing else is in flight, so that a worker's death names
        # the one member it ran (Dask counts a death against every task
        # queued on the worker too, and a member queued beside the one
        # that kills its workers was reported with it on a busy machine).
        # The member that kills its worker alone is reported, with its
        # parameters.
        # A watchdog: with tasks pending and no worker left for
        # _NO_WORKER_GRACE seconds (workers that died and were not
        # restarted), the members left are reported as not run and the
        # sweep returns what it has.
        grace = float(os.environ.get("LDAEC_SWEEP_NO_WORKER_GRACE",
                                     _NO_WORKER_GRACE))
        alone_since = None
        suspects = []
        while chunk_of or suspects:
            if suspects and not chunk_of:
                member = suspects.pop(0)
                chunk_of[client.submit(run_chunk, spec, [member],
                                       pure=False)] = [member]
            try:
                done, _ = distributed.wait(list(chunk_of),
                                           timeout=_WATCH_INTERVAL,
                                           return_when="FIRST_COMPLETED")
            except _TIMEOUTS:
                done = ()
            progress = False
            for future in done:
                chunk = chunk_of.pop(future)
                try:
                    batch = future.result(timeout=_WATCH_INTERVAL)
                except _TIMEOUTS:
                    # Finished, but its result went with its worker before
                    # it was fetched: Dask runs it again, or the watchdog
                    # reports it.
                    chunk_of[future] = chunk
                    continue
                except Exception as e:  # the worker died, or the task failed
                    progress = True
                    single = len(chunk) == 1
                    again = [m for m in chunk
                             if not single or
                             tries.get(m[0], 0) < _MEMBER_TRIES]
                    if again:
                        for member in again:
                            tries[member[0]] = tries.get(member[0], 0) + single
                        suspects += again
                        continue
                    [(index, params)] = chunk
                    batch = [_not_run(index, params,
                                      f"the worker process running it died: "
                                      f"{type(e).__name__}: {e}")]
                progress = True
                counter.add(batch)
                records += batch
            if progress or not chunk_of or client.scheduler_info()["workers"]:
                alone_since = None
            elif alone_since is None:
                alone_since = time.perf_counter()
            elif time.perf_counter() - alone_since > grace:
                batch = [_not_run(i, p, "no worker was left to run it (the "
                                  "cluster's workers died and none came back "
                                  "within %g s)" % grace)
                         for chunk in (list(chunk_of.values()) +
                                       [[m] for m in suspects])
                         for i, p in chunk]
                suspects.clear()
                client.cancel(list(chunk_of))
                chunk_of.clear()
                counter.add(batch)
                records += batch
        return SweepResult(records, setup, time.perf_counter() - t0 - setup)
    finally:
        for thing in owned:
            thing.close()
