"""The verification campaign (``dptbd verify``) on the Dask execution layer against the
process pool it replaced: wall time on 1 and 2 workers and their ratio.

    python benchmarks/bench_campaign.py                         # --runs-scale 0.1, 3 rounds
    python benchmarks/bench_campaign.py --runs-scale 0.05 --repeat 2 --json build/bench_campaign.json

One process, the same campaign slice (every default case, ``round(runs * runs_scale)`` runs
each, at least one, and the four 4-state store checks on Icarus) run in these ways:

* ``in process``        : ``run_campaign(workers=1)``, as ``dptbd verify --workers 1`` (no
  Dask, one run after the other);
* ``old pool, N``       : the ``ProcessPoolExecutor`` loop ``run_campaign`` had before Dask
  (:func:`_old_pool`, a copy kept here only to be measured), N = 1, 2; its time includes
  starting the pool, as it did in ``dptbd verify``;
* ``dask cluster, N``   : ``run_campaign(scheduler=…)`` on a LocalCluster of N worker
  processes (:func:`dptbd.evaluation.execution.local_cluster`) started before the clock;
* ``dask local, 2``     : ``run_campaign(workers=2)``, as ``dptbd verify --workers 2``: its
  time includes starting the LocalCluster and checking its workers.

Every Verilator executable is built (or found in the cache) before the first round, so no
way pays for a build. Beside each wall time, the CPU time of this process and its waited-for
children (``os.times``: the pool's or the cluster's processes, the simulators they ran) over
the way, pool or cluster start and stop included: what the way costs whatever the load. The ways run in rounds (``--repeat``), each way once per round, and
the medians are printed with the ratio of the 1-worker to the 2-worker time: the machine is
shared and its load drifts (the load average is printed). Every way's outcomes (every run
and store check, without timings) are checked equal to the in-process ones; the script
fails otherwise.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import pathlib
import statistics
import time
from concurrent.futures import ProcessPoolExecutor

from dptbd.evaluation.execution import local_cluster
from dptbd.sim.campaign import (CampaignResult, campaign_task, campaign_tasks, default_cases,
                                run_campaign)


def _old_pool(tasks: list[tuple], workers: int) -> tuple[float, list]:
    """The pre-Dask loop of ``run_campaign`` (a process pool, the futures read in task
    order); its seconds and outcomes."""
    start = time.perf_counter()
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(campaign_task, *t) for t in tasks]
        outcomes = [f.result() for f in futures]
    return time.perf_counter() - start, outcomes


def _cpu() -> float:
    """User + system seconds of this process and its waited-for children."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def _untimed(outcomes) -> list:
    return [dataclasses.replace(o, sim_seconds=0.0, wall_seconds=0.0) for o in outcomes]


def _campaign(**kwargs) -> tuple[float, list]:
    result: CampaignResult = run_campaign(**kwargs)
    return result.wall_seconds, list(result.outcomes)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs-scale", type=float, default=0.1)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", type=pathlib.Path)
    args = parser.parse_args()

    from dptbd.sim.verilator import build

    cases = default_cases()
    for case in cases:                                   # every build before the clock
        build(case.cfg, case.design)
    tasks = campaign_tasks(cases, runs_scale=args.runs_scale, base_seed=args.seed)
    common = dict(cases=cases, runs_scale=args.runs_scale, base_seed=args.seed)
    print(f"{len(tasks)} tasks ({len(tasks) - 4} Verilator runs, 4 Icarus store checks), "
          f"load average {os.getloadavg()[0]:.2f}", flush=True)

    seconds: dict[str, list[float]] = {}
    cpu: dict[str, list[float]] = {}
    reference = None

    def on_cluster(n: int) -> tuple[float, list]:
        with local_cluster(n) as cluster:
            return _campaign(scheduler=cluster.scheduler_address, workers=n, **common)

    ways = {"in process": lambda: _campaign(workers=1, **common),
            "old pool, 1": lambda: _old_pool(tasks, 1),
            "old pool, 2": lambda: _old_pool(tasks, 2),
            "dask cluster, 1": lambda: on_cluster(1),
            "dask cluster, 2": lambda: on_cluster(2),
            "dask local, 2": lambda: _campaign(workers=2, **common)}
    for r in range(args.repeat):
        for name, run in ways.items():
            before = _cpu()
            took, outcomes = run()
            cpu.setdefault(name, []).append(_cpu() - before)
            seconds.setdefault(name, []).append(took)
            reference = _untimed(outcomes) if reference is None else reference
            assert _untimed(outcomes) == reference, f"{name}: outcomes differ"
        print(f"round {r + 1}: " + ", ".join(f"{k} {v[-1]:.2f} s" for k, v in seconds.items())
              + f" (load {os.getloadavg()[0]:.2f})", flush=True)

    median = {k: statistics.median(v) for k, v in seconds.items()}
    words = sum(o.words_out for o in reference)
    median_cpu = {k: statistics.median(v) for k, v in cpu.items()}
    print(f"\n{'way':18s} {'median s':>9s} {'CPU s':>7s}  rounds (s)")
    for k, v in seconds.items():
        print(f"{k:18s} {median[k]:9.2f} {median_cpu[k]:7.1f}  "
              f"{', '.join(f'{s:.2f}' for s in v)}")
    ratios = {"old pool 1 / 2": median["old pool, 1"] / median["old pool, 2"],
              "dask cluster 1 / 2": median["dask cluster, 1"] / median["dask cluster, 2"],
              "in process / dask local 2": median["in process"] / median["dask local, 2"],
              "dask local 2 / old pool 2": median["dask local, 2"] / median["old pool, 2"]}
    print(f"\n{words} words compared per way, all ways' outcomes identical")
    for k, v in ratios.items():
        print(f"{k:28s} {v:.2f}")
    print(f"load average at the end {os.getloadavg()[0]:.2f}")
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({
            "runs_scale": args.runs_scale, "seed": args.seed, "tasks": len(tasks),
            "words_compared": words, "seconds": seconds, "median": median, "cpu": cpu,
            "median_cpu": median_cpu, "ratios": ratios}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
