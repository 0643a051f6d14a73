"""Run-time settings in the golden model (``dptbd.model.settings``): schedules of (K, n, s)
per segment for the DP (reference and fast kernel, bit for bit), the segmenter models and
the saturation counts; refusals with their whole messages."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.errors import ConfigError
from dptbd.model.fast import run_fixed_fast
from dptbd.model.fixed import (dp_step, dp_step_saturated, frame_segments, run_fixed,
                               saturation_counts, segment_start)
from dptbd.model.segmentation import segment_fixed, segment_sequence, segment_stream
from dptbd.model.settings import SegmentSettings as S, check_schedule, segment_lengths
from dptbd.model.segments import segment_spans
from helpers.refusals import whole


def config(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**{"width": 9, "height": 7, "segment_frames": 2,
                           "max_segment_frames": 5, "histogram_bits": 5, "candidate_count": 6,
                           **kw})


def frames_for(cfg, n, seed=0):
    return np.random.default_rng(seed).integers(0, cfg.pixel_max + 1,
                                                (n, cfg.height, cfg.width)).astype(np.uint16)


SCHEDULE = [S(3, 2, 0), S(1, 5, 3), S(5, 0, 2), S(2, 7, 4)]


def test_spans_follow_the_schedule_and_its_last_entry():
    cfg = config()
    assert segment_lengths(SCHEDULE, 16) == [3, 1, 5, 2, 2, 2]
    assert segment_spans(cfg, 16, SCHEDULE) == [(0, 3), (3, 1), (4, 5), (9, 2), (11, 2),
                                                (13, 2)]
    assert segment_spans(cfg, 7, None) == [(0, 2), (2, 2), (4, 2)]
    assert frame_segments(cfg, 6, SCHEDULE).tolist() == [[0, 0], [0, 1], [0, 2], [1, 0],
                                                         [2, 0], [2, 1]]


def test_run_fixed_with_a_schedule_is_per_segment_runs():
    cfg = config()
    frames = frames_for(cfg, 14)
    out = run_fixed(frames, cfg, SCHEDULE)
    assert out.end_frames.tolist() == [2, 3, 8, 10, 12]
    for j, (first, k) in enumerate(segment_spans(cfg, 14, SCHEDULE)):
        alone = run_fixed(frames[first:first + k], cfg.replace(segment_frames=k))
        np.testing.assert_array_equal(out.energy[j], alone.energy[0])
        np.testing.assert_array_equal(out.direction[j], alone.direction[0])


@pytest.mark.parametrize("weights", [None, "random"])
def test_fast_kernel_is_bit_identical_with_a_schedule(weights):
    kw = {} if weights is None else {
        "weights": np.random.default_rng(2).random((10, 9)), "weight_frac_bits": 5}
    cfg = config(energy_bits=11, **kw)
    frames = np.stack([frames_for(cfg, 14, seed) for seed in range(3)])    # 3 trials
    ref = run_fixed(frames, cfg, SCHEDULE)
    fast = run_fixed_fast(frames, cfg, schedule=SCHEDULE, threads=2)
    np.testing.assert_array_equal(ref.energy, fast.energy)
    np.testing.assert_array_equal(ref.direction, fast.direction)
    np.testing.assert_array_equal(ref.end_frames, fast.end_frames)


def test_saturation_counts_are_the_clipped_sums():
    cfg = config(input_bits=8, energy_bits=9)
    frames = frames_for(cfg, 9, seed=4)
    counts = saturation_counts(frames, cfg, SCHEDULE)
    brute, e, d = [], None, None
    for t, (_, k) in enumerate(frame_segments(cfg, 9, SCHEDULE)):
        if k == 0:
            e, d = segment_start(frames[t], cfg)
            brute.append(0)
            continue
        e_new, d_new, clipped = dp_step_saturated(e, d, frames[t], cfg)
        np.testing.assert_array_equal((e_new, d_new), dp_step(e, d, frames[t], cfg))
        assert ((e_new == cfg.e_max) | ~clipped).all()
        brute.append(int(clipped.sum()))
        e, d = e_new, d_new
    assert counts.tolist() == brute and sum(brute) > 0
    assert saturation_counts(frames[None], cfg, SCHEDULE).tolist() == [brute]


def test_segment_sequence_uses_s_of_the_segment_and_n_of_the_previous_one():
    cfg = config(candidate_count=4, candidate_capacity=8)
    frames = frames_for(cfg, 14, seed=5)
    out = run_fixed(frames, cfg, SCHEDULE)
    lists = segment_sequence(out.energy, out.direction, cfg, SCHEDULE)
    prev = prev_n = None
    for j, lst in enumerate(lists):
        entry = SCHEDULE[min(j, len(SCHEDULE) - 1)]
        want = segment_fixed(out.energy[j], out.direction[j], cfg, prev,
                             shift=entry.histogram_shift, prev_count=prev_n)
        assert (lst.count, lst.threshold) == (want.count, want.threshold)
        np.testing.assert_array_equal(lst.histogram, want.histogram)
        prev, prev_n = lst.histogram, entry.candidate_count
    assert segment_sequence(out.energy, out.direction, cfg, [S(2, cfg.n_candidates,
                                                               cfg.bin_shift)])[2].count \
        == segment_sequence(out.energy, out.direction, cfg)[2].count


def test_segment_stream_follows_per_word_settings():
    """The word-by-word model equals the per-image one for a scheduled, well-formed stream."""
    cfg = config(candidate_count=4, candidate_capacity=8)
    frames = frames_for(cfg, 11, seed=6)
    schedule = SCHEDULE[:3] + [S(2, 7, 4)]
    out = run_fixed(frames, cfg, schedule)
    by_image = segment_sequence(out.energy, out.direction, cfg, schedule)
    rows, settings = [], []
    for j, (first, k) in enumerate(segment_spans(cfg, 11, schedule)):
        e, d = segment_start(frames[first], cfg)
        for t in range(first, first + k):
            if t > first:
                e, d = dp_step(e, d, frames[t], cfg)
            block = np.zeros((cfg.height, cfg.width, 5), np.int64)
            block[..., 0], block[..., 1] = e, d
            block[:, -1, 2] = 1
            block[-1, -1, 3] = 1
            block[-1, -1, 4] = int(t == first + k - 1)
            rows.append(block.reshape(-1, 5))
            entry = schedule[j]
            settings.append(np.tile([k, entry.candidate_count, entry.histogram_shift],
                                    (cfg.height * cfg.width, 1)))
    by_stream = segment_stream(np.concatenate(rows), cfg, np.concatenate(settings))
    assert [(a.count, a.threshold) for a in by_stream] == \
        [(b.count, b.threshold) for b in by_image]


BAD = [
    ([S(6, 1, 1)], "segment_frames must be an integer in [1, K_max=5], got 6"),
    ([S(0, 1, 1)], "segment_frames must be an integer in [1, K_max=5], got 0"),
    ([S(2, 13, 1)], "candidate_count must be an integer in [0, C=12], got 13"),
    ([S(2, -1, 1)], "candidate_count must be an integer in [0, C=12], got -1"),
    ([S(2, 1, 16)], "histogram_shift must be an integer in [0, B_E-1=15], got 16"),
    ([S(2, 1, 2.0)], "histogram_shift must be an integer in [0, B_E-1=15], got 2.0"),
    ([], "schedule must hold at least one SegmentSettings, got none"),
    ([S(2, 1, 1), (2, 1, 1)], "schedule[1] must be a SegmentSettings, got tuple"),
]


@pytest.mark.parametrize("schedule, message", BAD, ids=[m for _, m in BAD])
def test_bad_schedules_are_refused(schedule, message):
    cfg = config()
    with pytest.raises(ConfigError, match=whole(message)):
        check_schedule(cfg, schedule)
    with pytest.raises(ConfigError, match=whole(message)):
        run_fixed(frames_for(cfg, 6), cfg, schedule)


def test_a_schedule_needs_non_overlapping_segments():
    cfg = config(segment_frames=3, segment_stride=1)
    with pytest.raises(ConfigError, match=r"^a run-time schedule needs non-overlapping "
                                          r"segments, but segment_stride=1 != "
                                          r"segment_frames=3$"):
        run_fixed(frames_for(cfg, 6), cfg, [S(2, 1, 1)])


def test_defaults_are_the_build_values():
    cfg = config()
    assert S.defaults(cfg) == S(2, cfg.n_candidates, cfg.bin_shift)
    assert check_schedule(cfg, None) == (S.defaults(cfg),)
