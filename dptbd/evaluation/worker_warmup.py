"""A ``dask.distributed`` worker plugin that runs a warm-up once per worker
(:func:`dptbd.evaluation.execution.map_tasks`): the numba kernels are loaded from their
on-disk cache (``cache=True``) before the worker's first task, and never per task."""

from __future__ import annotations

from typing import Callable

from distributed.diagnostics.plugin import WorkerPlugin

__all__ = ["WarmUp"]


class WarmUp(WorkerPlugin):
    """Call ``warm()`` on every worker when the plugin is registered or the worker joins."""

    def __init__(self, warm: Callable[[], None]) -> None:
        self.warm = warm

    def setup(self, worker) -> None:
        self.warm()
