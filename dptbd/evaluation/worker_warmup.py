"""A ``dask.distributed`` worker plugin that prepares each worker once
(:func:`dptbd.evaluation.execution.warmed`): glibc's allocator told to keep the Monte Carlo's
large arrays (:func:`keep_large_allocations`), then the job's warm-up, which loads the numba
kernels from their on-disk cache (``cache=True``) before the worker's first task, never per
task."""

from __future__ import annotations

import ctypes
import ctypes.util
from typing import Callable

from distributed.diagnostics.plugin import WorkerPlugin

__all__ = ["WarmUp", "keep_large_allocations"]

_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3


def keep_large_allocations(mmap_bytes: int = 64 << 20, trim_bytes: int = 128 << 20) -> bool:
    """Raise glibc's mmap and trim thresholds in this process; False where there is no glibc.

    A dask nanny starts its worker with ``MALLOC_TRIM_THRESHOLD_=65536``, which also freezes
    the mmap threshold at 128 KiB: every frame batch of a task (megabytes) is then mapped and
    unmapped again, page faults each time, and a ``dptbd compare`` task runs slower than in a
    plain process (measured: ``docs/throughput.md``, "The Monte Carlo on Dask"). With these
    thresholds the batches are reused from the heap. Memory held: at most ``trim_bytes`` of
    free heap per worker."""
    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name)
        mallopt = libc.mallopt
    except (OSError, AttributeError, TypeError):  # pragma: no cover - not glibc
        return False
    return bool(mallopt(_M_MMAP_THRESHOLD, mmap_bytes)) and bool(mallopt(_M_TRIM_THRESHOLD, trim_bytes))


class WarmUp(WorkerPlugin):
    """On every worker when the plugin is registered or the worker joins:
    :func:`keep_large_allocations`, then ``warm()``."""

    def __init__(self, warm: Callable[[], None]) -> None:
        self.warm = warm

    def setup(self, worker) -> None:
        keep_large_allocations()
        self.warm()
