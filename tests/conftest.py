"""Fixtures shared by the tests."""

import shutil

import pytest


@pytest.fixture
def no_verilator(monkeypatch):
    """``shutil.which`` finds no ``verilator``; ``check_tools``' cache cleared around it."""
    from dptbd.sim import verilator

    real = shutil.which
    monkeypatch.setattr(shutil, "which",
                        lambda name, *a, **k: None if name == "verilator" else real(name, *a, **k))
    verilator.check_tools.cache_clear()
    yield
    verilator.check_tools.cache_clear()
