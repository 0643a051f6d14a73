"""The dask worker plugin (:mod:`dptbd.evaluation.worker_warmup`)."""

from __future__ import annotations

import sys

import pytest

from dptbd.evaluation.worker_warmup import WarmUp, keep_large_allocations


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's mallopt")
def test_the_allocator_keeps_large_allocations_on_linux():
    assert keep_large_allocations() is True


def test_the_plugin_runs_the_warm_up_once_per_setup():
    calls = []
    plugin = WarmUp(lambda: calls.append(1))
    plugin.setup(worker=None)
    assert calls == [1]
