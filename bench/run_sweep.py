#!/usr/bin/env python3
"""A parameter sweep of the RC circuit (tests/models/rc_circuit.lsd) from
Python: N members (R over a range) on a local Dask cluster of --workers
processes, against the same members one after another in this process
over one compiled model (the reference, same script, same machine).

Reported separately: the cluster's start (processes, scheduler), the
sweep on the cluster (each worker compiles the model once on its first
chunk, then runs its members; results come back as arrays), the serial
run, and their ratio. Each figure is the best of --repeat.

Usage: PYTHONPATH=build/python /usr/bin/python3 bench/run_sweep.py
           [--members 1000] [--workers 2] [--repeat 3] [--write]
  --write  writes the table into docs/benchmarks.md ("Python sweep").
Needs the module (docs/python.md) and Debian's python3-distributed.
"""
import argparse
import os
import platform
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MODEL = os.path.join(ROOT, "tests", "models", "rc_circuit.lsd")
DOC = os.path.join(ROOT, "docs", "benchmarks.md")
sys.path.insert(0, HERE)
from benchdoc import write_section  # noqa: E402


def serial(ldaec, members, run):
    """Compile once, then every member in turn: (compile s, run s)."""
    t0 = time.perf_counter()
    m = ldaec.compile(MODEL, cache=False)
    t1 = time.perf_counter()
    for p in members:
        r = m.simulate(params=p, **run)
        assert r.status == 0, r.diagnostics
    return t1 - t0, time.perf_counter() - t1


def on_dask(ldaec, distributed, members, run, workers):
    """(cluster start s, first sweep s, second sweep s) on a fresh local
    cluster: the first sweep's workers import the module and compile the
    model, the second's have both done."""
    t0 = time.perf_counter()
    cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1,
                                       processes=True, dashboard_address=None)
    client = distributed.Client(cluster)
    client.wait_for_workers(workers)
    times = [time.perf_counter() - t0]
    try:
        for _ in range(2):
            t1 = time.perf_counter()
            result = ldaec.sweep(MODEL, members, client=client, cache=False,
                                 progress=False, **run)
            times.append(time.perf_counter() - t1)
            assert not result.failed, result.summary()
            assert result["capacitor.v"].shape[0] == len(members)
    finally:
        client.close()
        cluster.close()
    return times


# The sweep (the circuit's own experiment: to t = 0.5, 101 rows of
# every variable), and members a few milliseconds long (5001 rows of one
# output at a tight tolerance), where the cost of a task is amortized.
WORKLOADS = [
    ("to t = 0.5, 101 rows of every variable", {"stop": 0.5}),
    ("to t = 5, 5001 rows of capacitor.v, rtol 1e-10",
     {"stop": 5, "interval": 1e-3, "rtol": 1e-10, "atol": 1e-12,
      "outputs": ["capacitor.v"]}),
]


def measure(ldaec, distributed, members, run, args):
    compile_s, serial_s = min(serial(ldaec, members, run)
                              for _ in range(args.repeat))
    dask = [on_dask(ldaec, distributed, members, run, args.workers)
            for _ in range(args.repeat)]
    start_s, cold_s, warm_s = (min(d[k] for d in dask) for k in range(3))
    return compile_s, serial_s, start_s, cold_s, warm_s


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--members", type=int, default=1000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--write", "--doc", action="store_true")
    args = ap.parse_args()
    import distributed
    import ldaec

    n = args.members
    members = [{"R": 50 + 100 * k / max(1, n - 1)} for k in range(n)]
    rows = []
    for label, run in WORKLOADS:
        c, s, start, cold, warm = measure(ldaec, distributed, members, run,
                                          args)
        rows.append(f"| {label} | {c:.3f} | {s:.3f} ({s / n * 1e3:.2f} ms) "
                    f"| {start:.2f} | {cold:.3f} | {warm:.3f} "
                    f"| {s / cold:.2f} | {s / warm:.2f} |")
    table = "\n".join(rows)
    cores = os.cpu_count()
    load = os.getloadavg()[0]
    section = f"""## Python sweep

`bench/run_sweep.py{' --write' if args.write else ''}` ({platform.node()}, {cores} cores, load
average {load:.1f} when it ended): {n} members of the RC circuit
(tests/models/rc_circuit.lsd, R from 50 to 150), best of {args.repeat},
seconds. Serial: the model compiled once, then run {n} times in one
process (`Model.simulate`). Dask: a local cluster of {args.workers} worker
processes started (reported apart), then `ldaec.sweep` twice on it: the
first sweep's workers import the module and compile the model once each,
the second finds both done. Members go in chunks of about {n // (8 * args.workers)}, results
come back stacked into arrays. Speed-up: serial time over the sweep's
(above 1: Dask faster).

| members | compile | serial | cluster start | first sweep | second sweep | speed-up first | speed-up second |
|---|---:|---:|---:|---:|---:|---:|---:|
{table}

Members of a tenth of a millisecond cost less than a task's round trip
through the scheduler and back per chunk; the {args.workers} workers also share
the {cores} cores with the client, the scheduler and whatever else runs.
"""
    if args.write:
        os.environ["LDAE_BENCH_DOC"] = "1"
    write_section(DOC, "Python sweep", section)


if __name__ == "__main__":
    main()
