"""The Icarus/cocotb runner without a simulator: build naming, scene checks, refusals before
anything runs."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning, plain_weights
from dptbd.sim.runner import check_scene, config_name


def small(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**{"width": 8, "height": 6, "segment_frames": 3, **kw})


def frames_for(cfg, n=7, seed=0):
    return np.random.default_rng(seed).integers(0, cfg.pixel_max + 1,
                                                size=(n, cfg.height, cfg.width))


def test_build_directory_names_separate_parameter_sets():
    base = DPConfig(width=13, height=7)
    names = {config_name(c) for c in [
        base, base.replace(rounding="half_up"), DPConfig(width=13, height=7, radius=2),
        base.replace(weights=plain_weights(1)), base.replace(segment_frames=5)]}
    assert len(names) == 5
    assert config_name(base).startswith("13x7-k4-in8-e16-f8-r1-truncate-")
    assert config_name(base) == config_name(DPConfig(width=13, height=7))


def test_check_scene_refuses_bad_scenes():
    cfg = small(input_bits=6)
    good = np.zeros((2, 6, 8), dtype=np.int64)
    assert check_scene(cfg, good).dtype == np.uint16
    with pytest.raises(ValueError, match="8x6 .*width=8 x height=6|9x6"):
        check_scene(cfg, np.zeros((2, 6, 9), dtype=np.int64))
    with pytest.raises(ValueError, match=r"input_bits=6 \(0 … 63\); found 1 outside, e.g. \[64\]"):
        bad = good.copy()
        bad[1, 2, 3] = 64
        check_scene(cfg, bad)
    with pytest.raises(ValueError, match="integers"):
        check_scene(cfg, good.astype(float))
    with pytest.raises(ValueError, match="shape"):
        check_scene(cfg, good[0])


@pytest.mark.parametrize("codes, match", [
    (np.ones((9, 9), dtype=int), r"shape \(10, 9\)"),          # (M+1) x M for r = 1
    (np.full((10, 9), 257), r"\[0, 2\*\*F = 256\]"),           # codes above unity
])
def test_simulate_refuses_a_bad_lut_before_anything_runs(tmp_path, codes, match):
    """The Python API checks a run-time LUT before writing the job or starting Icarus."""
    from dptbd.sim.runner import SimBuild, simulate

    cfg = small()
    sim = SimBuild(cfg=cfg, directory=tmp_path / "build", verilog=tmp_path / "none.v",
                   manifest={"latency": 14}, waves=False, seconds=0.0)
    with pytest.raises(ValueError, match=match):
        simulate(sim, frames_for(cfg), lut_codes=codes)
    assert not (tmp_path / "build").exists(), "nothing may be written for a refused LUT"
