"""``dptbd compare`` on dask (:mod:`dptbd.evaluation.execution`): the same CSVs on one worker,
two local workers and a two-worker cluster started here as separate processes (``dask
scheduler`` + two ``dask worker`` on 127.0.0.1, ephemeral ports); a worker killed by its pid
mid-run loses and duplicates no trial."""

from __future__ import annotations

import os
import pathlib
import signal

import numpy as np
import pytest
from helpers.dask_processes import process_cluster

from dptbd.evaluation.compare import compare_job
from dptbd.evaluation.compare.plan import make_plan
from dptbd.evaluation.compare.runner import _chunk
from dptbd.evaluation.compare.spec import build_spec
from dptbd.evaluation.execution import Execution, cluster_workers, map_tasks

CSVS = ("compare_pd.csv", "compare_pfa.csv", "compare_configs.csv")


@pytest.fixture
def cluster(tmp_path):
    """``(scheduler address, [worker pids])`` of a scheduler and two single-thread workers
    (:func:`dask_processes.process_cluster`), stopped afterwards."""
    with process_cluster(tmp_path) as (address, pids):
        yield address, list(pids.values())


def _csvs(folder: pathlib.Path) -> dict:
    return {name: (folder / name).read_bytes() for name in CSVS}


def test_one_worker_two_local_workers_and_a_cluster_write_identical_csvs(
        small_compare, tmp_path, cluster):
    address, _ = cluster
    runs = {"one": dict(workers=1), "two": dict(workers=2), "cluster": dict(scheduler=address)}
    got = {}
    for label, kw in runs.items():
        outcome = compare_job(small_compare, tmp_path / label, progress=False, **kw)
        got[label] = _csvs(tmp_path / label)
        assert outcome.result.workers == (2 if label != "one" else 1)
    assert got["one"] == got["two"] == got["cluster"]


def test_a_worker_killed_mid_run_loses_and_duplicates_no_trial(small_compare, cluster):
    address, pids = cluster
    plan = make_plan(build_spec(dict(small_compare, trials=40, chunk=2)))
    tasks = [(plan, a, a + 2) for a in range(0, 40, 2)]
    expected = map_tasks(_chunk, tasks)  # in this process
    finished = []

    def kill_once(i):
        finished.append(i)
        if len(finished) == 2:
            os.kill(pids[0], signal.SIGKILL)

    with Execution(workers=2, scheduler=address).client() as client:
        got = map_tasks(_chunk, tasks, client, done=kill_once)
        assert len(cluster_workers(client)) == 1  # the killed one is gone
    assert sorted(finished) == list(range(len(tasks)))  # each task once
    for e, g in zip(expected, got):
        assert e.keys() == g.keys()
        for key in e:
            assert np.array_equal(e[key], g[key]), key
