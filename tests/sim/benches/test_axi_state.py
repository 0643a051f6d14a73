"""RTL simulation of ``dptbd_axi`` built with ``m_axis_state`` (cocotb 2 + Icarus): every
per-pixel (E, d) word and every candidate word scored in order against the golden model,
with cocotbext-axi ``AxiStreamSink`` pause generators on both outputs (the broadcast inside
the core: back-pressure on either stalls the DP pipeline), run-time settings and a LUT
rewrite between segments, a soft reset at three cycles of a list; faults and the soft reset in
every cycle of a list behind ``-m slow``.

Builds go to ``build/sim/<config>-axi-state/`` (cached).
"""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from dptbd.hw.flow.register_export import constants_namespace
from dptbd.hw.register_map import FAULTS
from dptbd.sim.axi.stimulus import clean_beats, expected_outputs, fault_counts, with_fault
from dptbd.sim.icarus import simulate
from dptbd.sim.scenarios import make_frames
from helpers.cocotb_harness import CYCLE, assert_passed, built, make_config, random_pause

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")

# 12 x 10, K = 2 (K_max = 4), n = 4, C = 6, 64 bins of width 4
STATE_CFG = dict(width=12, height=10, segment_frames=2, max_segment_frames=4,
                 candidate_count=4, candidate_capacity=6, histogram_bits=6, histogram_shift=2)


def run(cfg, frames, beats, steps, name, **options):
    result = simulate(built(cfg, "axi-state"), frames, testcase="run_stream", run_name=name,
                      beats=beats.to_json(), steps=steps, state_output=True, **options)
    assert_passed(result)
    return result.summary


def test_state_and_candidate_streams_under_back_pressure_on_both():
    """Six frames: two segments of K = 2, then K = 1 and n = 6, then the LUT halved; random
    idle on the input and independent random back-pressure on both outputs."""
    cfg = make_config(**STATE_CFG)
    frames = make_frames("two-targets", cfg, 6, seed=3)
    beats = clean_beats(frames)
    frame = cfg.width * cfg.height
    halved = np.asarray(cfg.weight_codes) // 2
    steps = [{"stop": 4 * frame},
             {"writes": [["SEGMENT_FRAMES", 1], ["CANDIDATE_COUNT", 6]], "stop": 5 * frame},
             {"lut_codes": halved.tolist(), "stop": len(beats)}]
    expected = expected_outputs(cfg, beats, steps)
    assert [lst.count for lst in expected.lists] == [0, 6, 0, 1]      # the lists carry records
    assert len(expected.state_words) == len(beats) and expected.state_first.sum() == 6
    s = run(cfg, frames, beats, steps, "axi-state", valid_pause=random_pause(0.2, 1),
            ready_pause=random_pause(0.4, 2), state_pause=random_pause(0.5, 3),
            final_check={"FRAMES": 6, "SEGMENTS": 4, "LISTS": 4, "ERROR": 0})
    assert s["state_words"] == len(beats) and s["lists"] == 4
    assert s["counters"]["OUTPUT_STALLS"] == s["stalls_seen"]["output"]


@pytest.mark.slow
@pytest.mark.parametrize("kind", FAULTS)
def test_state_stream_after_a_fault_and_a_soft_reset(kind):
    """A fault of ``kind``, then a soft reset and a clean segment; verilog-axis's
    cycle_pause on the state output, random back-pressure on the candidates."""
    cfg = make_config(**STATE_CFG)
    frames = make_frames("two-targets", cfg, 5, seed=4)
    beats = with_fault(cfg, frames[:3], kind)
    clean = clean_beats(frames[3:])
    regs = constants_namespace(cfg)
    steps = [{"stop": len(beats)},
             {"soft_reset": True, "stop": len(beats) + len(clean)}]
    counts = fault_counts(cfg, beats)
    s = run(cfg, frames, beats + clean, steps, f"axi-state-{kind}",
            valid_pause=random_pause(0.2, 5), ready_pause=random_pause(0.3, 6),
            state_pause=CYCLE,
            final_check={"ERROR": getattr(regs, f"ERROR_{kind.upper()}_MASK"),
                         **{f"FAULT_{k.upper()}": v for k, v in counts.items()}})
    assert s["state_words"] == len(beats) + len(clean)


# 12 x 10, K = 1: every frame a segment; the second list (records) is sent while the third
# frame's states are
SWEEP_CFG = dict(width=12, height=10, segment_frames=1, candidate_count=4, candidate_capacity=8,
                 histogram_bits=5, histogram_shift=1)


def _calibrated_sweep():
    """SWEEP_CFG's build, scene and options, with the calibration run's cycles of the second
    list: (first word offered, trailer taken)."""
    cfg = make_config(**SWEEP_CFG)
    frames = make_frames("two-targets", cfg, 3, seed=1)
    beats = clean_beats(frames)
    lists = expected_outputs(cfg, beats, [{"stop": len(beats)}]).lists
    assert [lst.count for lst in lists] == [0, 4, 1]
    options = dict(testcase="soft_reset_sweep", beats=beats.to_json(), ready_pause=0.4,
                   ready_seed=3, state_output=True, state_pause=0.4, state_seed=5)
    sim = built(cfg, "axi-state")
    calibration = simulate(sim, frames, run_name="axi-state-sweep-calibration", issue=[],
                           **options)
    assert_passed(calibration)
    assert calibration.summary["state_outcomes"] == ["whole"]
    timeline = calibration.summary["last_timeline"]          # [cycle, tready, tlast]
    ends = [i for i, (_n, ready, last) in enumerate(timeline) if ready and last]
    assert len(ends) == 3
    first_offer, trailer_taken = timeline[ends[0] + 1][0], timeline[ends[1]][0]
    return cfg, frames, sim, options, first_offer, trailer_taken


@pytest.mark.slow
def test_soft_reset_in_every_cycle_of_a_line_and_a_list():
    """CONTROL.soft_reset landing in every cycle of a list being sent while state lines are
    (``tb_axi.soft_reset_sweep`` on the ``--state-output`` build, independent random tready
    on both outputs): a calibration run gives the cycles of the second list (first word
    offered to trailer taken), the sweep issues the write from 4 cycles before it to its
    trailer, one iteration per cycle. Every cycle keeps AXI4-Stream on both outputs; every
    state packet is a line of W words ending with tlast, the model's words in order but for
    the fillers (tuser[3] only, tdata 0) completing a line the soft reset cut; every list is
    whole, a prefix closed by the cut trailer, or absent; the last iteration is bit-exact on
    both. A line cut after each possible number of words, a list cut after each possible
    number of records, and both in one soft reset, all occur."""
    cfg, frames, sim, options, first_offer, trailer_taken = _calibrated_sweep()
    issue = list(range(first_offer - 4, trailer_taken + 1))
    result = simulate(sim, frames, run_name="axi-state-sweep", issue=issue, **options)
    assert_passed(result)
    outcomes, lines = result.summary["outcomes"], result.summary["state_outcomes"]
    assert len(outcomes) == len(lines) == len(issue) + 1
    assert outcomes[-1] == lines[-1] == "whole"
    assert {"dropped", *[f"cut {k}" for k in range(1, 5)]} <= set(outcomes[:-1])
    assert {"whole", *[f"fill {k}" for k in range(1, cfg.width)]} <= set(lines[:-1])
    assert any(o.startswith("cut") and s.startswith("fill") for o, s in zip(outcomes, lines))


def test_soft_reset_before_inside_and_at_the_end_of_a_list():
    """The sweep above (``-m slow``) at three of its cycles: 4 cycles before the second list's
    first word is offered, midway, and the cycle its trailer is taken; the same checks on
    every iteration (AXI4-Stream on both outputs, lines of W words ending with tlast, lists
    whole, a prefix closed by the cut trailer, or absent), the last bit-exact on both."""
    cfg, frames, sim, options, first_offer, trailer_taken = _calibrated_sweep()
    issue = [first_offer - 4, (first_offer + trailer_taken) // 2, trailer_taken]
    result = simulate(sim, frames, run_name="axi-state-sweep-three", issue=issue, **options)
    assert_passed(result)
    outcomes, lines = result.summary["outcomes"], result.summary["state_outcomes"]
    assert (first_offer, trailer_taken) == (293, 475)
    # before the list: dropped; inside: cut after 2 records while a line is cut after 4 words
    # (filled); at the trailer: dropped; then the bit-exact iteration
    assert outcomes == ["dropped", "cut 2", "dropped", "whole"]
    assert lines == ["fill 4", "fill 4", "fill 11", "whole"]
