"""The bins of the stream designs' runs (:mod:`dptbd.sim.coverage.bins.stream`): the
extraction on hand-made runs of ``dp`` and ``segmenter`` with exact counts, a failed run and
the empty bins it leaves; which bins the default suite's campaign slice fills is asserted in
``tests/sim/campaign/test_campaign.py``."""

from __future__ import annotations

import re
from types import SimpleNamespace

import numpy as np
import pytest

from dptbd.model.segmentation import segment_stream
from dptbd.model.settings import SegmentSettings
from dptbd.sim.campaign import Case
from dptbd.sim.candidate_scoreboard import list_words
from dptbd.sim.coverage import bins
from dptbd.sim.coverage.bins.stream import _reset_occupancy
from dptbd.sim.rtl.check import Stimulus
from dptbd.sim.stimulus import pixel_words
from dptbd.sim.stream_model import expected_stream, split_words

from helpers.refusals import whole

STALL = "stall: gaps heavy, back-pressure none, "


def _words(cfg, frames):
    return split_words(cfg, pixel_words(cfg, np.asarray(frames, dtype=np.uint16)))


def _hits(counts, group):
    return {k: v for k, v in counts.items() if k.startswith(group + ": ")}


def _dp_run():
    """5 frames of 4 x 3 at the largest pixel, K = 2, a reset after frame 0 (3 words in
    flight), LUT writes before words 0 and 18, a settings write after the last word."""
    case = Case("hand", dict(width=4, height=3, segment_frames=2, input_bits=4, energy_bits=4,
                             weight_frac_bits=2), "dp", 5, 1,
                ("reset", "misaligned_first", "lut", "settings"))
    cfg = case.cfg
    pixels, first = _words(cfg, np.full((5, 3, 4), cfg.pixel_max))
    codes_a = np.full((cfg.n_moves + 1, cfg.n_moves), 4)
    codes_b = np.zeros((cfg.n_moves + 1, cfg.n_moves), dtype=np.int64)
    codes_b[0, 0] = 3
    stim = Stimulus(valid_gap=0.5, resets=((14, 1),), lut_changes=((0, codes_a), (18, codes_b)),
                    settings_changes=((60, SegmentSettings.defaults(cfg)),))
    exp0 = expected_stream(cfg, pixels[:12], first[:12], {0: codes_a})
    exp1 = expected_stream(cfg, pixels[12:], first[12:], {6: codes_b})
    accept = np.arange(2, 62, dtype=np.uint64)             # one word per cycle from cycle 2
    result = SimpleNamespace(
        passed=True, words_in=60, raw=SimpleNamespace(accept_cycles=accept, out_cycles=accept + 3),
        scored=((0, exp0, SimpleNamespace(count=9)), (12, exp1, SimpleNamespace(count=48))))
    return case, stim, result


SATURATES = pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")


@SATURATES
def test_a_dp_run_fills_its_bins_exactly():
    case, stim, result = _dp_run()
    counts = bins.stream_bins(case, stim, result, [("misaligned_first", 36)], latency=3)
    assert _hits(counts, "stall") == {
        f"stall: gaps {g}, back-pressure {b}, {p}": 0 for g, *_ in bins.BANDS
        for b, *_ in bins.BANDS for p in bins.POSITIONS} | {
        STALL + "first row": 20, STALL + "last row": 20, STALL + "first column": 15,
        STALL + "last column": 15, STALL + "interior": 10, STALL + "segment boundary frame": 60}
    # 12 words accepted before cycle 14, 9 outputs (cycles 5 … 13)
    assert _hits(counts, "reset") == {"reset: 0 words in flight": 0,
                                      "reset: 1 word in flight": 0,
                                      "reset: 2 words in flight": 0,
                                      "reset: 3 words in flight": 1,
                                      "reset: more than L words (output FIFO)": 0}
    # whole segments [12, 36) (the LUT write at 18 inside: not clean) and [36, 60) (clean):
    # the settings write at 60 has no clean segment after it
    assert _hits(counts, "fault") == {"fault: reset recovered": 1, "fault: lut recovered": 1,
                                      "fault: misaligned_first recovered": 1,
                                      "fault: settings recovered": 0}
    assert _hits(counts, "LUT") == {
        "LUT: written between frames": 1, "LUT: written in the first row": 0,
        "LUT: written in a middle row": 1, "LUT: written in the last row": 0,
        "LUT: code 0": 89, "LUT: code 2**F - 1": 1, "LUT: code 2**F (the largest)": 90}
    assert counts[bins.SATURATION] == 60                       # B_E = B_in, every pixel at max
    assert not _hits(counts, "lists") and bins.TIES not in counts
    assert set(counts) == set(bins.declared_stream("dp", case.faults, True, 3))


@SATURATES
def test_a_failed_run_fills_no_bin_and_the_campaign_names_the_empty_ones():
    case, stim, result = _dp_run()
    failed = bins.stream_bins(case, stim, SimpleNamespace(passed=False), (), latency=3)
    assert failed == bins.declared_stream("dp", case.faults, True, 3)
    assert set(failed.values()) == {0}
    good = bins.stream_bins(case, stim, result, [("misaligned_first", 36)], latency=3)
    merged = bins.merge(good, failed)
    assert merged == good                                       # adding zeros changes nothing
    empty = bins.empty_bins(merged)
    assert empty[:3] == ["stall: gaps none, back-pressure none, first row",
                         "stall: gaps none, back-pressure none, last row",
                         "stall: gaps none, back-pressure none, first column"]
    assert empty[48:] == ["reset: 0 words in flight", "reset: 1 word in flight",
                          "reset: 2 words in flight", "reset: more than L words (output FIFO)",
                          "fault: settings recovered", "LUT: written in the first row",
                          "LUT: written in the last row"]
    message = bins.empty_message(["reset: 1 word in flight", "LUT: written in the last row"])
    assert re.fullmatch(whole("functional coverage: 2 empty bins: reset: 1 word in flight; "
                              "LUT: written in the last row"), message)
    assert bins.empty_message(["ties: two or more pixels in the threshold bin"]) == (
        "functional coverage: 1 empty bin: ties: two or more pixels in the threshold bin")



SEG = dict(width=4, height=3, segment_frames=1, input_bits=4, energy_bits=4,
           weight_frac_bits=2, candidate_count=2, candidate_capacity=3, histogram_bits=4)


def _seg_frames():
    """K = 1, n = 2, C = 3, bin = E = pixel: frames A, A, B (4 pixels at 1), zero."""
    a = np.zeros((3, 4), dtype=np.uint16)
    a[0, 1] = a[2, 3] = 8
    b = np.zeros((3, 4), dtype=np.uint16)
    b[1, :] = 1
    return np.stack([a, a, b, np.zeros_like(a)])


def test_a_segmenter_run_counts_lists_and_ties():
    case = Case("seg", SEG, "segmenter", 4, 1, ())
    cfg = case.cfg
    pixels, first = _words(cfg, _seg_frames())
    exp = expected_stream(cfg, pixels, first)
    lists = segment_stream(exp.fields, cfg, exp.settings)
    # list 0 unprimed (T = 16): empty; list 1: T = 1, the 2 pixels at 8; list 2: T = 1,
    # 4 pixels in bin 1 (a tie), 3 records and the overflow; list 3: T = 2, empty
    assert [(lst.count, lst.threshold, lst.overflow) for lst in lists] == \
        [(0, 16, False), (2, 1, False), (3, 1, True), (0, 2, False)]
    words = sum(len(w) for w in list_words(cfg, lists))
    run = SimpleNamespace(passed=True, words_in=48,
                          raw=SimpleNamespace(accept_cycles=np.arange(2, 50, dtype=np.uint64),
                                              out_cycles=np.zeros(0, dtype=np.uint64)),
                          scored=((0, exp, SimpleNamespace(lists=lists, count=words)),))
    counts = bins.stream_bins(case, Stimulus(), run, latency=4)
    assert _hits(counts, "lists") == {"lists: 0 records (empty)": 2,
                                      "lists: exactly n records (0 < n < C)": 1,
                                      "lists: C records (at capacity)": 1,
                                      "lists: overflowing (more than C)": 1}
    assert counts[bins.TIES] == 1
    # cut by a reset after list 1's trailer and one record of list 2: lists 0 and 1 only
    run.scored = ((0, exp, SimpleNamespace(lists=lists, count=1 + 3 + 1)),)
    counts = bins.stream_bins(case, Stimulus(), run, latency=4)
    assert list(_hits(counts, "lists").values()) == [1, 1, 0, 0] and counts[bins.TIES] == 0


def test_a_segmenter_reset_counts_the_words_of_the_last_latency_cycles():
    accept = np.array([2, 3, 4, 10, 11, 30], dtype=np.int64)
    # cycle 12: words at 10, 11 within [8, 12); cycle 31: the word at 30, none since reset 12
    assert _reset_occupancy("segmenter", [(31, 1), (12, 2)], accept,
                            np.zeros(0, dtype=np.int64), 4) == [2, 1]
    # dp: accepted minus transferred since the previous reset
    assert _reset_occupancy("dp", [(12, 2), (31, 1)], accept,
                            np.array([6, 7, 20], dtype=np.int64), 4) == [3, 0]

