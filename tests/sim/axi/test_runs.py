"""Random runs of ``dptbd_axi`` (:mod:`dptbd.sim.axi.runs`): drawn from the seed only, every
refusal class drawn, the model's register values (ERROR, fault counters) and the list a
soft reset cuts; a few seeds on Verilator, bit-exact, and a wrong model caught."""

from __future__ import annotations

import collections
import dataclasses

import numpy as np
import pytest

from dptbd.hw.register_map import FAULTS, constants_namespace, register_map
from dptbd.sim.axi import runs as axi_runs, stimulus as axi_stimulus
from dptbd.sim.axi.runs import (ACTIONS, AXI_FAULTS, NOW_SWEEP, REFUSALS, check_run,
                                draw_run)
from dptbd.sim.axi.stimulus import (FAULT_KINDS, SETTINGS, CutList, clean_beats,
                                    expected_outputs, fault_counts, with_fault)
from dptbd.sim.campaign import Case
from dptbd.sim.coverage import bins
from dptbd.sim.scenarios import make_frames
from dptbd.sim.verilator.axi import check_axi, fault_pulse_array
from helpers.verilator_harness import HAVE_VERILATOR, built, make_config, needs_verilator

# the configuration of tests/sim/verilator/test_axi.py (one build): 12 x 10, K = 2 of
# K_max = 4, n = 4, C = 6, 64 bins of width 4
SMALL = dict(width=12, height=10, segment_frames=2, max_segment_frames=4, candidate_count=4,
             candidate_capacity=6, histogram_bits=6, histogram_shift=2)
CASE = Case("axi-12x10", SMALL, "axi", 30, 4, AXI_FAULTS)

def test_a_run_is_its_seed():
    a, b, c = draw_run(CASE, 5), draw_run(CASE, 5), draw_run(CASE, 6)
    for name in ("pixel", "first", "last"):
        assert np.array_equal(getattr(a.beats, name), getattr(b.beats, name))
    assert a.steps == b.steps and a.notes == b.notes and a.drawn == b.drawn
    assert (a.valid_gap, a.ready_pause) == (b.valid_gap, b.ready_pause)
    assert a.steps != c.steps
    assert a.steps[-1]["stop"] == len(a.beats) and "check" in a.steps[-1]


def test_every_class_is_drawn_over_twenty_seeds():
    drawn = collections.Counter()
    plans = [draw_run(CASE, seed) for seed in range(20)]
    for plan in plans:
        drawn.update(plan.drawn)
    assert dict(drawn) == {
        "settings": 73, "no_strobe": 19, "no_sof": 20, "irq_enable": 23, "lut_table": 47,
        "lut_entry": 53, "soft_reset": 19, "soft_reset_now": 170, "aresetn": 12,
        "aresetn_now": 15, "clear_counters": 20, "w1c_error": 24, "w1c_irq": 31, "check": 84,
        "setting_range": 50, "setting_strobe": 23, "lut_code": 51, "lut_strobe": 28,
        "unaligned_write": 26, "unaligned_read": 38, "lut_read": 23, "unmapped_read": 25,
        "unmapped_write": 28, "read_only_write": 31, "sof_unexpected": 9, "frame_short": 10,
        "frame_long": 9, "line_length": 20}
    # a sweep of soft resets with words in flight in each run without input gaps (seeds
    # 0, 1, 2, 9, 10, 11, 18, 19), the j-th after j idle cycles
    sweeps = {seed: [step["soft_reset_wait"] for step in plan.steps
                     if step.get("soft_reset") == "now" and len(step) == 3]
              for seed, plan in enumerate(plans)}
    assert [seed for seed, waits in sweeps.items() if waits == list(range(NOW_SWEEP))] == \
        [0, 1, 2, 9, 10, 11, 18, 19]
    assert all(plan.valid_gap == 0 for seed, plan in enumerate(plans) if seed % 9 < 3)
    assert {(bins.band(p.valid_gap), bins.band(p.ready_pause)) for p in plans} == {
        (g, b) for g, *_ in bins.BANDS for b, *_ in bins.BANDS}
    assert set(drawn) == {*ACTIONS, *REFUSALS, *FAULT_KINDS}
    # every range refusal of every writable register, every refused LUT code and strobe
    # (over 30 seeds)
    cfg, regmap = CASE.cfg, register_map(CASE.cfg)
    unity = 1 << cfg.weight_frac_bits
    refused, codes, strobes = set(), set(), set()
    for plan in plans + [draw_run(CASE, seed) for seed in range(20, 30)]:
        for step in plan.steps:
            for name, value in step.get("writes", []):
                lo, hi = (regmap[name].fields[0].limits if regmap[name].kind == "setting"
                          else (0, 2**32 - 1))
                if value < lo or value > hi:
                    refused.add((name, "ones" if value == 2**32 - 1 else
                                 "below" if value < lo else "above"))
            for _p, _m, code, strobe in step.get("lut_writes", []):
                (codes.add(code) if code > unity else None)
                strobes.add(strobe)
    assert refused == {(name, side) for name in (*SETTINGS, "VIDEO_INPUT")
                       for side in ("above", "ones")} | {("SEGMENT_FRAMES", "below")}
    assert codes == {unity + 1, (1 << cfg.weight_bits) - 1, 2**32 - 1}
    assert strobes == {0, 1, 7, 8, 0xE, 0xF}


def test_a_case_draws_only_its_faults():
    case = dataclasses.replace(CASE, faults=())
    drawn = collections.Counter()
    for seed in range(10):
        plan = draw_run(case, seed)
        drawn.update(plan.drawn)
        assert fault_counts(case.cfg, plan.beats) == {k: 0 for k in FAULTS}
        assert not any(k in step for step in plan.steps
                       for k in ("writes", "lut_codes", "lut_writes", "soft_reset",
                                 "aresetn", "clear_counters"))
    assert {k for k, v in drawn.items() if v} == {"check", "w1c_error", "w1c_irq"}


def fault_scene(cfg):
    """Two clean frames, two frames of which the first is cut short, one clean frame."""
    frames = make_frames("two-targets", cfg, 5, seed=2)
    return (clean_beats(frames[:2]) + with_fault(cfg, frames[2:4], "frame_short")
            + clean_beats(frames[4:]))


def test_error_and_fault_counters_follow_pulses_refusals_and_clears():
    cfg = make_config(**SMALL)
    regs = constants_namespace(cfg)
    beats = fault_scene(cfg)
    frame = cfg.width * cfg.height
    model = {"ERROR": "model", "FAULT_FRAME_SHORT": "model", "FAULT_FRAME_LONG": "model"}
    steps = [{"writes": [["SEGMENT_FRAMES", 0]], "stop": 2 * frame},
             {"check": dict(model), "bus": [["w", regs.REG_ERROR, regs.ERROR_WRITE_REFUSED_MASK,
                                             0xF, 0]], "stop": len(beats)},
             {"check": dict(model), "clear_counters": True, "stop": len(beats)},
             {"check": dict(model), "stop": len(beats)}]
    pulses = axi_runs.fill_checks(cfg, beats, steps)
    assert pulses.sum(axis=0).tolist() == [0, 1, 0, 0]
    assert [s["check"] for s in steps[1:]] == [
        {"ERROR": regs.ERROR_WRITE_REFUSED_MASK, "FAULT_FRAME_SHORT": 0, "FAULT_FRAME_LONG": 0},
        {"ERROR": regs.ERROR_FRAME_SHORT_MASK, "FAULT_FRAME_SHORT": 1, "FAULT_FRAME_LONG": 0},
        {"ERROR": regs.ERROR_FRAME_SHORT_MASK, "FAULT_FRAME_SHORT": 0, "FAULT_FRAME_LONG": 0}]
    if HAVE_VERILATOR:
        result = check_axi(built(cfg, "axi"), beats, steps, valid_gap=0.3, ready_pause=0.3)
        assert result.passed, result.report()
        assert result.expected_counters["FAULT_FRAME_SHORT"] == 0      # cleared after it


def test_the_monitor_restarts_at_a_soft_reset_and_no_sof_hides_frame_long():
    cfg = make_config(**SMALL)
    beats = clean_beats(make_frames("two-targets", cfg, 6, seed=1))
    mid_line = [{"stop": 414}, {"soft_reset": True, "stop": len(beats)}]
    line = [{"stop": 432}, {"soft_reset": True, "stop": len(beats)}]
    assert fault_pulse_array(cfg, beats, mid_line).sum(axis=0).tolist() == [1, 0, 1, 1]
    assert fault_pulse_array(cfg, beats, line).sum(axis=0).tolist() == [0, 1, 1, 0]
    no_sof = [{"stop": 400}, {"writes": [["VIDEO_INPUT", 1]], "stop": 432},
              {"soft_reset": True, "stop": len(beats)}]            # as `line`, no frame_long
    assert fault_pulse_array(cfg, beats, no_sof).sum(axis=0).tolist() == [0, 1, 0, 0]


@needs_verilator
def test_a_few_runs_are_bit_exact():
    """Four seeds of the small case: every candidate word, flag, response and checked read;
    the bins they fill (a failed run would fill none)."""
    outcomes = [check_run(CASE, seed) for seed in range(4)]
    assert [o.report for o in outcomes if not o.passed] == []
    assert sum(o.words_in for o in outcomes) == sum(len(draw_run(CASE, s).beats)
                                                    for s in range(4))
    merged = bins.merge(*(o.bins for o in outcomes))
    assert {k: v for k, v in merged.items() if not k.startswith("stall")} == SLICE_BINS
    # seeds 0 … 3: gaps none with back-pressure none, light, heavy; gaps light without
    # back-pressure; no LUT written inside a first or last row, no saturation (B_E = 16)
    drawn = {("none", "none"), ("none", "light"), ("none", "heavy"), ("light", "none")}
    assert bins.empty_bins(merged) == [
        f"stall: gaps {g}, back-pressure {b}, {p}" for g, *_ in bins.BANDS
        for b, *_ in bins.BANDS if (g, b) not in drawn for p in bins.POSITIONS] + [
        "LUT: written in the first row", "LUT: written in the last row", bins.SATURATION]


SLICE_BINS = {
    **{bins.soft_reset_bin(k): hits for k, hits in enumerate(
        [16, 4, 2, 3, 3, 3, 3, 4, 3, 3, 2, 3, 4, 3, 4, 3, 2, 1])},
    "aresetn: 0 words in flight": 3, "fault: sof_unexpected recovered": 32,
    "fault: frame_short recovered": 5, "fault: frame_long recovered": 28,
    "fault: line_length recovered": 47, "LUT: written between frames": 4,
    "LUT: written in the first row": 0, "LUT: written in a middle row": 5,
    "LUT: written in the last row": 0, "LUT: code 0": 14, "LUT: code 2**F - 1": 5,
    "LUT: code 2**F (the largest)": 13, bins.SATURATION: 0,
    "lists: 0 records (empty)": 51, "lists: exactly n records (0 < n < C)": 2,
    "lists: C records (at capacity)": 6, "lists: overflowing (more than C)": 4,
    bins.TIES: 2, "register: SEGMENT_FRAMES value out of range": 3,
    "register: CANDIDATE_COUNT value out of range": 6,
    "register: HISTOGRAM_SHIFT value out of range": 2,
    "register: VIDEO_INPUT value out of range": 5, "register: LUT value out of range": 4,
    "register: LUT write without wstrb = 1111": 3, "register: LUT read": 5,
    "register: write to a constant register": 1, "register: write to a counter": 2,
    "register: write to the status register": 2, "register: unaligned write": 3,
    "register: unaligned read": 10, "register: unmapped write": 5,
    "register: unmapped read": 5}


def _register_bins(plan, keep=lambda op: True):
    """The register bins of a plan (its soft resets taken as drained: no cycles here), of
    its raw bus operations only those ``keep`` keeps."""
    steps = [{**step, "soft_reset": True} if step.get("soft_reset") else dict(step)
             for step in plan.steps]
    for step in steps:
        step["bus"] = [op for op in step.get("bus", []) if keep(op)]
    counts = bins.axi_bins(CASE.cfg, plan.beats, steps, passed=True, latency=17)
    return {k: v for k, v in counts.items() if k.startswith("register: ")}


def test_the_register_bins_count_the_refusals_the_plan_drew():
    """Per refusal class drawn (:data:`REFUSALS`), the hits of its bins; without the plans'
    unmapped reads their bin stays empty, and the verdict names it alone."""
    plans = [draw_run(CASE, seed) for seed in range(8)]
    for plan in plans:
        hits = {k[len("register: "):]: v for k, v in _register_bins(plan).items()}
        d = plan.drawn
        assert sum(hits[f"{name} value out of range"] for name in (*SETTINGS, "VIDEO_INPUT")) \
            == d["setting_range"] + d["setting_strobe"]
        assert (hits["LUT value out of range"], hits["LUT write without wstrb = 1111"],
                hits["LUT read"], hits["unaligned write"], hits["unaligned read"],
                hits["unmapped write"], hits["unmapped read"]) == (
            d["lut_code"], d["lut_strobe"], d["lut_read"], d["unaligned_write"],
            d["unaligned_read"], d["unmapped_write"], d["unmapped_read"])
        assert hits["write to a constant register"] + hits["write to a counter"] + \
            hits["write to the status register"] == d["read_only_write"]
    assert bins.empty_bins(bins.merge(*map(_register_bins, plans))) == []
    regs = register_map(CASE.cfg)
    lut = regs.window("LUT")
    mapped = {r.address for r in regs.registers}
    unmapped_read = (lambda op: op[0] == "r" and op[1] % 4 == 0 and op[1] not in mapped
                     and not lut.base <= op[1] < lut.end)
    empty = bins.empty_bins(bins.merge(*(_register_bins(plan, lambda op: not unmapped_read(op))
                                         for plan in plans)))
    assert bins.empty_message(empty) == "functional coverage: 1 empty bin: register: unmapped read"


@needs_verilator
def test_a_wrong_model_fails_the_run(monkeypatch):
    """The check can fail: without the cut list, or with a wrong ERROR value, a run fails
    and its report names the seed and what differs."""
    seed = next(s for s in range(20) if any(
        isinstance(lst, CutList) and lst.drained for lst in expected_outputs(
            CASE.cfg, draw_run(CASE, s).beats, draw_run(CASE, s).steps, cut_lists=True).lists))
    assert check_run(CASE, seed).passed
    monkeypatch.setattr(axi_stimulus, "_cut_list", lambda *args: None)
    outcome = check_run(CASE, seed)
    assert not outcome.passed and outcome.report.startswith(f"seed {seed}: done; ")
    monkeypatch.undo()
    fill = axi_runs.fill_checks

    def wrong_error(cfg, beats, steps, store=None):
        pulses = fill(cfg, beats, steps, store)
        steps[-1]["check"]["ERROR"] ^= 1 << 31
        return pulses

    monkeypatch.setattr(axi_runs, "fill_checks", wrong_error)
    outcome = check_run(CASE, 0)
    assert not outcome.passed and "read ERROR = " in outcome.report


@needs_verilator
@pytest.mark.slow
def test_settings_at_a_misaligned_segment_start_after_a_resync():
    """K = 1 build (9 x 7, r = 2): frame 0 cut after 1.5 lines (sof_unexpected), K set to 3
    at beat 25; the segmenter's next segment start (word 63) is one its counters reach on
    their own (misaligned) while the DP input has begun its next segment (beat 76, K = 3):
    the segmenter keeps K = 1 until it realigns (docs/arithmetic.md §6.5a), in the model
    and the RTL alike (they differed when the RTL took the latest DP segment start's K)."""
    cfg = make_config(width=9, height=7, segment_frames=1, max_segment_frames=3,
                      candidate_capacity=2, candidate_count=1, histogram_bits=4, radius=2,
                      weight_frac_bits=3)
    beats = with_fault(cfg, make_frames("two-targets", cfg, 12, seed=1), "sof_unexpected")
    steps = [{"stop": 25}, {"writes": [["SEGMENT_FRAMES", 3]], "stop": len(beats)}]
    result = check_axi(built(cfg, "axi"), beats, steps)
    assert result.passed, result.report()

