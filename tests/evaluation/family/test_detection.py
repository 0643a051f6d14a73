"""``dptbd.evaluation.family.detection``: variants, their configurations, the counts."""

from __future__ import annotations


import numpy as np
import pytest

from dptbd.errors import DptbdError
from dptbd.evaluation.family import detection as fd
from dptbd.evaluation.metrics import DetectionCounts
from dptbd.evaluation.table1.experiment import table1_config
from helpers.refusals import whole


def test_segment_variant_is_table1s_configuration_with_stride_k():
    cfg = fd.variant_config(fd.segments(8))
    assert cfg == table1_config(8, 8) and cfg.is_paper001_datapath


def test_recursive_variant_configuration():
    cfg = fd.variant_config(fd.recursive(0.85))
    assert cfg.recursive and cfg.forgetting_code == 218 and cfg.energy_bits == 20
    assert not cfg.is_paper001_datapath and cfg.penalty_codes is None


def test_zero_move_penalty_is_on_the_centre_move_after_a_moving_or_still_predecessor():
    cfg = fd.variant_config(fd.recursive(0.9, zero_move_penalty=24))
    table = cfg.penalty_code_array
    assert table.shape == (10, 9) and np.all(table[:9, 4] == 24) and table[9, 4] == 0
    assert table.sum() == 9 * 24


def test_alpha_one_is_a_recursion_without_forgetting():
    cfg = fd.variant_config(fd.recursive(1.0))
    assert cfg.recursive and cfg.forgetting_code == 256 and cfg.energy_bits == 20
    assert fd.recursive(1.0).label == "recursive alpha=1"


@pytest.mark.parametrize("call, message", [
    (lambda: fd.recursive(1.5), "forgetting must be a finite real number in (0, 1], got 1.5"),
    (lambda: fd.recursive(0.0), "forgetting must be a finite real number in (0, 1], got 0.0"),
    (lambda: fd.recursive(-0.2), "forgetting must be a finite real number in (0, 1], got -0.2"),
    (lambda: fd.recursive(float("nan")), "forgetting must be a finite real number in (0, 1], got nan"),
    (lambda: fd.recursive(0.001),  # DPConfig's refusal: alpha's 8-bit code would be 0
     "forgetting must be a finite real number in [0.00195312, 1] for forgetting_bits=8 (its code "
     "round(forgetting * 2**8) must be >= 1), got 0.001"),
    (lambda: fd.recursive(0.5, warmup=100), "warmup must be an integer in [0, 99], got 100"),
    (lambda: fd.segments(0), "segment_frames must be an integer in [1, 100], got 0"),
    (lambda: fd.recursive(0.5, zero_move_penalty=-1),
     "zero_move_penalty must be an integer in [0, 65535], got -1"),
])
def test_refusals(call, message):
    with pytest.raises(DptbdError, match=whole(message)):
        call()


@pytest.mark.parametrize("variant, maps", [(fd.segments(6), 16), (fd.recursive(0.8, warmup=7), 93)])
def test_counts_one_map_per_segment_or_per_frame(variant, maps):
    c = fd.variant_counts(variant, 2.3, (1.0, 1.0), trials=1, seed=5, size=32)
    assert c.frames == maps
    assert c.opportunities <= maps and 0 <= c.detections <= c.opportunities
    # n = count_for_rate(0.2 %, 32 x 32) = 2 candidates per map at most
    assert c.false_points <= 2 * maps


def test_paired_difference():
    from dptbd.evaluation.metrics import DetectionCounts
    a = [DetectionCounts(1, 2, 0, 2), DetectionCounts(2, 4, 0, 4), DetectionCounts(0, 1, 0, 1)]
    b = [DetectionCounts(2, 2, 0, 2), DetectionCounts(3, 4, 0, 4), DetectionCounts(1, 1, 0, 1)]
    mean, lo, hi = fd.paired_pd_difference(a, b)
    assert mean == pytest.approx((0.5 + 0.25 + 1.0) / 3) and lo < mean < hi
    with pytest.raises(ValueError, match=r"^paired_pd_difference needs two equally long lists "
                                         r"of at least 2 scenes, got 3 and 2$"):
        fd.paired_pd_difference(a, b[:2])


def test_trial_counts_sum_to_the_setting_counts():
    per = fd.variant_trial_counts(fd.segments(4), 2.0, (1.0, 1.0), trials=3, seed=7, size=24,
                                  chunk=2)
    total = fd.variant_counts(fd.segments(4), 2.0, (1.0, 1.0), trials=3, seed=7, size=24)
    assert len(per) == 3 and sum(c.detections for c in per) == total.detections
    assert sum(c.frames for c in per) == total.frames == 3 * 25


def test_range_counts_split_the_maps_by_their_last_frame():
    rec = fd.recursive(0.9, warmup=7)
    per = fd.variant_range_counts(rec, 2.3, (1.0, 1.0), ranges=((0, 99), (7, 15), (16, 99), (0, 6)),
                                  trials=2, seed=5, size=32)
    assert len(per) == 2
    for total, early, late, none in per:
        assert (early.frames, late.frames, total.frames) == (9, 84, 93)
        assert early + late == total and none == DetectionCounts(0, 0, 0, 0)
    # the whole range is variant_trial_counts
    assert [p[0] for p in per] == fd.variant_trial_counts(rec, 2.3, (1.0, 1.0), trials=2, seed=5,
                                                          size=32)
    # K = 6 segments end at frames 5, 11, ..., 95: two of them in 0..11
    seg = fd.variant_range_counts(fd.segments(6), 2.3, (1.0, 1.0), ranges=((0, 11),), trials=1,
                                  seed=5, size=32)
    assert seg[0][0].frames == 2


def test_parse_segment_lengths_and_frame_ranges():
    assert fd.parse_segment_lengths("6, 8,12,16,24,32") == (6, 8, 12, 16, 24, 32)
    assert fd.parse_frame_ranges("7-15, 64-99") == ((7, 15), (64, 99))
    assert fd.check_frame_ranges([(0, 0)]) == ((0, 0),)


@pytest.mark.parametrize("call, message", [
    (lambda: fd.parse_segment_lengths("6,x"), "k must be comma-separated integers in [1, 100], got '6,x'"),
    (lambda: fd.parse_segment_lengths("6,101"), "segment_frames must be an integer in [1, 100], got 101"),
    (lambda: fd.parse_segment_lengths("6,8,6"), "k must hold distinct segment lengths, got '6,8,6'"),
    (lambda: fd.parse_frame_ranges("7-15,64"),
     "frame ranges must be comma-separated FIRST-LAST pairs of frames, got '7-15,64'"),
    (lambda: fd.parse_frame_ranges("7-15,64-100"), "frame range 1 last must be an integer in [64, 99], got 100"),
    (lambda: fd.parse_frame_ranges("15-7"), "frame range 0 last must be an integer in [15, 99], got 7"),
    (lambda: fd.check_frame_ranges([(-1, 5)]), "frame range 0 first must be an integer in [0, 99], got -1"),
    (lambda: fd.check_frame_ranges([(1, 2, 3)]),
     "frame range 0 must be a pair (first, last) of frames, got (1, 2, 3)"),
    (lambda: fd.check_frame_ranges([]), "ranges must hold at least one (first, last) frame range"),
])
def test_frame_range_and_segment_length_refusals(call, message):
    with pytest.raises(DptbdError, match=whole(message)):
        call()
