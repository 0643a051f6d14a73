"""The bins of a ``dptbd_axi`` run (:mod:`dptbd.sim.coverage.bins.axi`): the extraction on a
hand-made run with exact counts (every refusal of the register block among them), strobed
setting writes, the refusal of a soft reset "now" without the run's cycles."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from dptbd.sim.axi.stimulus import clean_beats, with_fault
from dptbd.sim.campaign import Case
from dptbd.sim.coverage import bins

from helpers.refusals import whole


def _hits(counts, group):
    return {k: v for k, v in counts.items() if k.startswith(group + ": ")}



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
    from dptbd.sim.verilator.axi import step_operations

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
