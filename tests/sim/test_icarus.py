"""The cocotb + Icarus build and run (dptbd.sim.icarus) without a simulator: scene checks, refusals before anything runs."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.sim.icarus import SimBuild, check_scene, simulate

#: 8 x 6, K = 3.
CFG = DPConfig(width=8, height=6, segment_frames=3)


def test_check_scene_takes_integer_frames_in_range():
    cfg = CFG.replace(input_bits=6)
    good = np.zeros((2, 6, 8), dtype=np.int64)
    good[1, 2, 3] = 63
    checked = check_scene(cfg, good)
    assert checked.dtype == np.uint16 and np.array_equal(checked, good)


def _outside(frames):
    frames = frames.copy()
    frames[1, 2, 3] = 64
    return frames


@pytest.mark.parametrize("change, message", [
    (lambda f: np.zeros((2, 6, 9), dtype=np.int64),
     r"scene frames are 9x6 \(W x H\) but the configuration is width=8 x height=6"),
    (_outside, r"scene pixels must fit input_bits=6 \(0 … 63\); found 1 outside, e.g. \[64\]"),
    (lambda f: f.astype(float), r"scene pixels must be integers, got dtype float64"),
    (lambda f: f[0], r"scene must have shape \(frames, height, width\), got shape \(6, 8\)"),
])
def test_check_scene_refuses_bad_scenes(change, message):
    good = np.zeros((2, 6, 8), dtype=np.int64)
    with pytest.raises(ValueError, match=f"^{message}$"):
        check_scene(CFG.replace(input_bits=6), change(good))


@pytest.mark.parametrize("codes, message", [
    (np.ones((9, 9), dtype=int),                               # (M+1) x M for r = 1
     r"LUT codes must have shape \(10, 9\) for radius=1, got \(9, 9\)"),
    (np.full((10, 9), 257),                                    # codes above unity
     r"LUT codes must be in \[0, 2\*\*F = 256\], found \[257, 257, 257\]"),
])
def test_simulate_refuses_a_bad_lut_before_anything_runs(tmp_path, codes, message):
    """The Python API checks a run-time LUT before writing the job or starting Icarus."""
    sim = SimBuild(cfg=CFG, directory=tmp_path / "build", verilog=tmp_path / "none.v",
                   manifest={"latency": 14}, waves=False, seconds=0.0)
    frames = np.random.default_rng(0).integers(0, 256, size=(7, 6, 8))
    with pytest.raises(ValueError, match=f"^{message}$"):
        simulate(sim, frames, lut_codes=codes)
    assert not (tmp_path / "build").exists(), "nothing may be written for a refused LUT"
