"""The P-pixel pipeline (``hw/dp_wide.py``) against the golden model, bit for bit.

Whole small scenes stream through ``DPPipelineWide`` (and ``DPCoreWide`` with a memory
model) in the Amaranth simulator with random input gaps and output back-pressure; every
state of every pixel is compared with ``dptbd.model.fixed``, as the P = 1 pipeline's in
``test_dp_pipeline.py``.
"""

import itertools
import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.errors import ConfigError
from dptbd.hw.dp_core import CORE_OPTIONS
from dptbd.hw.dp_pipeline import DPPipeline
from dptbd.hw.dp_wide import (DPCoreWide, DPPipelineWide, WideWindow, check_wide, dp_pipeline,
                              lane_column, pack_beat, unpack_beat_states, wide_pixel_layout,
                              wide_state_layout)
from dptbd.hw.layouts import pack
from helpers.hw_harness import (assert_states_equal, event_counter, lut_writes_for,
                                reference_states, refused, simulate)
from helpers.refusals import whole
from helpers.wide_harness import frames_to_beats, run_beats


def make_config(**kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def random_frames(cfg, n_frames, seed):
    rng = np.random.default_rng(seed)
    return rng.integers(0, cfg.pixel_max + 1, size=(n_frames, cfg.height, cfg.width))


SCENES = {
    "p2-8x5-r1-k3": (dict(width=8, height=5, segment_frames=3, pixels_per_clock=2), 7),
    "p4-12x8-r1-k2": (dict(width=12, height=8, segment_frames=2, pixels_per_clock=4), 5),
    "p2-10x7-r2-k3-half_up": (dict(width=10, height=7, segment_frames=3, radius=2,
                                   rounding="half_up", pixels_per_clock=2), 6),
    "p4-16x6-r2-k2-f3": (dict(width=16, height=6, segment_frames=2, radius=2,
                              weight_frac_bits=3, pixels_per_clock=4), 5),
    "p4-12x6-r1-k4-b4-e6": (dict(width=12, height=6, segment_frames=4, input_bits=4,
                                 energy_bits=6, pixels_per_clock=4), 9),
}


@pytest.mark.parametrize("name", SCENES)
def test_scene_matches_golden_model(name):
    kw, n_frames = SCENES[name]
    cfg = make_config(**kw)
    frames = random_frames(cfg, n_frames, seed=len(name))
    run = run_beats(DPPipelineWide(cfg), cfg, frames_to_beats(cfg, frames),
                    valid_probability=0.7, ready_probability=0.6, seed=5)
    assert_states_equal(run.outputs, reference_states(cfg, frames))
