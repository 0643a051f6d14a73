"""The execution layer (:mod:`dptbd.evaluation.execution`): worker counts, an unreachable
scheduler, too few workers, unfit workers, tasks in task order."""

from __future__ import annotations

import re
import socket
import time

import pytest

from dptbd.evaluation import execution
from dptbd.evaluation.execution import Execution, ExecutionError, check_workers, map_tasks


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("workers", [0, -1, True, 1.5])
def test_bad_worker_counts_are_refused(workers):
    with pytest.raises(ExecutionError, match=rf"^workers must be an integer >= 1, got "
                                             rf"{re.escape(repr(workers))}$"):
        Execution(workers=workers)


def test_workers_are_needed_without_a_scheduler(monkeypatch):
    monkeypatch.delenv(execution.SCHEDULER_ENV, raising=False)
    with pytest.raises(ExecutionError, match=r"^workers must be given without a scheduler$"):
        Execution(workers=None)


def test_the_environment_variable_names_the_scheduler(monkeypatch):
    monkeypatch.setenv(execution.SCHEDULER_ENV, "tcp://10.0.0.1:8786")
    assert Execution(workers=None).address == "tcp://10.0.0.1:8786"
    assert Execution(workers=None, scheduler="tcp://h:1").address == "tcp://h:1"
    assert not Execution(workers=1).in_process


def test_one_worker_runs_in_this_process_in_order(monkeypatch):
    monkeypatch.delenv(execution.SCHEDULER_ENV, raising=False)
    seen = []
    with Execution(workers=1).client() as client:
        assert client is None
        out = map_tasks(pow, [(2, 3), (3, 2), (5, 1)], client, done=seen.append)
    assert out == [8, 9, 5] and seen == [0, 1, 2]


def test_an_unreachable_scheduler_fails_within_seconds():
    address = f"tcp://127.0.0.1:{_free_port()}"
    start = time.perf_counter()
    with pytest.raises(ExecutionError, match=rf"^cannot reach the dask scheduler at "
                                             rf"{re.escape(address)} within 1 s \(\w+\)$"):
        with Execution(workers=None, scheduler=address, connect_timeout=1.0).client():
            pass
    assert time.perf_counter() - start < 10


@pytest.fixture(scope="module")
def threaded_cluster():
    """One in-process worker (threads): enough to test the checks, fast to start."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        yield cluster


def test_tasks_on_a_cluster_come_back_in_task_order(threaded_cluster):
    with Execution(workers=1, scheduler=threaded_cluster.scheduler_address).client() as client:
        assert client is not None
        out = map_tasks(time.sleep, [(0.2,), (0.0,), (0.1,)], client)
        assert out == [None, None, None]
        assert map_tasks(pow, [(2, k) for k in range(20)], client) == [2 ** k for k in range(20)]


def test_too_few_workers_are_refused(threaded_cluster):
    address = threaded_cluster.scheduler_address
    with pytest.raises(ExecutionError, match=rf"^the dask cluster at {re.escape(address)} has 1 "
                                             rf"worker\(s\), 3 asked for$"):
        with Execution(workers=3, scheduler=address, connect_timeout=0.5).client():
            pass


def test_a_worker_with_another_dptbd_version_is_refused(threaded_cluster):
    import distributed

    with distributed.Client(threaded_cluster) as client:
        check_workers(client)  # the same environment: fit
        worker = re.escape(next(iter(client.scheduler_info()["workers"])))
        mine = re.escape(execution.version())
        with pytest.raises(ExecutionError, match=(
                rf"^unfit dask workers \(every worker needs the same dptbd, see "
                rf"docs/distributed\.md\): worker {worker} has dptbd {mine}, this process 0\.0\.0$")):
            check_workers(client, expected="0.0.0")


def test_a_worker_lacking_a_package_is_refused_by_name(threaded_cluster):
    import distributed

    with distributed.Client(threaded_cluster) as client:
        worker = re.escape(next(iter(client.scheduler_info()["workers"])))
        with pytest.raises(ExecutionError, match=(
                rf"^unfit dask workers \(every worker needs the same dptbd, see "
                rf"docs/distributed\.md\): worker {worker} lacks the Python package "
                rf"'no_such_package_h9'$")):
            check_workers(client, packages=("dptbd", "numba", "no_such_package_h9"))
