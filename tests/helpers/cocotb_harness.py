"""Shared pieces of the cocotb + Icarus tests: configurations without the saturation
warning, cached builds per design, pause specs, and the pass assertion with the log tail."""

from __future__ import annotations

import pathlib
import warnings

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.sim.icarus import build

BUILD_ROOT = pathlib.Path(__file__).resolve().parents[2] / "build" / "sim"
CYCLE = {"kind": "pattern", "pattern": [1, 1, 1, 0]}          # verilog-axis's cycle_pause

_BUILDS: dict = {}


def random_pause(probability: float, seed: int) -> dict:
    """A :func:`dptbd.sim.benches.drivers.pause_generator` spec pausing with ``probability``."""
    return {"kind": "random", "probability": probability, "seed": seed}


def make_config(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def built(cfg: DPConfig, design: str):
    """:func:`dptbd.sim.icarus.build` of ``design`` for ``cfg``, once per test session."""
    if (cfg, design) not in _BUILDS:
        _BUILDS[cfg, design] = build(cfg, BUILD_ROOT, design=design)
    return _BUILDS[cfg, design]


def assert_passed(result) -> None:
    assert result.passed, f"{result.report}\n--- {result.log} (tail) ---\n{result.log_tail()}"
