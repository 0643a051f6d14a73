"""Dask clusters of separate processes for the tests of the execution layer: a ``dask
scheduler`` and ``dask worker`` processes on 127.0.0.1 (ephemeral ports, no dashboards), and
workers whose Python truly lacks a package (:func:`worker_lacking`)."""

from __future__ import annotations

import contextlib
import os
import pathlib
import re
import subprocess
import sys
import sysconfig
import time
from typing import Iterator, Mapping, Sequence

#: The ``dask`` command of this environment.
DASK = pathlib.Path(sys.executable).parent / "dask"
#: ``dask worker`` started by a Python that reads its packages from the site directory in
#: ``argv[1]`` only (``python -S``: not this environment's site-packages).
_WORKER_FROM_SITE = ("import site, sys; site.addsitedir(sys.argv.pop(1)); "
                     "from distributed.cli.dask_worker import main; "
                     "sys.argv[0] = 'dask-worker'; main()")


def _distribution(entry: str) -> str:
    """The package an entry of site-packages belongs to: ``numba``, ``numba-0.68.1.dist-info``
    and dptbd's editable-install files ``__editable__.dptbd-0.1.0.pth``,
    ``__editable___dptbd_0_1_0_finder.py`` give ``numba`` and ``dptbd``."""
    name = entry.removeprefix("__editable__").lstrip("_.")
    return re.split(r"[-_.]", name, maxsplit=1)[0].lower()


def worker_lacking(folder: pathlib.Path, packages: Sequence[str]) -> list[str]:
    """The command of a ``dask worker`` whose Python has every package of this environment
    except ``packages`` (neither importable nor in its distribution metadata): a site
    directory in ``folder`` of links to the other entries of site-packages."""
    site = pathlib.Path(sysconfig.get_paths()["purelib"])
    folder.mkdir(parents=True)
    for entry in site.iterdir():
        if _distribution(entry.name) not in packages:
            (folder / entry.name).symlink_to(entry)
    return [sys.executable, "-S", "-c", _WORKER_FROM_SITE, str(folder)]


@contextlib.contextmanager
def process_cluster(folder: pathlib.Path,
                    workers: Mapping[str, Sequence[str] | None] = {"w0": None, "w1": None},
                    timeout: float = 60.0) -> Iterator[tuple[str, dict[str, int]]]:
    """``(scheduler address, {worker name: pid})`` of a scheduler and the ``workers`` (name ->
    command that starts a ``dask worker``, None: this environment's), one thread each and no
    nanny (the pid is the worker's own process); everything killed on exit.

    The workers run in ``folder`` (so the repository's ``dptbd/`` is not importable from the
    current directory) without ``PYTHONPATH``."""
    import distributed

    file = folder / "scheduler.json"
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    quiet = dict(stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=folder, env=env)
    procs = [subprocess.Popen([str(DASK), "scheduler", "--host", "127.0.0.1", "--port", "0",
                               "--no-dashboard", "--scheduler-file", str(file)], **quiet)]
    pids = {}
    try:
        deadline = time.monotonic() + timeout
        while not file.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        for name, command in workers.items():
            command = [str(DASK), "worker"] if command is None else list(command)
            procs.append(subprocess.Popen(
                command + ["--scheduler-file", str(file), "--nthreads", "1", "--no-nanny",
                           "--no-dashboard", "--host", "127.0.0.1", "--name", name], **quiet))
            pids[name] = procs[-1].pid
        with distributed.Client(scheduler_file=str(file), timeout=timeout) as client:
            client.wait_for_workers(len(workers), timeout=timeout)
            address = client.scheduler.address
        yield address, pids
    finally:  # the workers hold nothing worth a graceful close (theirs takes seconds)
        for p in reversed(procs):
            if p.poll() is None:
                p.kill()
            p.wait(timeout=30)


def worker_addresses(address: str) -> dict[str, str]:
    """``{worker name: worker address}`` of the cluster at ``address``."""
    import distributed

    from dptbd.evaluation.execution import cluster_workers

    with distributed.Client(address, timeout=30) as client:
        info = cluster_workers(client)
    return {w["name"]: a for a, w in info.items()}
