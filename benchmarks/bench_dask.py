"""The Monte Carlo on dask against the process pool it replaced: trials per second of the
default ``dptbd compare``, scheduling overhead per task, numba kernel loading per worker;
and ``dptbd table1`` in this process (how it ran before dask) against dask.

    python benchmarks/bench_dask.py                      # default comparison, 240 trials
    python benchmarks/bench_dask.py --trials 96 --json build/bench_dask.json
    python benchmarks/bench_dask.py --table1-trials 0    # without table1

One process, one run after the other, on the same spec (the default
:func:`dptbd.evaluation.compare.build_spec`, bootstrap off since it is not the Monte Carlo):

* ``in process``   : ``run_compare(spec, workers=1)`` (no dask, as before);
* ``old pool, N``  : the ``ProcessPoolExecutor`` (fork) code that ``run_compare`` had before
  dask (:func:`_old_pool`, a copy of it kept here only to be measured), N = 1, 2;
* ``dask local, N``: ``run_compare`` on a LocalCluster of N worker processes started by
  :func:`dptbd.evaluation.execution.local_cluster`, as ``run_compare(spec, workers=N)``
  starts for N > 1 (one thread each, Dask's housekeeping slowed); its start (processes
  spawned, packages imported, kernels loaded by the warm-up plugin) is timed apart, outside
  :attr:`CompareResult.seconds` (the pool's fork is inside its time).

The ways run in rounds (``--repeat``), each way once per round, and the medians are printed:
the machine is shared and its load drifts.

``table1`` (``--table1-trials`` per setting, 6 settings, tasks of 10 trials of one setting):
``run_table1(workers=1)`` (in this process, as before dask: numba's threads on every core
for the DP kernel) and ``run_table1`` on a LocalCluster of N = 1, 2 workers (one thread
each) started and warmed (kernels loaded) beforehand; its time includes connecting, the
worker checks and the warm-up plugin's second, quick, call.

All runs' counts (and table1 rows) are checked identical (the script fails otherwise). Per-task scheduling
overhead: wall time per task of ``N_NOOP`` empty tasks on the 2-worker LocalCluster, and as a
fraction of the mean task time (one chunk of ``spec.chunk`` trials, in process). Kernel
loading: ``_warm(plan)`` in a fresh worker from numba's on-disk cache, and in a fresh
interpreter with an empty ``NUMBA_CACHE_DIR`` (a full compile). Idle cluster CPU: what an
idle 2-worker LocalCluster and its client use (psutil, which distributed depends on), with
Dask's default housekeeping and with ``local_cluster``'s. The load average is printed: the
machine is shared.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import pathlib
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor, as_completed

import distributed
import numpy as np
import psutil

from dptbd.evaluation.compare import build_spec, make_plan, run_compare
from dptbd.evaluation.compare.runner import _chunk, _warm
from dptbd.evaluation.execution import Execution, local_cluster, map_tasks
from dptbd.evaluation.table1 import experiment as table1
from dptbd.evaluation.table1.experiment import SETTINGS, run_table1

N_NOOP = 400
IDLE_SECONDS = 20.0


def _idle_cpu(quiet: bool) -> float:
    """CPU (fraction of one core) that an idle 2-worker LocalCluster and this process's client
    use over :data:`IDLE_SECONDS`: with :func:`local_cluster`'s quiet housekeeping, or with
    dask's defaults (the same cluster otherwise)."""
    if quiet:
        cluster = local_cluster(2)
    else:
        cluster = distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
            scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}, silence_logs=40)
    with cluster, distributed.Client(cluster) as client:
        client.wait_for_workers(2)
        time.sleep(2.0)  # the start's work done
        me = psutil.Process()
        procs = [me] + me.children(recursive=True)
        before = sum(sum(p.cpu_times()[:2]) for p in procs)
        start = time.perf_counter()
        time.sleep(IDLE_SECONDS)
        used = sum(sum(p.cpu_times()[:2]) for p in procs) - before
        return used / (time.perf_counter() - start)


def _old_pool(plan, workers: int) -> tuple[float, list]:
    """The pre-dask path of ``run_compare`` (fork pool, one future per chunk); its seconds."""
    spec = plan.spec
    bounds = [(a, min(a + spec.chunk, spec.trials)) for a in range(0, spec.trials, spec.chunk)]
    parts = [None] * len(bounds)
    start = time.perf_counter()
    ctx = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(max_workers=min(workers, len(bounds)), mp_context=ctx) as pool:
        jobs = {pool.submit(_chunk, plan, a, b): i for i, (a, b) in enumerate(bounds)}
        for job in as_completed(jobs):
            parts[jobs[job]] = job.result()
    return time.perf_counter() - start, parts


def _noop() -> None:
    return None


def _timed_warm(plan) -> float:
    start = time.perf_counter()
    _warm(plan)
    return time.perf_counter() - start


def _compile_seconds() -> float:
    """``_warm`` of the default plan in a fresh interpreter with an empty numba cache."""
    code = ("import time; from dptbd.evaluation.compare import build_spec, make_plan; "
            "from dptbd.evaluation.compare.runner import _warm; p = make_plan(build_spec({}, "
            "trials=8, bootstrap=0)); t = time.perf_counter(); _warm(p); "
            "print(time.perf_counter() - t)")
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                             text=True, check=True)
    return float(out.stdout.split()[-1])


def _table1_round(trials: int, reference: list, seconds: dict) -> None:
    """One round of table1: in this process, then on LocalClusters of 1 and 2 workers; the
    rows checked equal to ``reference``."""
    start = time.perf_counter()
    rows = run_table1(trials, workers=1).rows
    seconds.setdefault("table1 in process", []).append(time.perf_counter() - start)
    assert rows == reference, "table1 in process: rows differ"
    for n in (1, 2):
        with local_cluster(n) as cluster:
            with distributed.Client(cluster) as client:  # kernels loaded before the clock,
                client.run(table1._warm, table1.table1_config(), 2003)  # as compare's start
            start = time.perf_counter()
            rows = run_table1(trials, scheduler=cluster.scheduler_address, workers=n).rows
            seconds.setdefault(f"table1 dask, {n}", []).append(time.perf_counter() - start)
        assert rows == reference, f"table1 dask {n}: rows differ"


def _same(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=240, help="trials (default 240, the default run)")
    ap.add_argument("--repeat", type=int, default=2, help="rounds; medians printed (default 2)")
    ap.add_argument("--table1-trials", type=int, default=20,
                    help="table1 trials per setting (default 20; 0: table1 not measured)")
    ap.add_argument("--json", metavar="PATH", help="also write the numbers as JSON")
    args = ap.parse_args(argv)
    spec = build_spec({}, trials=args.trials, bootstrap=0)
    plan = make_plan(spec)
    _warm(plan)
    n_tasks = -(-spec.trials // spec.chunk)
    load0 = os.getloadavg()[0]

    ref = run_compare(spec, workers=1)  # the reference counts; also warms this process
    table1_ref = run_table1(args.table1_trials, workers=1).rows if args.table1_trials else None
    seconds: dict = {}
    start_seconds: dict = {}
    for _ in range(args.repeat):  # rounds: every way once per round, so load drifts hit all
        res = run_compare(spec, workers=1)
        seconds.setdefault("in process", []).append(res.seconds)
        for n in (1, 2):
            took, parts = _old_pool(plan, n)
            counts = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
            assert _same(ref.counts, counts), f"old pool {n}: counts differ"
            seconds.setdefault(f"old pool, {n}", []).append(took)
            start = time.perf_counter()
            with local_cluster(n) as cluster:
                res = run_compare(spec, scheduler=cluster.scheduler_address, workers=n)
            total = time.perf_counter() - start
            assert _same(ref.counts, res.counts), f"dask local {n}: counts differ"
            seconds.setdefault(f"dask local, {n}", []).append(res.seconds)
            start_seconds.setdefault(f"dask local, {n}", []).append(total - res.seconds)
        if args.table1_trials:
            _table1_round(args.table1_trials, table1_ref, seconds)
    rows = {name: dict(seconds=float(np.median(s)), all_seconds=s,
                       start_seconds=float(np.median(start_seconds[name]))
                       if name in start_seconds else None)
            for name, s in seconds.items()}

    with Execution(workers=2).client() as client:
        map_tasks(_noop, [()] * 20, client)  # the first round trip
        start = time.perf_counter()
        map_tasks(_noop, [()] * N_NOOP, client)
        per_task = (time.perf_counter() - start) / N_NOOP
        fresh = client.run(_timed_warm, plan)  # first call in each worker: the on-disk cache
        again = client.run(_timed_warm, plan)  # loaded: nothing left to do
    idle = {name: [_idle_cpu(quiet) for _ in range(args.repeat)]
            for name, quiet in (("dask defaults", False), ("quiet", True))}
    mean_task = ref.seconds / n_tasks
    compile_s = _compile_seconds()
    load1 = os.getloadavg()[0]

    print(f"default compare, {spec.trials} trials in {n_tasks} tasks of {spec.chunk} trials, "
          f"{len(plan.floats) + len(plan.fixed)} detector runs per scene; load {load0:.1f} -> "
          f"{load1:.1f}; {os.cpu_count()} cores")
    print(f"{'':16s} {'Monte Carlo s':>13s} {'trials/s':>9s} {'start s':>8s}   (median of "
          f"{args.repeat}; every run's seconds)")
    table1_trials = args.table1_trials * len(SETTINGS)
    for name, r in rows.items():  # table1: trials of all settings
        r["trials_per_second"] = (table1_trials if name.startswith("table1")
                                  else spec.trials) / r["seconds"]
        st = "" if r["start_seconds"] is None else f"{r['start_seconds']:8.2f}"
        each = " ".join(f"{s:.1f}" for s in r["all_seconds"])
        print(f"{name:16s} {r['seconds']:13.2f} {r['trials_per_second']:9.2f} {st:>8s}   {each}")
    for n in (1, 2):
        ratio = rows[f"dask local, {n}"]["trials_per_second"] / rows[f"old pool, {n}"]["trials_per_second"]
        print(f"dask / old pool on {n} worker(s): {ratio:.3f}")
    table1_task = None
    if args.table1_trials:
        table1_tasks = len(SETTINGS) * -(-args.table1_trials // 10)
        table1_task = rows["table1 in process"]["seconds"] / table1_tasks
        for n in (1, 2):
            ratio = rows["table1 in process"]["seconds"] / rows[f"table1 dask, {n}"]["seconds"]
            print(f"table1 ({table1_trials} trials in {table1_tasks} tasks): speed of dask on "
                  f"{n} worker(s) / in process: {ratio:.3f}")
    print(f"scheduling overhead: {per_task * 1e3:.2f} ms per task ({N_NOOP} empty tasks, 2 "
          f"workers) = {100 * per_task / mean_task:.2f} % of a mean compare task "
          f"({mean_task:.3f} s)" + ("" if table1_task is None else
                                    f", {100 * per_task / table1_task:.2f} % of a mean table1 "
                                    f"task ({table1_task:.3f} s)"))
    print(f"kernels per worker: {max(fresh.values()):.2f} s loading from numba's cache (first "
          f"call), {max(again.values()) * 1e3:.1f} ms after; full compile {compile_s:.1f} s")
    print("idle cluster CPU (2 workers, client, scheduler, nannies; fraction of one core, "
          f"median of {args.repeat} x {IDLE_SECONDS:.0f} s): "
          + ", ".join(f"{name} {np.median(v):.3f}" for name, v in idle.items()))
    if args.json:
        out = dict(trials=spec.trials, tasks=n_tasks, chunk=spec.chunk, runs=rows,
                   overhead_seconds_per_task=per_task, mean_task_seconds=mean_task,
                   table1_trials_per_setting=args.table1_trials,
                   table1_mean_task_seconds=table1_task,
                   warm_from_cache_seconds=max(fresh.values()),
                   warm_again_seconds=max(again.values()), compile_seconds=compile_s,
                   idle_cluster_cpu={k: float(np.median(v)) for k, v in idle.items()},
                   load_average=[load0, load1])
        pathlib.Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        pathlib.Path(args.json).write_text(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
