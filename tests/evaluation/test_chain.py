"""``dptbd.evaluation.chain``: the FPGA -> DSP chain behind ``dptbd run``, on a small scene.

The main job's whole-run figures are tested through the command (``tests/commands/test_run.py``);
here the chain itself: the association implementation it runs, and its refusals.
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
