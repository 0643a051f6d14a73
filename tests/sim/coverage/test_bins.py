"""The functional coverage bins (:mod:`dptbd.sim.coverage.bins`): the extraction on hand-made
runs with exact counts, the merge by addition, the empty-bin verdict; which bins the default
suite's campaign slice fills is asserted in ``tests/sim/test_campaign.py``."""

from __future__ import annotations

import re
from types import SimpleNamespace

import numpy as np
import pytest

from dptbd.model.segmentation import segment_stream
from dptbd.model.settings import SegmentSettings
from dptbd.sim.axi_stimulus import clean_beats, with_fault
from dptbd.sim.campaign import Case, _make_run
from dptbd.sim.candidate_scoreboard import list_words
from dptbd.sim.coverage import bins
from dptbd.sim.rtl_check import Stimulus
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


def test_stall_bands_have_their_edges():
    assert [bins.band(p) for p in (0.0, 1e-9, 0.3499, 0.35, 0.7, 0.999)] == \
        ["none", "light", "light", "heavy", "heavy", "heavy"]


def test_merge_adds_hits_over_the_union_of_declared_bins():
    assert bins.merge({"a: x": 1, "b: y": 0}, {"a: x": 2, "c: z": 0}, {}) == \
        {"a: x": 3, "b: y": 0, "c: z": 0}
    assert bins.merge() == {}
    assert bins.table({"reset: 10 words in flight": 1, "reset: 2 words in flight": 0,
                       "stall: gaps light, back-pressure none, interior": 5,
                       "stall: gaps none, back-pressure heavy, first row": 7}) == [
        ("stall: gaps none, back-pressure heavy, first row", "dp, core, segmenter, axi", 7),
        ("stall: gaps light, back-pressure none, interior", "dp, core, segmenter, axi", 5),
        ("reset: 2 words in flight", "dp, core, segmenter", 0),
        ("reset: 10 words in flight", "dp, core, segmenter", 1)]


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
    assert bins._reset_occupancy("segmenter", [(31, 1), (12, 2)], accept,
                                 np.zeros(0, dtype=np.int64), 4) == [2, 1]
    # dp: accepted minus transferred since the previous reset
    assert bins._reset_occupancy("dp", [(12, 2), (31, 1)], accept,
                                 np.array([6, 7, 20], dtype=np.int64), 4) == [3, 0]


@pytest.mark.parametrize("seed", range(4))
def test_list_ends_follow_the_segmenters_control_flow(seed):
    """One list end per list of segment_stream, on hostile streams with every framing fault
    and run-time settings."""
    case = Case("t", dict(width=7, height=5, segment_frames=3, candidate_count=3), "segmenter",
                40, 1, ("misaligned_first", "short_frame", "long_frame", "settings"))
    cfg = case.cfg
    words, stim, _, events = _make_run(case, seed)
    assert {f for f, _ in events} == {"misaligned_first", "short_frame", "long_frame"}
    pixels, first = split_words(cfg, words)
    exp = expected_stream(cfg, pixels, first, None, {int(i): s for i, s in stim.settings_changes})
    lists = segment_stream(exp.fields, cfg, exp.settings)
    ends = bins.list_ends(cfg, exp.fields, exp.settings)
    assert len(ends) == len(lists) > 5
    assert all(a[0] < b[0] for a, b in zip(ends, ends[1:]))
    for j, (end, n) in enumerate(ends):            # list j is made by word `end`, not before
        assert len(segment_stream(exp.fields[:end], cfg, exp.settings[:end])) == j
        assert len(segment_stream(exp.fields[:end + 1], cfg, exp.settings[:end + 1])) == j + 1
        assert 0 <= n <= cfg.record_capacity
    assert {n for _, n in ends} > {cfg.n_candidates}                # n rewritten at run time


def _axi():
    """6 frames of 4 x 3, K = 2, n = 2; frame 0 has 2 lines (frame_short at beat 8). Whole
    LUT before beat 0, refused settings; single LUT entries at beat 8; a soft reset after
    the settle at 32 (frame 3), with strobed writes of HISTOGRAM_SHIFT; a soft reset "now"
    at 44 (frame 4); aresetn at 56 (frame 5), then a strobed write."""
    from dptbd.hw.register_map import register_map

    cfg = Case("axi", dict(width=4, height=3, segment_frames=2, candidate_count=2), "axi", 6,
               1).cfg
    frames = np.random.default_rng(3).integers(0, cfg.pixel_max + 1, size=(6, 3, 4))
    beats = with_fault(cfg, frames, "frame_short")            # frame 0: 2 lines of 4 beats
    codes = np.zeros((cfg.n_moves + 1, cfg.n_moves), dtype=np.int64)
    codes[1:, :] = 1 << cfg.weight_frac_bits
    unity = 1 << cfg.weight_frac_bits
    shift = register_map(cfg)["HISTOGRAM_SHIFT"].address
    steps = [{"stop": 8, "writes": [("SEGMENT_FRAMES", 0), ("HISTOGRAM_SHIFT", 99),
                                    ("CANDIDATE_COUNT", 1)], "lut_codes": codes},
             {"stop": 32, "lut_writes": [[0, 0, unity - 1, 0xF], [1, 0, unity + 1, 0xF],
                                         [1, 1, 0, 0x7], [2, 1, 0, 0xF]]},
             {"stop": 44, "soft_reset": True,
              "bus": [["w", shift, 2**32 - 1, 0b0010, 2],      # byte 1: 0xFF00 | s, refused
                      ["w", shift, 0xFFFFFF01, 0b0001, 0],     # byte 0: s = 1
                      ["w", shift, 2**32 - 1, 0b0000, 0]]},    # no strobe: nothing
             {"stop": 56, "soft_reset": "now"},
             {"stop": len(beats), "aresetn": 2,
              "bus": [["w", shift, 0x00000100, 0b0011, 2]]}]    # 0x100: refused
    return cfg, beats, steps, codes


def _axi_run(cfg, steps):
    """The cycles of a hand-made run: beat i accepted at cycle 10 + 2 i, every register
    operation done at cycle 100 (the soft reset "now" before beat 44: its write began at
    98, beats 41, 42 and 43 accepted in the 6 cycles before)."""
    from dptbd.sim.verilator_axi import step_operations

    _, checks = step_operations(cfg, steps, 0, [])
    return SimpleNamespace(accept_cycles=10 + 2 * np.arange(68, dtype=np.uint64),
                           op_cycles=np.full(len(checks), 100, dtype=np.int64))


def test_an_axi_run_fills_its_bins_exactly():
    from dptbd.hw.register_map import register_map

    cfg, beats, steps, codes = _axi()
    regs = register_map(cfg)
    lut = regs.window("LUT").base
    top = max(r.address for r in regs.registers) + 4
    at = {r.name: r.address for r in regs.registers}
    bus = [("w", 1, 0, 0xF), ("r", 2, 0, 0), ("w", lut, 0, 0x3), ("r", lut, 0, 0xF),
           ("w", lut + 4, (1 << cfg.weight_frac_bits) + 1, 0xF), ("w", lut + 8, 0, 0xF),
           ("w", at["ID"], 1, 0xF), ("w", at["FRAMES"], 0, 0xF), ("w", at["STATUS"], 0, 0xF),
           ("w", top, 0, 0xF), ("r", top, 0, 0xF), ("w", at["SEGMENT_FRAMES"], 99, 0xF),
           ("w", at["CONTROL"], 1, 0xF), ("r", at["FRAMES"], 0, 0xF)]
    counts = bins.axi_bins(cfg, beats, steps, passed=True, latency=6, valid_gap=0.5,
                           ready_pause=0.1, run=_axi_run(cfg, steps), bus=bus)
    # 68 words: frame 0's two lines, 5 whole frames; K = 2: every frame a segment's first
    # or last
    light = "stall: gaps heavy, back-pressure light, "
    assert _hits(counts, "stall") == {
        f"stall: gaps {g}, back-pressure {b}, {p}": 0 for g, *_ in bins.BANDS
        for b, *_ in bins.BANDS for p in bins.POSITIONS} | {
        light + "first row": 24, light + "last row": 20, light + "first column": 17,
        light + "last column": 17, light + "interior": 12,
        light + "segment boundary frame": 68}
    assert _hits(counts, "soft reset") == {bins.soft_reset_bin(k): int(k in (0, 3))
                                           for k in range(7)}
    assert _hits(counts, "aresetn") == {bins.ARESETN: 1}
    # frame_short pulses at beat 8, where a clean segment [8, 32) begins (the entries
    # written before beat 8 are not inside it)
    assert _hits(counts, "fault") == {"fault: sof_unexpected recovered": 0,
                                      "fault: frame_short recovered": 1,
                                      "fault: frame_long recovered": 0,
                                      "fault: line_length recovered": 0}
    assert _hits(counts, "LUT") == {
        "LUT: written between frames": 1, "LUT: written in the first row": 0,
        "LUT: written in a middle row": 0, "LUT: written in the last row": 0,
        "LUT: code 0": cfg.n_moves + 1, "LUT: code 2**F - 1": 1,
        "LUT: code 2**F (the largest)": cfg.n_moves ** 2}
    assert _hits(counts, "register") == {
        "register: SEGMENT_FRAMES value out of range": 2,
        "register: CANDIDATE_COUNT value out of range": 0,
        "register: HISTOGRAM_SHIFT value out of range": 3,
        "register: VIDEO_INPUT value out of range": 0,
        "register: LUT value out of range": 2,
        "register: LUT write without wstrb = 1111": 2, "register: LUT read": 1,
        "register: write to a constant register": 1, "register: write to a counter": 1,
        "register: write to the status register": 1, "register: unaligned write": 1,
        "register: unaligned read": 1, "register: unmapped write": 1,
        "register: unmapped read": 1}
    assert set(_hits(counts, "lists")) == {"lists: " + label for label in bins.LIST_LABELS}
    assert set(counts) == set(bins.declared_axi(cfg, 6))
    assert not _hits(counts, "reset")
    failed = bins.axi_bins(cfg, beats, steps, passed=False, latency=6, run=None, bus=bus)
    assert failed == bins.declared_axi(cfg, 6) and set(failed.values()) == {0}


def test_a_strobed_setting_write_refuses_the_word_it_makes():
    """After aresetn (s the build's again): bytes 0 and 1 of 0x100 make 256, refused; byte 0
    of 0xFFFFFF00 makes 0 (taken: the bytes not strobed are the held s's); byte 0 of 0xFF
    makes 255, refused; byte 1 of 0 leaves the held 0, taken."""
    cfg, beats, steps, _ = _axi()
    shift = steps[-1]["bus"][0][1]
    steps[-1]["bus"] += [["w", shift, 0xFFFFFF00, 0b0001, 0], ["w", shift, 0xFF, 0b0001, 2],
                         ["w", shift, 0, 0b0010, 0]]
    counts = bins.axi_bins(cfg, beats, steps, passed=True, latency=6, run=_axi_run(cfg, steps))
    assert counts["register: HISTOGRAM_SHIFT value out of range"] == 4


def test_a_soft_reset_with_words_in_flight_needs_the_runs_cycles():
    cfg, beats, steps, _ = _axi()
    with pytest.raises(ValueError, match=whole(
            'axi_bins needs the run\'s cycles (run=) to count the words in flight at a soft '
            'reset of "now"')):
        bins.axi_bins(cfg, beats, steps, passed=True, latency=6)


def test_clean_frames_have_no_fault_to_recover_from():
    cfg, _, _, _ = _axi()
    beats = clean_beats(np.zeros((4, 3, 4), dtype=np.int64))
    counts = bins.axi_bins(cfg, beats, [{"stop": len(beats)}], passed=True, latency=6)
    assert set(_hits(counts, "fault").values()) == {0}
    assert counts[bins.SATURATION] == 0 and set(_hits(counts, "soft reset").values()) == {0}
