"""The stream model (no simulator): the gateware's counter / resynchronisation rule on
hand-made ``first`` patterns, equality with :func:`expected_words` on clean scenes, partial
frames, and LUT changes spliced in between and inside frames."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.hw.layouts import unpack_state
from dptbd.model.fixed import dp_step
from dptbd.sim.scoreboard import expected_words, model_frames
from dptbd.sim.stimulus import pixel_words
from dptbd.sim.stream_model import FrameRun, expected_stream, frame_runs, split_words


def make_config(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**{"width": 5, "height": 4, "segment_frames": 3, **kw})


def frames_for(cfg, n, seed=0):
    return np.random.default_rng(seed).integers(0, cfg.pixel_max + 1,
                                                size=(n, cfg.height, cfg.width))


def flags(n, marks):
    first = np.zeros(n, dtype=bool)
    first[list(marks)] = True
    return first


CFG = make_config()            # W·H = 20, K = 3


# ---- frame_runs ------------------------------------------------------------------------

def test_clean_stream_is_whole_frames_counted_in_segments():
    first = flags(100, range(0, 100, 20))
    assert frame_runs(CFG, first) == [FrameRun(20 * t, 20 * t + 20, t % 3, True)
                                      for t in range(5)]


def test_missing_first_is_ignored():
    """No flags at all, or some missing: the counters alone frame the stream."""
    expected = [FrameRun(20 * t, 20 * t + 20, t % 3, True) for t in range(5)]
    assert frame_runs(CFG, flags(100, [])) == expected
    assert frame_runs(CFG, flags(100, [0, 60])) == expected
    assert frame_runs(CFG, flags(100, [40])) == expected


def test_first_mid_frame_restarts_with_frame_zero():
    # frames 0, 1 whole; frame 2 cut after 7 words by a `first`: restart, frame 0 again
    first = flags(87, [0, 20, 40, 47, 67])
    assert frame_runs(CFG, first) == [
        FrameRun(0, 20, 0, True), FrameRun(20, 40, 1, True), FrameRun(40, 47, 2, False),
        FrameRun(47, 67, 0, True), FrameRun(67, 87, 1, True)]


def test_first_on_the_second_word_of_the_stream():
    assert frame_runs(CFG, flags(21, [1])) == [FrameRun(0, 1, 0, False),
                                               FrameRun(1, 21, 0, True)]


def test_long_frame_wraps_into_the_next_frame():
    """25 words between two flags: 20 make a frame, the 5 left over are the next frame's
    start, cut short by the next flag (a restart)."""
    first = flags(65, [0, 25, 45])
    assert frame_runs(CFG, first) == [
        FrameRun(0, 20, 0, True), FrameRun(20, 25, 1, False), FrameRun(25, 45, 0, True),
        FrameRun(45, 65, 1, True)]


def test_short_frame_and_a_short_stream_end():
    first = flags(40, [0, 20, 33])
    assert frame_runs(CFG, first) == [FrameRun(0, 20, 0, True), FrameRun(20, 33, 1, False),
                                      FrameRun(33, 40, 0, False)]
    assert frame_runs(CFG, flags(0, [])) == []


# ---- expected_stream -------------------------------------------------------------------

@pytest.mark.parametrize("kw,n", [({}, 7), ({"radius": 2, "width": 11, "height": 9}, 5),
                                  ({"weight_frac_bits": 0}, 4),
                                  ({"energy_bits": 9, "rounding": "half_up"}, 6),
                                  ({"segment_frames": 1}, 3)])
def test_clean_scene_equals_expected_words(kw, n):
    cfg = make_config(**kw)
    frames = frames_for(cfg, n, seed=n)
    pixels, first = split_words(cfg, pixel_words(cfg, frames))
    np.testing.assert_array_equal(pixels, frames.ravel())
    exp = expected_stream(cfg, pixels, first)
    np.testing.assert_array_equal(exp.words, expected_words(cfg, frames).ravel())
    size = cfg.width * cfg.height
    p = np.arange(n * size)
    np.testing.assert_array_equal(exp.positions, np.stack(
        [p // size, p % size // cfg.width, p % cfg.width], axis=1))


def test_clean_scene_without_flags_equals_expected_words():
    frames = frames_for(CFG, 5, seed=3)
    pixels = frames.ravel()
    exp = expected_stream(CFG, pixels, np.zeros(pixels.size, dtype=bool))
    np.testing.assert_array_equal(exp.words, expected_words(CFG, frames).ravel())


def test_partial_frame_has_end_of_line_but_no_end_of_frame_or_segment():
    """Frames 0, 1 whole, frame 2 (the segment's last) cut after 13 words, then a new
    segment: the cut frame's words are the model's prefix with end_of_line only."""
    frames = frames_for(CFG, 6, seed=4)
    words = pixel_words(CFG, frames)
    stream = np.concatenate([words[:40 + 13], words[60:]])   # frames 3.. follow the cut
    pixels, first = split_words(CFG, stream)
    exp = expected_stream(CFG, pixels, first)
    assert [(r.frame, r.complete) for r in exp.runs] == [(0, True), (1, True), (2, False),
                                                          (0, True), (1, True), (2, True)]
    whole = expected_words(CFG, frames).ravel()
    cut = slice(40, 53)
    energy_dir = (1 << CFG.state_bits) - 1
    np.testing.assert_array_equal(exp.words[cut] & np.uint64(energy_dir),
                                  whole[cut] & np.uint64(energy_dir))
    np.testing.assert_array_equal(exp.fields[cut, 2], (np.arange(13) % 5) == 4)
    assert exp.fields[cut, 3].sum() == 0 and exp.fields[cut, 4].sum() == 0
    np.testing.assert_array_equal(exp.positions[cut], np.stack(
        [np.full(13, 2), np.arange(13) // 5, np.arange(13) % 5], axis=1))
    # after the cut: frames 3, 4, 5 as a new segment of their own
    np.testing.assert_array_equal(exp.words[:40], whole[:40])
    np.testing.assert_array_equal(exp.words[53:], expected_words(CFG, frames[3:]).ravel())
    assert exp.fields[:, 3].sum() == 5 and exp.fields[:, 4].sum() == 1
    assert unpack_state(CFG, int(exp.words[-1]))["end_of_segment"] == 1


def test_long_frame_extra_words_are_the_next_frame():
    """A frame of 25 words (no flag on the extra 5): the 5 extra are frame 1's first five
    pixels; the next flag restarts a segment."""
    frames = frames_for(CFG, 4, seed=5)
    words = pixel_words(CFG, frames)
    extra = frames[1].ravel()[:5].astype(np.uint64)            # pixels, no `first`
    stream = np.concatenate([words[:20], extra, words[20:]])
    pixels, first = split_words(CFG, stream)
    exp = expected_stream(CFG, pixels, first)
    assert [(r.start, r.stop, r.frame, r.complete) for r in exp.runs] == [
        (0, 20, 0, True), (20, 25, 1, False), (25, 45, 0, True), (45, 65, 1, True),
        (65, 85, 2, True)]
    whole = expected_words(CFG, frames).ravel()
    energy_dir = np.uint64((1 << CFG.state_bits) - 1)
    np.testing.assert_array_equal(exp.words[:20], whole[:20])
    np.testing.assert_array_equal(exp.words[20:25] & energy_dir, whole[20:25] & energy_dir)
    np.testing.assert_array_equal(exp.words[25:], expected_words(CFG, frames[1:]).ravel())


def test_refuses_mismatched_arrays():
    with pytest.raises(ValueError, match=r"^pixels and first must be 1-D of one length, "
                                         r"got \(3,\) and \(2,\)$"):
        expected_stream(CFG, np.zeros(3), np.zeros(2))


# ---- LUT changes -----------------------------------------------------------------------

def random_codes(cfg, seed):
    return np.random.default_rng(seed).integers(0, (1 << cfg.weight_frac_bits) + 1,
                                                size=(cfg.n_moves + 1, cfg.n_moves))


@pytest.mark.parametrize("kw", [{}, {"radius": 2, "width": 11, "height": 9},
                                {"weight_frac_bits": 2}])
def test_lut_change_at_a_segment_start_splices_whole_scenes(kw):
    cfg = make_config(**kw)
    size = cfg.width * cfg.height
    frames = frames_for(cfg, 8, seed=6)
    codes = random_codes(cfg, 7)
    new = cfg.with_weight_codes(codes)
    pixels, first = split_words(cfg, pixel_words(cfg, frames))
    exp = expected_stream(cfg, pixels, first, {3 * size: codes})
    np.testing.assert_array_equal(exp.words, np.concatenate([
        expected_words(cfg, frames[:3]).ravel(), expected_words(new, frames[3:]).ravel()]))
    # a change before word 0 is the LUT of the whole stream
    exp0 = expected_stream(cfg, pixels, first, {0: codes})
    np.testing.assert_array_equal(exp0.words, expected_words(new, frames).ravel())
    # negative indices (a change before the stream, as check_stream passes after a reset)
    np.testing.assert_array_equal(expected_stream(cfg, pixels, first, {-5: codes}).words,
                                  exp0.words)


def test_lut_change_mid_frame_applies_from_that_word():
    """A change before word 7 of frame 4 (inside a segment): frame 4's words 0 … 6 are the
    old LUT's, 7 … on use the new LUT on the old predecessor state; frame 5 continues from
    the spliced state; the next segment is the new LUT's alone."""
    cfg = CFG
    size = 20
    frames = frames_for(cfg, 9, seed=8)
    codes = random_codes(cfg, 9)
    new = cfg.with_weight_codes(codes)
    pixels, first = split_words(cfg, pixel_words(cfg, frames))
    at = 4 * size + 7
    exp = expected_stream(cfg, pixels, first, {at: codes})
    old_words = expected_words(cfg, frames).ravel()
    np.testing.assert_array_equal(exp.words[:at], old_words[:at])
    states = list(model_frames(cfg, frames))
    e_new, d_new = dp_step(*states[3], frames[4], new)
    e = exp.fields[4 * size:5 * size, 0]
    d = exp.fields[4 * size:5 * size, 1]
    np.testing.assert_array_equal(e[7:], e_new.ravel()[7:])
    np.testing.assert_array_equal(d[7:], d_new.ravel()[7:])
    assert not np.array_equal(e_new.ravel(), states[4][0].ravel())   # the change shows
    spliced_e = np.concatenate([states[4][0].ravel()[:7], e_new.ravel()[7:]]).reshape(4, 5)
    spliced_d = np.concatenate([states[4][1].ravel()[:7], d_new.ravel()[7:]]).reshape(4, 5)
    e5, d5 = dp_step(spliced_e, spliced_d, frames[5], new)
    np.testing.assert_array_equal(exp.fields[5 * size:6 * size, 0], e5.ravel())
    np.testing.assert_array_equal(exp.fields[5 * size:6 * size, 1], d5.ravel())
    np.testing.assert_array_equal(exp.words[6 * size:],
                                  expected_words(new, frames[6:]).ravel())


def test_two_lut_changes_in_one_frame():
    cfg = CFG
    frames = frames_for(cfg, 3, seed=10)
    a, b = random_codes(cfg, 11), random_codes(cfg, 12)
    pixels, first = split_words(cfg, pixel_words(cfg, frames))
    exp = expected_stream(cfg, pixels, first, {25: a, 31: b})
    states = list(model_frames(cfg, frames))
    e_a, _ = dp_step(*states[0], frames[1], cfg.with_weight_codes(a))
    e_b, _ = dp_step(*states[0], frames[1], cfg.with_weight_codes(b))
    e = exp.fields[20:40, 0]
    np.testing.assert_array_equal(e[:5], states[1][0].ravel()[:5])
    np.testing.assert_array_equal(e[5:11], e_a.ravel()[5:11])
    np.testing.assert_array_equal(e[11:], e_b.ravel()[11:])


# ---- run-time settings ------------------------------------------------------------------

def test_settings_are_sampled_at_segment_starts():
    """K written in the middle of a segment waits for the next segment start; the words of
    each segment carry its (K, n, s); saturated flags come from the accumulator's sums."""
    from dptbd.model.fixed import run_fixed, saturation_counts
    from dptbd.model.settings import SegmentSettings as S

    cfg = make_config(segment_frames=2, max_segment_frames=4, energy_bits=9,
                      candidate_count=2)
    size = cfg.width * cfg.height
    frames = frames_for(cfg, 9, seed=3)
    pixels, first = split_words(cfg, pixel_words(cfg, frames))
    # written before word 5 (frame 0): segment 0 is K = 2 already sampled -> from segment 1
    changes = {5: S(3, 1, 4), 2 * size + 7: S(1, 3, 2), 5 * size: S(4, 0, 1)}
    exp = expected_stream(cfg, pixels, first, settings_changes=changes)
    schedule = [S(2, 2, cfg.bin_shift), S(3, 1, 4), S(4, 0, 1)]
    segments = run_fixed(frames, cfg, schedule)
    ends = np.flatnonzero(exp.fields[:, 4])
    assert (ends + 1).tolist() == [2 * size, 5 * size, 9 * size]
    for j, end in enumerate(ends):
        np.testing.assert_array_equal(exp.fields[end + 1 - size:end + 1, 0],
                                      segments.energy[j].ravel())
    assert exp.settings[0].tolist() == [2, 2, cfg.bin_shift]
    assert exp.settings[3 * size].tolist() == [3, 1, 4]
    assert exp.settings[-1].tolist() == [4, 0, 1]
    assert exp.saturation_counts().tolist() == saturation_counts(frames, cfg, schedule).tolist()
    assert exp.saturated.sum() > 0
