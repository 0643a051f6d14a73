"""The execution layer (:mod:`dptbd.evaluation.execution`): worker counts, an unreachable
scheduler, too few workers, unfit workers, tasks in task order."""

from __future__ import annotations

import re
import socket
import time
import urllib.error
import urllib.request

import pytest

from dptbd.evaluation import execution
from dptbd.evaluation.execution import (Execution, ExecutionError, check_worker_count,
                                        check_workers, cluster_workers, job_execution,
                                        map_tasks, run_tasks)
from helpers.refusals import whole


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("workers", [0, -1, 1025, True, 1.5, "2"])
def test_bad_worker_counts_are_refused(workers):
    message = whole(f"workers must be an integer in [1, 1024], got {workers!r}")
    with pytest.raises(ExecutionError, match=message):
        Execution(workers=workers)
    with pytest.raises(ExecutionError, match=message):
        job_execution(workers)
    with pytest.raises(ExecutionError, match=message.replace("workers", "jobs", 1)):
        check_worker_count(workers, "jobs")


def test_job_execution_sizes_the_local_cluster(monkeypatch):
    monkeypatch.delenv(execution.SCHEDULER_ENV, raising=False)
    assert job_execution(None).workers == execution.default_workers()
    assert job_execution(None, tasks=1).in_process  # no idle processes
    assert job_execution(8, tasks=3).workers == 3
    assert job_execution(2, tasks=3, dashboard=True) == Execution(workers=2, dashboard=True)
    on_cluster = job_execution(None, scheduler="tcp://h:1", tasks=1)
    assert on_cluster.workers is None and on_cluster.address == "tcp://h:1"
    assert job_execution(5, scheduler="tcp://h:1", tasks=1).workers == 5  # the cluster's count


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


def test_the_dashboard_is_none_in_this_process(monkeypatch, capsys):
    monkeypatch.delenv(execution.SCHEDULER_ENV, raising=False)
    with Execution(workers=1, dashboard=True).client() as client:
        assert client is None
    assert capsys.readouterr().err == ("dask dashboard: none, one worker runs the tasks in this "
                                       "process without dask\n")


def test_the_dashboard_address_is_printed_and_serves_the_dashboard(monkeypatch, capsys):
    monkeypatch.delenv(execution.SCHEDULER_ENV, raising=False)
    with Execution(workers=2, dashboard=True).client() as client:
        line = capsys.readouterr().err
        found = re.fullmatch(r"dask dashboard: (http://127\.0\.0\.1:\d+/status)\n", line)
        assert found, line
        with urllib.request.urlopen(found[1], timeout=30) as page:
            assert page.status == 200
            assert b"Dask" in page.read()
        assert len(cluster_workers(client)) == 2
        assert set(client.run(_profiling).values()) == {True}   # the profile page has data
    with pytest.raises(urllib.error.URLError):  # shut down with the cluster
        urllib.request.urlopen(found[1], timeout=5)


def _profiling() -> bool:
    import dask
    return dask.config.get("distributed.worker.profile.enabled")


def _housekeeping() -> dict:
    import dask
    return {key: dask.config.get(key) for key in execution.QUIET_LOCAL_CLUSTER}


def test_local_workers_do_not_profile_without_a_dashboard(monkeypatch):
    """The workers' 10 ms stack sampler costs compute time and feeds only the dashboard."""
    monkeypatch.delenv(execution.SCHEDULER_ENV, raising=False)
    with Execution(workers=2).client() as client:
        assert set(client.run(_profiling).values()) == {False}


def test_local_workers_run_dasks_housekeeping_slowed_down(monkeypatch):
    """Every worker got the quiet settings (the nannies pass them on), and they are slower
    than Dask's defaults, not faster."""
    monkeypatch.delenv(execution.SCHEDULER_ENV, raising=False)
    import dask
    from dask.utils import parse_timedelta

    with Execution(workers=2).client() as client:
        seen = client.run(_housekeeping)
    assert list(seen.values()) == [execution.QUIET_LOCAL_CLUSTER] * 2
    defaults = dask.config.get("distributed")  # this process: dask's own values
    for key, value in execution.QUIET_LOCAL_CLUSTER.items():
        if isinstance(value, str):
            default = dask.config.get(key)
            assert parse_timedelta(value) > parse_timedelta(default), (key, default)
    assert defaults["worker"]["profile"]["enabled"] is True


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
    # the scheduler's HTTP server on an ephemeral port, as local_cluster's: 8787 may be taken
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None,
                                  scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}) as cluster:
        yield cluster


def test_tasks_on_a_cluster_come_back_in_task_order(threaded_cluster):
    with Execution(workers=1, scheduler=threaded_cluster.scheduler_address).client() as client:
        assert client is not None
        out = map_tasks(time.sleep, [(0.2,), (0.0,), (0.1,)], client)
        assert out == [None, None, None]
        assert map_tasks(pow, [(2, k) for k in range(20)], client) == [2 ** k for k in range(20)]


def test_too_few_workers_are_refused(threaded_cluster):
    address = threaded_cluster.scheduler_address
    with pytest.raises(ExecutionError, match=whole(f"the dask cluster at {address} has 1 "
                                                   f"worker(s), 3 asked for")):
        with Execution(workers=3, scheduler=address, connect_timeout=0.5).client():
            pass


def test_a_worker_with_another_dptbd_version_is_refused(threaded_cluster):
    import distributed

    with distributed.Client(threaded_cluster) as client:
        check_workers(client)  # the same environment: fit
        worker = next(iter(cluster_workers(client)))
        mine = execution.version()
        with pytest.raises(ExecutionError, match=whole(
                f"unfit dask workers (every worker needs the same dptbd, see "
                f"docs/distributed.md): worker {worker} has dptbd {mine}, this process 0.0.0")):
            check_workers(client, expected="0.0.0")


def test_a_worker_lacking_a_package_is_refused_by_name(threaded_cluster):
    import distributed

    with distributed.Client(threaded_cluster) as client:
        worker = next(iter(cluster_workers(client)))
        with pytest.raises(ExecutionError, match=whole(
                f"unfit dask workers (every worker needs the same dptbd, see "
                f"docs/distributed.md): worker {worker} lacks the Python package "
                f"'no_such_package_h9'")):
            check_workers(client, packages=("dptbd", "numba", "no_such_package_h9"))


def test_workers_that_truly_lack_numba_or_dptbd_or_cannot_import_numba_are_refused(tmp_path):
    """Real ``dask worker`` processes: one whose Python has no numba (neither importable nor
    installed), one without dptbd, one whose ``import numba`` fails (a ``numba`` package on
    its ``PYTHONPATH`` that raises ImportError); the job refuses before any task, naming
    each."""
    from helpers.dask_processes import DASK, process_cluster, worker_addresses, worker_lacking
    from dptbd.evaluation.table1.experiment import run_table1

    broken = tmp_path / "broken" / "numba"
    broken.mkdir(parents=True)
    (broken / "__init__.py").write_text("raise ImportError('numba is broken here')\n")
    broken_numba = ["env", f"PYTHONPATH={broken.parent}", str(DASK)]
    workers = {"no-numba": worker_lacking(tmp_path / "site-a", ["numba"]),
               "no-dptbd": worker_lacking(tmp_path / "site-b", ["dptbd"]),
               "broken-numba": broken_numba + ["worker"]}
    with process_cluster(tmp_path, workers) as (address, _):
        w = {name: re.escape(a) for name, a in worker_addresses(address).items()}
        problems = sorted([(w["no-dptbd"], "lacks the Python package 'dptbd'")]) + sorted(
            [(w["no-numba"], "lacks the Python package 'numba'"),
             (w["broken-numba"], r"cannot import the Python package 'numba' \(ImportError: "
                                 r"numba is broken here\)")])
        with pytest.raises(ExecutionError, match=(
                r"^unfit dask workers \(every worker needs the same dptbd, see "
                r"docs/distributed\.md\): " + "; ".join(f"worker {a} {p}" for a, p in problems)
                + "$")):
            run_table1(1, scheduler=address, workers=None, size=24)


def test_run_tasks_connects_then_prepares_then_reports_every_result(threaded_cluster):
    """In this process and on a cluster: ``prepare`` once before the tasks, ``on_result``
    once per task, results in task order, the workers that ran them; an unreachable
    scheduler is refused before ``prepare``."""
    tasks = [(2, k) for k in range(6)]
    for where in (Execution(workers=1),
                  Execution(workers=1, scheduler=threaded_cluster.scheduler_address)):
        calls = []
        results, used = run_tasks(pow, tasks, where,
                                  prepare=lambda: calls.append("prepare"),
                                  on_result=lambda i, r: calls.append((i, r)))
        assert results == [2 ** k for k in range(6)] and used == 1
        assert calls[0] == "prepare" and sorted(calls[1:]) == list(enumerate(results))
    calls = []
    address = f"tcp://127.0.0.1:{_free_port()}"
    with pytest.raises(ExecutionError, match=rf"^cannot reach the dask scheduler at "
                                             rf"{re.escape(address)} within 1 s \(\w+\)$"):
        run_tasks(pow, tasks, Execution(workers=None, scheduler=address, connect_timeout=1.0),
                  prepare=lambda: calls.append("prepare"))
    assert calls == []
