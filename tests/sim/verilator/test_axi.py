"""Compiled RTL simulation of the AXI top level ``dptbd_axi`` (Verilator, harness
``sim/harness/dptbd_axi_harness.cpp``): beats with injected frame-sync faults, random
``tvalid`` gaps and ``tready`` back-pressure, AXI4-Lite writes (K, n, s, LUT entries, W1C,
soft reset, refused values) and reads at given beats; every candidate word, its
``tuser[0]`` / ``tlast``, every write response, every check read and the end counters
scored against the golden model (:func:`dptbd.sim.verilator.axi.check_axi`). A long
128 x 128 run behind ``-m slow``.
"""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.hw.register_map import FAULTS, constants_namespace
from dptbd.sim import verilator as V
from dptbd.sim.axi.stimulus import clean_beats, with_fault
from dptbd.sim.scenarios import make_frames
from dptbd.sim.verilator.axi import (CUT_COUNTERS, beat_words, check_axi, run_axi,
                                     step_operations)
from helpers.refusals import whole
from helpers.verilator_harness import SEG, built, make_config, needs_verilator

pytestmark = needs_verilator

# 12 x 10, K = 2 (K_max = 4), n = 4, C = 6, 64 bins of width 4: lists with records
SMALL = dict(width=12, height=10, segment_frames=2, max_segment_frames=4, candidate_count=4,
             candidate_capacity=6, histogram_bits=6, histogram_shift=2)


def test_beat_words_and_operations():
    cfg = make_config(**SMALL)
    beats = clean_beats(make_frames("two-targets", cfg, 1, seed=1))
    words = beat_words(beats)
    assert int(words[0]) >> 32 == 1 and int(words[11]) >> 32 == 2 and int(words[12]) >> 32 == 0
    regs = constants_namespace(cfg)
    ops, checks = step_operations(cfg, [{"writes": [["CANDIDATE_COUNT", 99]], "stop": 5},
                                        {"soft_reset": True, "check": {"ID": 1}, "stop": 9}],
                                  settle=7, final_reads=["FRAMES"])
    assert ops == [(0, "w", regs.REG_CANDIDATE_COUNT, 99), (5, "i", 7, 0),
                   (5, "r", regs.REG_ID, 0), (5, "w", regs.REG_CONTROL,
                                                 regs.CONTROL_SOFT_RESET_MASK, ),
                   (9, "i", 7, 0), (9, "r", regs.REG_FRAMES, 0)]
    assert checks == [("write", "CANDIDATE_COUNT", 2), ("read", "ID", 1),
                      ("write", "CONTROL", 0), ("read", "FRAMES", None)]
    with pytest.raises(ValueError, match=r"^run_axi needs a build of design 'axi', got 'dp'$"):
        run_axi(built(make_config(**SEG), "dp"), beats, [])     # the dp build others share
    with pytest.raises(ValueError, match=r"^the 'axi' build has its own harness: use "
                                         r"dptbd\.sim\.verilator\.axi\.run_axi$"):
        V.run(built(cfg, "axi"), beat_words(beats))
    with pytest.raises(ValueError, match=whole("operation 'x' before beat 3: kinds are w, r, "
                                               "i, m, b, a, p and beats 0 … 120")):
        run_axi(built(cfg, "axi"), beats, [(3, "x", 0, 0)])
    with pytest.raises(ValueError, match=whole("operation 'r' before beat 121: kinds are w, r, "
                                               "i, m, b, a, p and beats 0 … 120")):
        run_axi(built(cfg, "axi"), beats, [(121, "r", 0, 0)])


def test_operations_of_lut_entries_raw_accesses_and_counter_clears():
    cfg = make_config(**SMALL)
    regs = constants_namespace(cfg)
    lut = regs.LUT_BASE + 4 * cfg.lut_address(1, 2)
    ops, checks = step_operations(
        cfg, [{"clear_counters": True, "lut_writes": [[1, 2, 256, 0xF], [1, 2, 257, 0xF],
                                                      [1, 2, 0, 7]],
               "bus": [["w", 0x301, 5, 0xF, 2], ["r", lut, 2, 0]], "stop": 4},
              {"writes": [["VIDEO_INPUT", 2], ["IRQ_ENABLE", 2**32 - 1], ["ID", 0]],
               "stop": 4}, {"soft_reset": "now", "stop": 6}, {"aresetn": 3, "stop": 6},
              {"aresetn": 2, "aresetn_wait": 5, "stop": 8}],
        settle=7, final_reads=[])
    assert ops == [(0, "i", 7, 0), (0, "w", regs.REG_CONTROL, regs.CONTROL_CLEAR_COUNTERS_MASK),
                   (0, "m", lut, 256 | 0xF << 32), (0, "m", lut, 257 | 0xF << 32),
                   (0, "m", lut, 7 << 32), (0, "m", 0x301, 5 | 0xF << 32), (0, "r", lut, 0),
                   (4, "w", regs.REG_VIDEO_INPUT, 2), (4, "w", regs.REG_IRQ_ENABLE, 2**32 - 1),
                   (4, "w", regs.REG_ID, 0),
                   (4, "w", regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK),
                   (4, "b", regs.REG_STATUS, 0),
                   *((4, "r", getattr(regs, f"REG_{name}"), 0) for name in CUT_COUNTERS),
                   (6, "i", 7, 0), (6, "a", 3, 0),
                   (6, "i", 5, 0), (6, "a", 2, 0), (6, "b", regs.REG_STATUS, 0),
                   (8, "i", 7, 0)]
    assert checks == [("write", "CONTROL", 0), ("write", "LUT[1, 2]", 0),
                      ("write", "LUT[1, 2]", 2), ("write", "LUT[1, 2]", 2),
                      ("write", "0x301", 2), ("bus-read", f"{lut:#05x}", (2, 0)),
                      ("write", "VIDEO_INPUT", 2), ("write", "IRQ_ENABLE", 0),
                      ("write", "ID", 2), ("write", "CONTROL", 0), ("wait", "STATUS", 4),
                      *(("cut", name, 4) for name in CUT_COUNTERS), ("mark", "STATUS", 6)]


def scene(cfg, seed):
    """Two clean segments, then every fault class, each in a two-frame stretch; the beats
    and the index where each stretch begins."""
    frames = make_frames("two-targets", cfg, 4 + 2 * len(FAULTS), seed=seed)
    beats, starts = clean_beats(frames[:4]), []
    for i, kind in enumerate(FAULTS):
        starts.append(len(beats))
        beats = beats + with_fault(cfg, frames[4 + 2 * i:6 + 2 * i], kind)
    return beats, starts


def test_short_run_settings_lut_faults_soft_reset():
    """K / n / s written between segments (one refused), the LUT halved, every fault class,
    ERROR cleared by W1C, a soft reset between two fault stretches (on a frame boundary, so
    the monitor's counts are the stream's); 20 % input gaps, 30 % output back-pressure."""
    cfg = make_config(**SMALL)
    regs = constants_namespace(cfg)
    beats, starts = scene(cfg, seed=3)
    frame = cfg.width * cfg.height
    every = sum(getattr(regs, f"ERROR_{k.upper()}_MASK") for k in FAULTS)
    halved = (np.asarray(cfg.weight_codes) // 2).tolist()
    steps = [{"check": {"ID": regs.MAGIC}, "stop": 2 * frame},
             {"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", 6],
                         ["HISTOGRAM_SHIFT", cfg.energy_bits]], "stop": 4 * frame},
             {"check": {"SEGMENTS": 3}, "lut_codes": halved,
              "writes": [["SEGMENT_FRAMES", 3], ["ERROR", regs.ERROR_WRITE_REFUSED_MASK]],
              "stop": starts[2]},
             {"soft_reset": True, "writes": [["HISTOGRAM_SHIFT", 1]], "stop": len(beats)},
             {"check": {"ERROR": every}, "writes": [["ERROR", every]], "stop": len(beats)}]
    result = check_axi(built(cfg, "axi"), beats, steps, valid_gap=0.2, ready_pause=0.3,
                       seed=4)
    assert result.passed, result.report()
    assert result.board.records_expected >= 3                 # the lists carry records
    assert all(result.reads[f"FAULT_{k.upper()}"] == 1 for k in FAULTS)
    assert result.run.counters["stalled_input_cycles"] > 0


@pytest.mark.slow
def test_long_run_128x128_hundred_frames():
    """001's frame size, 100 frames: K changed between segments (4, 2, 5), n and s changed,
    every fault class injected twice, the LUT rewritten once; gaps and back-pressure."""
    cfg = make_config(width=128, height=128, segment_frames=4, max_segment_frames=8)
    frames = make_frames("two-targets", cfg, 100, seed=12)
    frame = cfg.width * cfg.height
    beats = clean_beats(frames[:52])
    for i, kind in enumerate(FAULTS * 2):
        beats = beats + with_fault(cfg, frames[52 + 6 * i:58 + 6 * i], kind)
    assert len(beats) > 97 * frame
    halved = (np.asarray(cfg.weight_codes) // 2).tolist()
    steps = [{"stop": 8 * frame},
             {"writes": [["SEGMENT_FRAMES", 2], ["CANDIDATE_COUNT", 20],
                         ["HISTOGRAM_SHIFT", cfg.bin_shift + 1]], "stop": 20 * frame},
             {"writes": [["SEGMENT_FRAMES", 5]], "lut_codes": halved, "stop": 52 * frame},
             {"writes": [["SEGMENT_FRAMES", 4], ["CANDIDATE_COUNT", cfg.n_candidates]],
              "stop": len(beats)}]
    result = check_axi(built(cfg, "axi"), beats, steps, valid_gap=0.1, ready_pause=0.2,
                       seed=7)
    assert result.passed, result.report()
    assert all(result.reads[f"FAULT_{k.upper()}"] == 2 for k in FAULTS)
    assert result.reads["FRAMES"] >= 90 and result.board.records_expected > 100


def test_a_run_without_lists():
    """One frame of a K = 2 build: no list; nothing sent, nothing expected."""
    cfg = make_config(**SMALL)
    beats = clean_beats(make_frames("two-targets", cfg, 1, seed=1))
    result = check_axi(built(cfg, "axi"), beats, [{"stop": len(beats)}])
    assert result.passed, result.report()
    assert result.board.lists == [] and len(result.run.out_words) == 0


def test_repeated_beats_and_the_cycles_of_irq():
    """``repeat`` offers the beats again and again (the operations count every beat): the
    same transfers, in the same cycles, as the beats written out, and no accept cycles;
    ``irq_cycles`` holds the cycles in which ``irq`` rose and fell, in turn."""
    cfg = make_config(**SMALL)
    regs = constants_namespace(cfg)
    frame = clean_beats(make_frames("two-targets", cfg, 1, seed=1))
    three = clean_beats(np.tile(make_frames("two-targets", cfg, 1, seed=1), (3, 1, 1)))
    ops = [(120, "w", regs.REG_IRQ_ENABLE, 1), (360, "i", 200, 0),
           (360, "w", regs.REG_IRQ_STATUS, 1), (360, "r", regs.REG_FRAMES, 0)]
    sim = built(cfg, "axi")
    once, thrice = run_axi(sim, three, ops), run_axi(sim, frame, ops, repeat=3)
    for name in ("out_words", "out_flags", "out_cycles", "op_data", "op_cycles", "irq_cycles"):
        assert np.array_equal(getattr(once, name), getattr(thrice, name)), name
    assert once.cycles == thrice.cycles and len(once.accept_cycles) == 360
    assert len(thrice.accept_cycles) == 0 and thrice.counters["accepted"] == 360
    assert int(thrice.op_data[2]) == 3 and once.counters["irq_rises"] == 1
    # irq rises with the first segment's end (K = 2: after frame 1) and falls in the cycle
    # of the IRQ_STATUS write's B response
    rise, fall = (int(c) for c in once.irq_cycles)
    assert once.accept_cycles[239] < rise < int(once.op_cycles[1]) - 200
    assert fall == int(once.op_cycles[1])
    with pytest.raises(ValueError, match=whole("repeat must be an integer of at least 1, "
                                               "got 0")):
        run_axi(sim, frame, [], repeat=0)
    with pytest.raises(ValueError, match=whole("operation 'r' before beat 361: kinds are w, r, "
                                               "i, m, b, a, p and beats 0 … 360")):
        run_axi(sim, frame, [(361, "r", 0, 0)], repeat=3)
