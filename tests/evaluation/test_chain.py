"""``dptbd.evaluation.chain``: the FPGA -> DSP chain behind ``dptbd run``, on a small scene.

The main job's whole-run figures are tested through the command (``tests/commands/run/``);
here the chain itself: the association implementation it runs, the segmenter settings it
takes from the data, and its refusals.
"""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.dsp.association import AssociationConfig
from dptbd.evaluation.chain import run_pipeline, segmenter_settings
from dptbd.scenes import synthetic


@pytest.fixture(scope="module")
def scene():
    targets = [synthetic.Target(start=(10.0, 12.0), velocity=(0.5, 0.4), amplitude=4 * 1.732)]
    s = synthetic.make_scene((32, 40), 30, targets, mu=30.0, sigma=1.732, seed=3)
    frames = synthetic.quantise(s.frames, 12, gain=16.0)
    cfg = DPConfig(width=40, height=32, segment_frames=5, input_bits=12, energy_bits=16)
    assoc = AssociationConfig()
    cfg = segmenter_settings(cfg, frames, 6, assoc)
    return frames, cfg, assoc


@pytest.mark.parametrize("lists", ["gateware", "ideal"])
def test_c_firmware_and_python_model_give_the_same_chain(scene, lists):
    frames, cfg, assoc = scene
    py = run_pipeline(frames, cfg, 6, assoc, lists=lists)
    c = run_pipeline(frames, cfg, 6, assoc, lists=lists, dsp="c")
    assert (py.dsp, c.dsp) == ("python", "c")
    assert py.stats == c.stats
    assert len(py.tracks) == len(c.tracks) > 0
    for a, b in zip(py.tracks, c.tracks, strict=True):
        assert a.id == b.id and np.array_equal(a.points, b.points)
    for a, b in zip(py.candidates, c.candidates, strict=True):
        assert np.array_equal(a, b)


def test_an_unknown_dsp_is_refused(scene):
    frames, cfg, assoc = scene
    with pytest.raises(ValueError, match=r"^dsp must be one of python, c, got 'asm'$"):
        run_pipeline(frames, cfg, 6, assoc, dsp="asm")


def test_segmenter_settings_come_from_the_data_unless_given():
    cfg = DPConfig(width=128, height=128, segment_frames=6, input_bits=12, energy_bits=16)
    frames = np.full((12, 128, 128), 600, np.uint16)
    frames[8, 5, 5] = 4000                    # after the first segment: not calibrated on
    got = segmenter_settings(cfg, frames, 33, AssociationConfig())
    # the first K = 6 frames: K * max = 3600 needs 12 bits: 2^10 bins reach it with s = 2
    # (DPConfig's configuration-only default: 15 - 10 = 5; the whole sequence: 6 * 4000
    # needs 15 bits, s = 5 too)
    assert cfg.bin_shift == 5 and got.bin_shift == 2
    assert segmenter_settings(cfg, frames, 33, AssociationConfig(),
                              calibration_frames=12).bin_shift == 5
    with pytest.raises(ValueError, match=r"^calibration_frames must be an integer in \[1, inf\), got 0$"):
        segmenter_settings(cfg, frames, 33, AssociationConfig(), calibration_frames=0)
    # the gateware selects 2n = 66 (headroom 2), the DSP trims to 33; C = min(2 * 66, 128)
    assert got.n_candidates == 66 and got.record_capacity == 128
    assert segmenter_settings(cfg, frames, 33, AssociationConfig(), 1.0).n_candidates == 33
    mine = DPConfig(width=128, height=128, segment_frames=6, input_bits=12, energy_bits=16,
                    histogram_shift=4, candidate_capacity=40)
    kept = segmenter_settings(mine, frames, 33, AssociationConfig())
    assert kept.bin_shift == 4 and kept.record_capacity == 40 and kept.n_candidates == 40
