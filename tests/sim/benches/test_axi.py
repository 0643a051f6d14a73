"""RTL simulation of the generated ``dptbd_axi`` (cocotb 2 + Icarus, cocotbext-axi drivers)
against the golden model: candidate lists bit for bit over whole small scenes, under a
matrix of input idle × output back-pressure patterns, with register writes between
segments, a LUT rewritten mid-run, every frame-sync fault injected, refused writes, W1C and
interrupt timing.

Builds go to ``build/sim/<config>-axi/`` (cached). ``pytest -m slow`` adds a larger pause
matrix and one run per fault class.
"""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from dptbd.hw.register_map import FAULTS, constants_namespace
from dptbd.sim.axi.stimulus import clean_beats, expected_outputs, fault_counts, with_fault
from dptbd.sim.candidate_scoreboard import list_words
from dptbd.sim.icarus import simulate
from dptbd.sim.scenarios import make_frames
from helpers.cocotb_harness import CYCLE, assert_passed, built, make_config, random_pause

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")
RANDOM = random_pause

# 16 x 16, K = 2 (K_max = 4), n = 5, C = 8, 32 bins
SCENE_CFG = dict(width=16, height=16, segment_frames=2, max_segment_frames=4, candidate_count=5,
                 candidate_capacity=8, histogram_bits=5, histogram_shift=2)


def run(cfg, frames, beats, steps, name, *, records=True, **options):
    result = simulate(built(cfg, "axi"), frames, testcase="run_stream", run_name=name,
                      beats=beats.to_json(), steps=steps, **options)
    assert_passed(result)
    # every run must compare records, not only trailers: a scene whose lists are all empty
    # would let a wrong record path pass
    assert not records or sum(result.summary["counts"]) > 0, \
        f"{name}: every expected list is empty"
    return result.summary


@pytest.mark.parametrize("valid_pause,ready_pause", [
    (None, None), (RANDOM(0.3, 1), RANDOM(0.5, 2)),
    pytest.param(CYCLE, RANDOM(0.2, 3), marks=pytest.mark.slow),
    pytest.param(RANDOM(0.5, 4), CYCLE, marks=pytest.mark.slow),
    pytest.param(CYCLE, CYCLE, marks=pytest.mark.slow)],
    ids=["no-pauses", "random-random", "cycle-random", "random-cycle", "cycle-cycle"])
def test_clean_scene_counters_and_identification(valid_pause, ready_pause):
    cfg = make_config(**SCENE_CFG)
    regs = constants_namespace(cfg)
    frames = make_frames("two-targets", cfg, 6, seed=5)
    beats = clean_beats(frames)
    s = run(cfg, frames, beats, [{"check": {"ID": regs.MAGIC, "BUILD_FRAME": 16 | 16 << 16},
                                  "stop": len(beats)}],
            f"axi-clean-{bool(valid_pause)}-{bool(ready_pause)}",
            valid_pause=valid_pause, ready_pause=ready_pause,
            final_check={"FRAMES": 6, "SEGMENTS": 3, "LISTS": 3, "ERROR": 0,
                         **{f"FAULT_{k.upper()}": 0 for k in FAULTS}})
    assert s["lists"] == 3 and s["accepted"] == len(beats)
    counters = s["counters"]
    assert counters["INPUT_STALLS"] == s["stalls_seen"]["input"]
    assert counters["OUTPUT_STALLS"] == s["stalls_seen"]["output"]
    if ready_pause is None:
        assert counters["INPUT_STALLS"] == counters["OUTPUT_STALLS"] == 0


def test_lut_rewritten_mid_run_and_refused_writes():
    """Segment 1 with the build LUT, then a LUT of zeros written between segments; the
    scoreboard applies it from that beat on. Writes out of range are refused (SLVERR, value
    kept, ERROR.write_refused set, then cleared by W1C)."""
    cfg = make_config(**SCENE_CFG)
    regs = constants_namespace(cfg)
    frames = make_frames("two-targets", cfg, 6, seed=9)
    beats = clean_beats(frames)
    half = len(beats) // 3                                   # after segment 1
    zeros = np.zeros((cfg.n_moves + 1, cfg.n_moves), dtype=int)     # no accumulation
    refused = regs.ERROR_WRITE_REFUSED_MASK
    steps = [
        {"writes": [["SEGMENT_FRAMES", 0], ["SEGMENT_FRAMES", regs.SEGMENT_FRAMES_SEGMENT_FRAMES_MAX + 1],
                    ["CANDIDATE_COUNT", regs.CANDIDATE_COUNT_CANDIDATE_COUNT_MAX + 1],
                    ["HISTOGRAM_SHIFT", cfg.energy_bits]], "stop": half},
        {"check": {"ERROR": refused, "IRQ_STATUS": regs.IRQ_STATUS_FAULT_MASK
                   | regs.IRQ_STATUS_SEGMENT_DONE_MASK, "SEGMENTS": 1},
         "writes": [["ERROR", refused], ["IRQ_STATUS", regs.IRQ_STATUS_FAULT_MASK]],
         "lut_codes": zeros.tolist(), "stop": len(beats)},
    ]
    with_lut = expected_outputs(cfg, beats, steps).lists
    without = expected_outputs(cfg, beats, [{"stop": len(beats)}]).lists
    assert list_words(cfg, with_lut) != list_words(cfg, without)     # the rewrite matters
    s = run(cfg, frames, beats, steps, "axi-lut", ready_pause=RANDOM(0.3, 4),
            final_check={"ERROR": 0, "LISTS": 3,
                         "IRQ_STATUS": regs.IRQ_STATUS_SEGMENT_DONE_MASK})
    assert s["lists"] == 3


@pytest.mark.slow
@pytest.mark.parametrize("kind", FAULTS)
def test_fault_is_counted_flagged_and_interrupts(kind):
    """One fault of ``kind`` in frame 0: its counter reads 1 and the others 0, its sticky
    bit is set (W1C clears it), the fault interrupt rises three cycles after the faulty beat
    is accepted (monitor register, the register block's event register, then the pending
    bit) and the lists after the fault
    match the model of the stream actually accepted."""
    cfg = make_config(**SCENE_CFG)
    regs = constants_namespace(cfg)
    frames = make_frames("two-targets", cfg, 5, seed=3)
    beats = with_fault(cfg, frames, kind)
    counts = fault_counts(cfg, beats)
    assert counts == {k: int(k == kind) for k in FAULTS}
    mask = getattr(regs, f"ERROR_{kind.upper()}_MASK")
    steps = [{"writes": [["IRQ_ENABLE", regs.IRQ_ENABLE_FAULT_MASK]], "stop": len(beats)}]
    s = run(cfg, frames, beats, steps, f"axi-fault-{kind}",
            final_check={"ERROR": mask, **{f"FAULT_{k.upper()}": v for k, v in counts.items()}})
    rises = [cycle for cycle, level in s["irq_edges"] if level]
    assert len(rises) == 1
    pulses = [i for i, p in enumerate(fault_pulses_of(cfg, beats)) if p]
    assert rises[0] == s["accept_cycles"][pulses[0]] + 3


def test_every_fault_class_in_one_stream():
    """The four faults one after the other (each followed by a clean frame): every counter
    reads 1, every sticky bit is set and cleared by W1C, the fault interrupt rises three
    cycles after the first faulty beat and stays (nobody clears IRQ_STATUS), and the lists
    match the model of the stream accepted."""
    cfg = make_config(**SCENE_CFG)
    regs = constants_namespace(cfg)
    frames = make_frames("two-targets", cfg, 8, seed=3)
    beats = with_fault(cfg, frames[0:2], FAULTS[0])
    for i, kind in enumerate(FAULTS[1:], 1):
        beats = beats + with_fault(cfg, frames[2 * i:2 * i + 2], kind)
    assert fault_counts(cfg, beats) == {k: 1 for k in FAULTS}
    every = sum(getattr(regs, f"ERROR_{k.upper()}_MASK") for k in FAULTS)
    steps = [{"writes": [["IRQ_ENABLE", regs.IRQ_ENABLE_FAULT_MASK]], "stop": len(beats)},
             {"check": {"ERROR": every, **{f"FAULT_{k.upper()}": 1 for k in FAULTS}},
              "writes": [["ERROR", every]], "stop": len(beats)}]
    s = run(cfg, frames, beats, steps, "axi-faults", valid_pause=RANDOM(0.2, 5),
            ready_pause=RANDOM(0.3, 6), final_check={"ERROR": 0})
    rises = [cycle for cycle, level in s["irq_edges"] if level]
    assert len(rises) == 1
    pulses = [i for i, p in enumerate(fault_pulses_of(cfg, beats)) if p]
    assert rises[0] == s["accept_cycles"][pulses[0]] + 3


def fault_pulses_of(cfg, beats):
    from dptbd.sim.axi.stimulus import fault_pulses
    return [any(p.values()) for p in fault_pulses(cfg, beats.first, beats.last)]


def test_segment_interrupt_timing_and_mask():
    """With IRQ_ENABLE.segment_done, irq rises once per segment end (the bench clears
    nothing, so it stays high); with the mask off it never rises but the pending bit is
    set."""
    cfg = make_config(**SCENE_CFG)
    regs = constants_namespace(cfg)
    frames = make_frames("two-targets", cfg, 4, seed=2)
    beats = clean_beats(frames)
    frame = cfg.width * cfg.height
    steps = [{"stop": frame * 2},
             {"check": {"IRQ_STATUS": regs.IRQ_STATUS_SEGMENT_DONE_MASK},
              "writes": [["IRQ_STATUS", regs.IRQ_STATUS_SEGMENT_DONE_MASK],
                         ["IRQ_ENABLE", regs.IRQ_ENABLE_SEGMENT_DONE_MASK]],
              "stop": len(beats)}]
    s = run(cfg, frames, beats, steps, "axi-irq")
    rises = [cycle for cycle, level in s["irq_edges"] if level]
    assert len(rises) == 1                                   # masked during segment 1
    sim = built(cfg, "axi")
    last_of_segment_2 = s["accept_cycles"][len(beats) - 1]
    # segment_done leaves the DP L cycles after its last pixel; the register block registers
    # the pulse, then sets the pending bit: two cycles later
    assert rises[0] == last_of_segment_2 + sim.manifest["dp_latency"] + 2


@pytest.mark.slow
def test_soft_reset_between_segments_restarts_the_core():
    """1.5 segments, CONTROL.soft_reset with the stream idle, then two whole segments: the
    lists are those of the two pieces each from reset; the registers are kept."""
    cfg = make_config(**SCENE_CFG)
    frames = make_frames("two-targets", cfg, 7, seed=4)
    beats = clean_beats(frames)
    frame = cfg.width * cfg.height
    steps = [{"stop": 3 * frame},
             {"soft_reset": True, "stop": len(beats)}]
    s = run(cfg, frames, beats, steps, "axi-soft-reset", valid_pause=RANDOM(0.2, 6))
    assert s["lists"] == 3


def test_run_time_settings_between_and_inside_segments():
    """K, n, s written before the first segment and between segments take effect at the next
    segment start; a K written inside a segment waits for the next one; values out of range
    are refused and change nothing; after a soft reset the written values hold. Lists,
    counters and SATURATED as the model with the gateware's sampling rule gives them."""
    cfg = make_config(**SCENE_CFG)
    regs = constants_namespace(cfg)
    frames = make_frames("two-targets", cfg, 11, seed=11)
    beats = clean_beats(frames)
    frame = cfg.width * cfg.height
    too_big = regs.SEGMENT_FRAMES_SEGMENT_FRAMES_MAX + 1
    steps = [{"writes": [["SEGMENT_FRAMES", 3], ["CANDIDATE_COUNT", 3], ["HISTOGRAM_SHIFT", 4],
                         ["SEGMENT_FRAMES", too_big]], "stop": 3 * frame},      # K = 3
             {"writes": [["SEGMENT_FRAMES", 4], ["CANDIDATE_COUNT", 6], ["HISTOGRAM_SHIFT", 4]],
              "stop": 5 * frame},                                              # K = 4 begins
             {"writes": [["SEGMENT_FRAMES", 2], ["HISTOGRAM_SHIFT", cfg.energy_bits]],
              "stop": 7 * frame},                                              # inside it
             {"soft_reset": True,
              "check": {"SEGMENTS": 2, "LISTS": 2, "SEGMENT_FRAMES": 2, "HISTOGRAM_SHIFT": 4},
              "writes": [["ERROR", regs.ERROR_WRITE_REFUSED_MASK], ["CANDIDATE_COUNT", 2]],
              "stop": len(beats)}]                                             # 2 x K = 2
    expected = expected_outputs(cfg, beats, steps)
    assert expected.counters() == {"FRAMES": 11, "SEGMENTS": 4, "LISTS": 4, "SATURATED": 0}
    default = expected_outputs(cfg, beats, [{"stop": len(beats)}])
    assert len(default.lists) == 5
    s = run(cfg, frames, beats, steps, "axi-settings", valid_pause=RANDOM(0.1, 8),
            ready_pause=RANDOM(0.3, 9),
            final_check={"ERROR": 0, "SEGMENT_FRAMES": 2, "CANDIDATE_COUNT": 2,
                         "HISTOGRAM_SHIFT": 4})
    assert s["lists"] == 4 and s["counts"] == [0, 8, 0, 0]   # list 2: records, capped at C


def test_saturation_events_are_counted():
    """B_E = 8 and a constant scene of 200: frame 0 of a segment holds E = 200, frame 1 adds
    200 to a weight-1 predecessor of 200 and clips at 255 in every pixel, so SATURATED
    counts W*H per segment."""
    cfg = make_config(**dict(SCENE_CFG, energy_bits=8, histogram_shift=3))
    frames = np.full((4, cfg.height, cfg.width), 200)
    beats = clean_beats(frames)
    frame = cfg.width * cfg.height
    assert expected_outputs(cfg, beats, [{"stop": len(beats)}]).saturated == 2 * frame
    s = run(cfg, frames, beats, [{"stop": len(beats)}], "axi-saturation", records=False,
            final_check={"SATURATED": 2 * frame, "SEGMENTS": 2})
    assert s["counters"]["SATURATED"] == 2 * frame


# 12 x 10, K = 1: every frame is a segment (an unprimed empty list, then lists with records)
SWEEP_CFG = dict(width=12, height=10, segment_frames=1, candidate_count=4, candidate_capacity=8,
                 histogram_bits=5, histogram_shift=1)


def test_soft_reset_in_every_cycle_of_a_list():
    """CONTROL.soft_reset landing in every cycle of a list being sent, with random tready
    (``tb_axi.soft_reset_sweep``): a calibration run gives the cycles of the second list
    (first word offered to trailer taken); the sweep then issues the write from 4 cycles
    before that list's first word to its trailer (the pulse lands 2 cycles after the
    write), one iteration per cycle. Every cycle keeps AXI4-Stream; every list is whole,
    or its prefix closed by the cut trailer, or (reset before it began) absent; the last
    iteration (after the last soft reset) is bit-exact; cut lists, whole lists and a list
    cut after each possible number of records all occur."""
    cfg = make_config(**SWEEP_CFG)
    frames = make_frames("two-targets", cfg, 2, seed=1)
    beats = clean_beats(frames)
    lists = expected_outputs(cfg, beats, [{"stop": len(beats)}]).lists
    assert [lst.count for lst in lists] == [0, 4]          # a list with records to cut
    options = dict(testcase="soft_reset_sweep", beats=beats.to_json(), ready_pause=0.4,
                   ready_seed=3)
    sim = built(cfg, "axi")
    calibration = simulate(sim, frames, run_name="axi-sweep-calibration", issue=[], **options)
    assert_passed(calibration)
    timeline = calibration.summary["last_timeline"]          # [cycle, tready, tlast]
    ends = [i for i, (_n, ready, last) in enumerate(timeline) if ready and last]
    assert len(ends) == 2
    first_offer, trailer_taken = timeline[ends[0] + 1][0], timeline[ends[1]][0]
    issue = list(range(first_offer - 4, trailer_taken + 1))
    result = simulate(sim, frames, run_name="axi-sweep", issue=issue, **options)
    assert_passed(result)
    outcomes = result.summary["outcomes"]
    assert len(outcomes) == len(issue) + 1 and outcomes[-1] == "whole"
    assert {"whole", "dropped", *[f"cut {k}" for k in range(1, 5)]} <= set(outcomes[:-1])
