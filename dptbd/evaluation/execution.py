"""The execution layer of the Monte Carlo jobs (``dptbd compare``, ``dptbd detectors``) on
``dask.distributed``.

A job splits its trials into tasks (pure functions of their arguments: every trial's seed
depends only on the base seed, the configuration, the SNR and the trial index, never on the
worker that runs it) and calls :func:`map_tasks`, which returns the results **in task
order** whatever order they finished in, so the job reduces them exactly as a serial loop
would and the output is bit-identical for any number of workers or any cluster.

Where the tasks run (:class:`Execution`):

* ``workers=1`` and no scheduler: in this process, one task after the other;
* ``workers=N > 1``: a ``LocalCluster`` of N worker processes with one thread each (the
  numba kernels release the GIL but run single-threaded, so processes give the parallelism);
* ``scheduler="tcp://HOST:PORT"`` (or the environment variable :data:`SCHEDULER_ENV`): an
  existing cluster started with ``dask scheduler`` / ``dask worker`` (``docs/distributed.md``).
  The connection times out after :data:`CONNECT_TIMEOUT` seconds with a clear error.

Every job builds its :class:`Execution` with :func:`job_execution`, which checks the worker
count (:func:`check_worker_count`, the one check of it). Before any task, every worker is
checked (:func:`check_workers`): ``dptbd`` and ``numba`` installed and importable, and the
same dptbd version as this process. A worker that dies mid-run loses
nothing: the scheduler reruns its tasks elsewhere (they are pure), and :func:`map_tasks`
keeps exactly one result per task.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib.metadata
import os
import pkgutil
import sys
import uuid
from typing import Any, Callable, Iterator, Sequence

from dptbd.errors import DptbdError, check_int

__all__ = ["ExecutionError", "Execution", "SCHEDULER_ENV", "CONNECT_TIMEOUT", "REQUIRED_PACKAGES",
           "MAX_WORKERS", "QUIET_LOCAL_CLUSTER", "check_worker_count", "default_workers",
           "job_execution", "local_cluster", "cluster_workers",
           "check_workers", "map_tasks", "run_tasks", "warmed", "version"]

#: Environment variable holding a scheduler address, used when ``--scheduler`` is not given.
SCHEDULER_ENV = "DPTBD_SCHEDULER"
#: Seconds to reach a scheduler (and to wait for the requested workers) before giving up.
CONNECT_TIMEOUT = 5.0
#: What a worker must be able to import to run a task.
REQUIRED_PACKAGES = ("dptbd", "numba")
#: Most workers a job may ask for: local worker processes, or the workers a cluster must have.
MAX_WORKERS = 1024
#: Environment of LocalCluster workers: one thread per process for every numeric library.
#: Dask settings of a LocalCluster (its nannies pass them on to the workers). Dask's defaults
#: keep every server's event loop busy with periodic checks: the loop-health tick every
#: 20 ms in the scheduler, each nanny and each worker, the memory monitor every 100 ms, the
#: system monitor every 500 ms, the cluster's repr every 500 ms, and the workers' statistical
#: profiler (a stack sample every 10 ms, only for the dashboard's profile page). These
#: settings slow them to what a batch of Monte Carlo tasks needs; the CPU an idle cluster uses
#: with either is measured by ``benchmarks/bench_dask.py`` ("idle cluster CPU",
#: ``docs/throughput.md``, "The Monte Carlo on Dask"). The memory monitor still enforces the
#: workers' memory limits, once a second.
QUIET_LOCAL_CLUSTER = {
    "distributed.admin.tick.interval": "1s",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.deploy.cluster-repr-interval": "10s",
    "distributed.worker.profile.enabled": False,
}
_WORKER_ENV = {v: "1" for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                                "NUMBA_NUM_THREADS")}


class ExecutionError(DptbdError):
    """The cluster cannot run the job (unreachable, too few workers, unfit workers) or a bad
    worker count: a refusal of the job's input, so ``dptbd`` reports it with exit 2."""


def version(package: str = "dptbd") -> str:
    """The installed version of ``package`` (its distribution metadata)."""
    return importlib.metadata.version(package)


def check_worker_count(value: Any, name: str = "workers") -> int:
    """The one check of a job's worker count: an integer in ``[1, MAX_WORKERS]``.

    ``name`` is the job's parameter (``workers``, ``jobs``). Raises :class:`ExecutionError`
    ``"{name} must be an integer in [1, 1024], got {value!r}"``."""
    return check_int(name, value, 1, MAX_WORKERS, error=ExecutionError)


def default_workers() -> int:
    """The machine's cores available to this process."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


@dataclasses.dataclass(frozen=True)
class Execution:
    """Where a job's tasks run.

    Attributes
    ----------
    workers : int
        Local worker processes (1: in this process); with a scheduler, the number of
        workers the cluster must have (None: whatever it has, at least one).
    scheduler : str or None
        ``tcp://HOST:PORT`` of an existing scheduler; None: :data:`SCHEDULER_ENV` if set, else
        a LocalCluster (or this process).
    dashboard : bool
        Print the dashboard's address on stderr when the cluster is up.
    connect_timeout : float
        Seconds to reach the scheduler and its workers.
    """

    workers: int | None = 1
    scheduler: str | None = None
    dashboard: bool = False
    connect_timeout: float = CONNECT_TIMEOUT

    def __post_init__(self) -> None:
        if self.workers is not None:
            check_worker_count(self.workers)
        if self.address is None and self.workers is None:
            raise ExecutionError("workers must be given without a scheduler")

    @property
    def address(self) -> str | None:
        """The scheduler address in use (argument, else :data:`SCHEDULER_ENV`), or None."""
        return self.scheduler or os.environ.get(SCHEDULER_ENV) or None

    @property
    def in_process(self) -> bool:
        return self.address is None and self.workers == 1

    @contextlib.contextmanager
    def client(self) -> Iterator[Any]:
        """A checked ``distributed.Client`` (None when the tasks run in this process)."""
        if self.in_process:
            if self.dashboard:
                print("dask dashboard: none, one worker runs the tasks in this process "
                      "without dask", file=sys.stderr)
            yield None
            return
        import distributed

        cluster = None
        address = self.address
        try:
            if address is None:
                cluster = local_cluster(self.workers, dashboard=self.dashboard)
                address = cluster
            try:
                client = distributed.Client(address, timeout=self.connect_timeout)
            except (OSError, TimeoutError) as exc:
                raise ExecutionError(
                    f"cannot reach the dask scheduler at {address} within "
                    f"{self.connect_timeout:g} s ({type(exc).__name__})") from None
            with client:
                if self.dashboard:
                    print(f"dask dashboard: {client.dashboard_link}", file=sys.stderr)
                self._wait_for_workers(client)
                check_workers(client)
                yield client
        finally:
            if cluster is not None:
                cluster.close()

    def _wait_for_workers(self, client) -> None:
        need = 1 if self.workers is None else self.workers
        try:
            client.wait_for_workers(need, timeout=self.connect_timeout)
        except (TimeoutError, OSError):
            have = len(cluster_workers(client))
            raise ExecutionError(
                f"the dask cluster at {client.scheduler.address} has {have} worker(s), "
                f"{need} asked for") from None


def local_cluster(workers: int, *, dashboard: bool = False):
    """A started ``distributed.LocalCluster`` of ``workers`` processes, one thread each, with
    Dask's periodic housekeeping slowed to what a batch of Monte Carlo tasks needs
    (:data:`QUIET_LOCAL_CLUSTER`; with a dashboard, only the profiler's and the system
    monitor's defaults come back, as they feed its pages).

    Without a dashboard the scheduler's HTTP server (health, metrics) still starts, on an
    ephemeral port: dask's 8787 may be taken by another run."""
    import dask
    import distributed

    config = dict(QUIET_LOCAL_CLUSTER)
    if dashboard:
        for key in ("distributed.worker.profile.enabled",
                    "distributed.admin.system-monitor.interval"):
            del config[key]
    with dask.config.set(config):
        return distributed.LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True,
            dashboard_address="127.0.0.1:0" if dashboard else None,
            scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
            env=dict(_WORKER_ENV), silence_logs=40)


def cluster_workers(client) -> dict:
    """``{address: info}`` of every worker of ``client``'s cluster, asked of the scheduler now.

    Not ``client.scheduler_info(n_workers=-1)``: it returns the client's cached copy, which
    the client's periodic refresh of the cluster's totals (no workers listed) can replace
    between the fetch and the return (a ``compare`` on a loaded machine counted 0 workers)."""
    return client.sync(client.scheduler.identity, n_workers=-1)["workers"]


def job_execution(workers: int | None, *, scheduler: str | None = None,
                  dashboard: bool = False, tasks: int | None = None,
                  name: str = "workers") -> Execution:
    """The :class:`Execution` of a job's ``workers`` argument (named ``name`` in messages).

    ``workers`` is checked by :func:`check_worker_count`. Without a scheduler (argument or
    :data:`SCHEDULER_ENV`), None means :func:`default_workers`, and no more local processes
    are started than the job has ``tasks``; with one, ``workers`` is the number the cluster
    must have (None: any).
    """
    if workers is not None:
        workers = check_worker_count(workers, name)
    execution = Execution(workers=workers if workers is not None else 1, scheduler=scheduler,
                          dashboard=dashboard)
    if execution.address is not None:
        return dataclasses.replace(execution, workers=workers)
    local = default_workers() if workers is None else workers
    if tasks is not None:
        local = max(1, min(local, tasks))
    return dataclasses.replace(execution, workers=local)


def _problem(worker: str, package: str, found, imported, expected: str) -> str | None:
    """What is wrong with ``package`` on ``worker`` (None: nothing), from its metadata
    version ``found`` and the result of importing it, ``imported``."""
    if isinstance(found, BaseException):
        return f"worker {worker} lacks the Python package {package!r}"
    if isinstance(imported, BaseException):
        why = (str(imported).strip().splitlines() or [""])[0][:200]
        return (f"worker {worker} cannot import the Python package {package!r} "
                f"({type(imported).__name__}: {why})")
    if package == "dptbd" and found != expected:
        return f"worker {worker} has dptbd {found}, this process {expected}"
    return None


def check_workers(client, expected: str | None = None,
                  packages: Sequence[str] = REQUIRED_PACKAGES) -> None:
    """Refuse (:class:`ExecutionError`) workers that lack one of ``packages``, cannot import
    it, or whose dptbd version differs from ``expected`` (default: this process's).

    The probes are standard-library functions, which every worker can unpickle:
    :func:`importlib.metadata.version` (installed?) and :func:`pkgutil.resolve_name` of
    ``"{package}:__name__"`` (importable?), so an unfit worker gives this message and not
    an unpickling traceback."""
    expected = version() if expected is None else expected
    problems = []
    for package in packages:
        found = client.run(importlib.metadata.version, package, on_error="return")
        imported = client.run(pkgutil.resolve_name, f"{package}:__name__", on_error="return")
        for worker in sorted(found):
            problem = _problem(worker, package, found[worker], imported.get(worker), expected)
            if problem is not None:
                problems.append(problem)
    if problems:
        raise ExecutionError("unfit dask workers (every worker needs the same dptbd, see "
                             "docs/distributed.md): " + "; ".join(problems))


@contextlib.contextmanager
def warmed(client, warm: Callable[[], None] | None) -> Iterator[None]:
    """Run ``warm()`` once on every worker of ``client`` (and on any worker that joins, e.g.
    one restarted after a crash) before its tasks: a worker plugin, removed on exit. With
    no client (in this process) or no ``warm``, nothing."""
    if client is None or warm is None:
        yield
        return
    from dptbd.evaluation.worker_warmup import WarmUp

    name = f"dptbd-warm-{uuid.uuid4().hex[:12]}"
    client.register_plugin(WarmUp(warm), name=name)
    try:
        yield
    finally:
        with contextlib.suppress(Exception):
            client.unregister_worker_plugin(name)


def map_tasks(fn: Callable, tasks: Sequence[tuple], client=None, *,
              sizes: Sequence[int] | None = None, bar=None,
              done: Callable[[int], None] | None = None,
              on_result: Callable[[int, Any], None] | None = None) -> list:
    """``[fn(*t) for t in tasks]``, on ``client``'s workers when given, in task order.

    ``sizes``: units (trials, tasks) of each task for the progress ``bar`` (a tqdm, updated
    as tasks finish; default 1 each). ``done(i)`` is called after task ``i`` completes,
    ``on_result(i, result)`` with its result (both in the order the tasks finish).
    A task rerun by the scheduler (its worker died) still gives one result: the one of its
    key.
    """
    sizes = [1] * len(tasks) if sizes is None else list(sizes)
    results: list = [None] * len(tasks)
    if client is None:
        for i, t in enumerate(tasks):
            results[i] = fn(*t)
            if on_result is not None:
                on_result(i, results[i])
            if bar is not None:
                bar.update(sizes[i])
            if done is not None:
                done(i)
        return results
    import distributed

    run = uuid.uuid4().hex[:12]
    name = getattr(fn, "__name__", "task").strip("_")
    futures = [client.submit(fn, *t, key=f"dptbd-{name}-{i}-{run}", pure=False)
               for i, t in enumerate(tasks)]
    index = {f.key: i for i, f in enumerate(futures)}
    try:
        for future in distributed.as_completed(futures):
            i = index[future.key]
            results[i] = future.result()
            if on_result is not None:
                on_result(i, results[i])
            if bar is not None:
                bar.update(sizes[i])
            if done is not None:
                done(i)
    finally:
        client.cancel(futures)
    return results


def run_tasks(fn: Callable, tasks: Sequence[tuple], execution: Execution, *,
              prepare: Callable[[], None] | None = None,
              on_result: Callable[[int, Any], None] | None = None,
              warm: Callable[[], None] | None = None) -> tuple[list, int]:
    """``([fn(*t) for t in tasks], workers)``: a whole job on ``execution`` in one call.

    The client is opened first (an unreachable scheduler, too few or unfit workers are
    refused before anything else), then ``prepare()`` runs in this process (e.g. builds
    the tasks' executables), then :func:`map_tasks` with ``on_result`` and, on every
    worker, ``warm`` (:func:`warmed`). ``workers``: how many ran the tasks (1 in this
    process, the local processes, or the cluster's workers at the start)."""
    with execution.client() as client, warmed(client, warm):
        if prepare is not None:
            prepare()
        if client is None:
            used = 1
        elif execution.address is None:
            used = int(execution.workers)
        else:
            used = len(cluster_workers(client))
        return map_tasks(fn, tasks, client, on_result=on_result), used
