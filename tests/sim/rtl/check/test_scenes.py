"""Compiled RTL runs scored against the golden model (:mod:`dptbd.sim.rtl.check`): whole
scenes bit for bit over parameter sets × input gaps × back-pressure."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from dptbd.sim.rtl.check import Stimulus, check_frames
from dptbd.sim.scenarios import make_frames
from dptbd.sim.scoreboard import expected_words
from dptbd.sim.candidate_scoreboard import expected_lists

from helpers.verilator_harness import SEG, assert_passed, built, make_config

pytestmark = pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")

BASE = make_config(**SEG)


def cases():
    """(id, config overrides, design, store_init, scenario, frames)."""
    return [
        ("dp", SEG, "dp", "zero", "two-targets", 7),
        ("core-zero", SEG, "core", "zero", "mixed", 5),        # SEG: BASE's core build
        ("core-random", SEG, "core", "random", "mixed", 5),
        ("segmenter", SEG, "segmenter", "zero", "two-targets", 9),
        ("dp-r2", {"radius": 2, "segment_frames": 2}, "dp", "zero", "edges", 5),
        ("dp-f0", {"weight_frac_bits": 0}, "dp", "zero", "noise", 5),
        ("dp-saturating", {"energy_bits": 9}, "dp", "zero", "saturating", 7),
        ("core-saturating", {"energy_bits": 9}, "core", "random", "saturating", 7),
        ("dp-13x7", {"width": 13, "height": 7}, "dp", "zero", "edges", 7),
        ("segmenter-13x7", {"width": 13, "height": 7, **SEG, "histogram_bits": 5,
                            "histogram_shift": 2},
         "segmenter", "zero", "two-targets", 9),
        ("dp-half-up-f3", {"rounding": "half_up", "weight_frac_bits": 3}, "dp", "zero",
         "ties", 5),
    ]


PAUSES = [(0.0, 0.0), (0.3, 0.0), (0.0, 0.6), (0.5, 0.5)]


@pytest.mark.parametrize("valid_gap,ready_pause", PAUSES, ids=lambda p: f"{p}")
@pytest.mark.parametrize("name,kw,design,store_init,scenario,n_frames", cases(),
                         ids=[c[0] for c in cases()])
def test_whole_scene_bit_exact(name, kw, design, store_init, scenario, n_frames, valid_gap,
                               ready_pause):
    cfg = make_config(**kw)
    sim = built(cfg, design)
    frames = make_frames(scenario, cfg, n_frames, seed=len(name))
    stimulus = Stimulus(valid_gap=valid_gap, ready_pause=ready_pause,
                        seed=int(valid_gap * 10 + ready_pause * 100), store_init=store_init)
    result = check_frames(sim, frames, stimulus)
    assert_passed(result)
    assert result.words_in == frames.size and result.epochs == 1
    assert result.raw.status == "done"
    if design == "segmenter":
        lists = expected_lists(cfg, frames)
        assert result.words_out == sum(lst.count + 1 for lst in lists)
        assert result.report == (f"bit-exact: {len(lists)} lists, "
                                 f"{sum(lst.count for lst in lists)} records, "
                                 f"{result.words_out} words")
    else:
        assert result.words_out == frames.size
        assert result.report == f"bit-exact: {frames.size} words ({n_frames} frames)"
        np.testing.assert_array_equal(result.raw.out_words, expected_words(cfg, frames).ravel())
    size = frames.size if design != "segmenter" else frames.size + 1
    if valid_gap == ready_pause == 0.0:
        assert result.cycles == size + sim.latency
    elif design == "segmenter":       # sparse candidates: back-pressure may cost nothing
        assert result.cycles >= size + sim.latency
    else:
        assert result.cycles > size + sim.latency


def test_segmenter_scenes_have_records():
    """The segmenter cases above are not vacuous: their lists carry records."""
    for name, kw, design, _, scenario, n_frames in cases():
        if design == "segmenter":
            cfg = make_config(**kw)
            lists = expected_lists(cfg, make_frames(scenario, cfg, n_frames, seed=len(name)))
            assert sum(lst.count for lst in lists) >= 5, name
