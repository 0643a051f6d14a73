"""Bad input to :mod:`dptbd.sim.rtl.check` refused before anything runs: frame size, pixel
width, float and flat scenes, a bad stimulus, a stray LUT write (a write beyond the table
is ignored by the gateware)."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from dptbd.sim import verilator as V
from dptbd.sim.rtl.check import Stimulus, check_frames, check_stream
from dptbd.sim.scenarios import make_frames
from dptbd.sim.stimulus import pixel_words

from helpers.verilator_harness import SEG, built, make_config
from helpers.refusals import whole

pytestmark = pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")

BASE = make_config(**SEG)


def fake_build(tmp_path, cfg=BASE, design="dp"):
    return V.VerilatorBuild(cfg, design, tmp_path, tmp_path / "missing-executable",
                            {"latency": 14}, "0" * 64, 0.0, True, False)


def test_check_frames_refuses_a_wrong_frame_size(tmp_path):
    frames = np.zeros((2, 7, 13), dtype=np.uint8)
    with pytest.raises(ValueError, match=r"^scene frames are 13x7 \(W x H\) but the "
                                         r"configuration is width=16 x height=12$"):
        check_frames(fake_build(tmp_path), frames)


def test_check_frames_refuses_pixels_wider_than_b_in(tmp_path):
    frames = np.zeros((2, 12, 16), dtype=np.int64)
    frames[1, 3, 4] = 256
    frames[0, 0, 0] = -1
    with pytest.raises(ValueError, match=whole(
            "scene pixels must fit input_bits=8 (0 … 255); found 2 outside, e.g. [-1, 256]")):
        check_frames(fake_build(tmp_path), frames)


def test_check_frames_refuses_float_and_flat_scenes(tmp_path):
    with pytest.raises(ValueError, match=r"^scene pixels must be integers, got dtype float64$"):
        check_frames(fake_build(tmp_path), np.zeros((1, 12, 16)))
    with pytest.raises(ValueError, match=r"^scene must have shape \(frames, height, width\), "
                                         r"got shape \(192,\)$"):
        check_frames(fake_build(tmp_path), np.zeros(192, dtype=np.uint8))


def test_check_stream_refuses_bad_stimulus_before_running(tmp_path):
    sim = fake_build(tmp_path)
    words = np.zeros(10, dtype=np.uint64)
    with pytest.raises(ValueError, match=r"^store_init must be 'zero' or 'random', "
                                         r"got 'garbage'$"):
        check_stream(sim, words, Stimulus(store_init="garbage"))
    with pytest.raises(ValueError, match=r"^reset at cycle 1 for 2 cycles is outside the run: "
                                         r"cycles 2 … \d+, hold >= 1$"):
        check_stream(sim, words, Stimulus(resets=((1, 2),)))
    with pytest.raises(ValueError, match=r"^trace needs a build made with waves=True$"):
        check_stream(sim, words, trace=tmp_path / "t.fst")


@pytest.mark.parametrize("address", [89, 128])
def test_check_stream_refuses_a_stray_lut_write_inside_or_beyond_the_port(tmp_path, address):
    words = pixel_words(BASE, np.zeros((1, 12, 16), dtype=np.uint8))
    with pytest.raises(ValueError, match=whole(
            f"a stray LUT write goes beyond the table: address 90 … 127, got {address}")):
        check_stream(fake_build(tmp_path), words, Stimulus(stray_lut_writes=((0, address, 1),)))


def test_a_lut_write_beyond_the_table_is_ignored():
    frames = make_frames("two-targets", BASE, 4, seed=2)
    words = pixel_words(BASE, frames)
    stray = ((0, 90, 0), (len(words) // 2, 127, 0))
    result = check_stream(built(BASE, "dp"), words, Stimulus(stray_lut_writes=stray))
    assert result.passed, result.report
    assert result.raw.counters["lut_writes"] == 2
