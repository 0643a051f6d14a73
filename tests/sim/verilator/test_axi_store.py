"""``dptbd_axi --state-store axi`` on Verilator (``sim/harness/dptbd_axi_harness.cpp`` built
with ``DPTBD_AXI_STORE``, the state behind the AXI4 memory model of
``sim/harness/axi4_memory.h``): every list word, flag, register read and counter scored
against the golden model (:func:`dptbd.sim.verilator.axi.check_axi`) under random memory
latency, ready and valid, with every AXI4 rule the model sees checked; ``STATE_BASE`` taken
at a soft reset; a soft reset with bursts in flight; error responses counted, flagged,
interrupting, and the lists exact again two segments on; at P = 2 and 4 pixels per clock
(``AXITopStore`` on the wide blocks), the lists bit-exact under random memory latency,
ready and valid.
"""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.hw.flow.register_export import constants_namespace
from dptbd.sim import verilator as V
from dptbd.sim.axi.stimulus import clean_beats, expected_outputs
from dptbd.sim.candidate_scoreboard import list_words
from dptbd.sim.scenarios import make_frames
from dptbd.sim.verilator.axi import OKAY, SLVERR, check_axi, run_axi, step_operations
from helpers.refusals import whole
from helpers.verilator_harness import make_config, needs_verilator

pytestmark = needs_verilator

# 12 x 10, K = 2 (K_max = 4), n = 4, C = 6, 64 bins of width 4: lists with records
SMALL = dict(width=12, height=10, segment_frames=2, max_segment_frames=4, candidate_count=4,
             candidate_capacity=6, histogram_bits=6, histogram_shift=2)
FRAME = 12 * 10

_BUILDS: dict = {}


# at P = 2 and 4: 16 x 12 (a row of 8 or 4 beats), the rest as SMALL
WIDE = dict(SMALL, width=16, height=12)


def store_build(data_bits=64, burst_beats=4, outstanding=4, base_address=0, p=1):
    cfg = make_config(**SMALL) if p == 1 else make_config(**WIDE, pixels_per_clock=p)
    store = cfg.axi_store(data_bits=data_bits, burst_beats=burst_beats,
                          outstanding=outstanding, base_address=base_address)
    if store not in _BUILDS:
        _BUILDS[store] = V.build(cfg, "axi", state_store=store)
    return _BUILDS[store]


def beats_of(frames: int, seed: int = 1):
    cfg = make_config(**SMALL)
    return clean_beats(make_frames("two-targets", cfg, frames, seed=seed))


@pytest.mark.parametrize("store, memory", [
    (dict(), {}),
    (dict(data_bits=32, burst_beats=2, outstanding=2),
     dict(latency=(0, 200), axi_ready=0.6, axi_valid=0.6)),
    # a build of its own: -m slow (the default suite's 128-bit port: the P = 4 test below)
    pytest.param(dict(data_bits=128, burst_beats=2),
                 dict(latency=(100, 400), write_latency=(0, 50), axi_ready=0.8),
                 marks=pytest.mark.slow),
])
def test_lists_are_bit_exact_under_memory_latency_and_stalls(store, memory):
    """K, n and s written between segments, a soft reset in the middle of a frame (words
    and bursts in flight), input gaps and output back-pressure: every word, flag and counter
    the model's, no AXI4 rule broken, nothing left in flight."""
    sim = store_build(**store)
    beats = beats_of(10)
    steps = [{"stop": 2 * FRAME},
             {"writes": [["SEGMENT_FRAMES", 3], ["CANDIDATE_COUNT", 6]], "stop": 5 * FRAME + 37},
             {"soft_reset": "now", "writes": [["SEGMENT_FRAMES", 2]], "stop": len(beats)}]
    result = check_axi(sim, beats, steps, valid_gap=0.1, ready_pause=0.2, seed=5,
                       memory=memory)
    assert result.passed, result.report()
    assert result.board.records_expected >= 2
    counters = result.run.counters
    assert counters["violations"] == 0 and counters["memory_idle"] == 1
    assert counters["read_bursts"] > 0 and counters["write_bursts"] > 0


@pytest.mark.parametrize("p, store, memory", [
    # each P a build of its own: the default suite runs P = 4, -m slow both
    pytest.param(2, dict(data_bits=64, burst_beats=2, outstanding=2),
                 dict(latency=(0, 200), axi_ready=0.6, axi_valid=0.6), marks=pytest.mark.slow),
    (4, dict(data_bits=128, burst_beats=4),
     dict(latency=(100, 400), write_latency=(0, 50), axi_ready=0.7, axi_valid=0.8)),
])
def test_wide_lists_are_bit_exact_under_memory_latency_and_stalls(p, store, memory):
    """P = 2 and 4 (store words of P states): K and n written between segments, a soft
    reset in the middle of a frame with bursts in flight, input gaps, output back-pressure
    and the memory's random latency, ready and valid: every word, flag and counter the
    model's, no AXI4 rule broken, nothing left in flight, every burst in the frame's
    region."""
    sim = store_build(**store, p=p)
    cfg = sim.cfg
    frame = cfg.width * cfg.height
    beats = clean_beats(make_frames("two-targets", cfg, 10, seed=p))
    steps = [{"stop": 2 * frame},
             {"writes": [["SEGMENT_FRAMES", 3], ["CANDIDATE_COUNT", 6]], "stop": 5 * frame + 36},
             {"soft_reset": "now", "writes": [["SEGMENT_FRAMES", 2]], "stop": len(beats)}]
    result = check_axi(sim, beats, steps, valid_gap=0.1, ready_pause=0.2, seed=p,
                       memory=memory)
    assert result.passed, result.report()
    assert result.board.records_expected >= 2
    counters = result.run.counters
    assert counters["violations"] == 0 and counters["memory_idle"] == 1
    assert counters["read_bursts"] > 0 and counters["write_bursts"] > 0
    assert counters["stalled_input_cycles"] > 0
    assert result.run.bursts[:, 2].max() < sim.state_store.frame_bytes


def test_aresetn_abandons_the_bursts_in_flight():
    """aresetn in the middle of a frame with reads and writes in flight (AXI4 lets it drop
    them; the memory model forgets them too): everything after it is the model's again, no
    rule broken."""
    sim = store_build()
    beats = beats_of(8)
    steps = [{"stop": 3 * FRAME + 50}, {"aresetn": 3, "aresetn_wait": 0, "stop": len(beats)}]
    result = check_axi(sim, beats, steps, memory=dict(latency=(50, 150)))
    assert result.passed, result.report()
    assert result.run.counters["violations"] == 0
    # a read taken within 50 cycles before the last beat before aresetn: still unanswered
    cut = int(result.run.accept_cycles[3 * FRAME + 49])
    bursts = result.run.bursts
    reads = bursts[(bursts[:, 1] == 0) & (bursts[:, 0] > cut - 50) & (bursts[:, 0] <= cut)]
    assert len(reads) > 0


def test_soft_reset_waits_for_the_bursts_in_flight():
    """Reads answered 400 cycles after their address: the restart (and the end of
    STATUS.soft_reset_busy) comes only after the last read issued before the request has
    its data, and the reads after it start again where they start after aresetn."""
    sim = store_build()
    beats = beats_of(6)
    steps = [{"stop": 3 * FRAME + 50}, {"soft_reset": "now", "stop": len(beats)}]
    result = check_axi(sim, beats, steps, memory=dict(latency=(400, 400),
                                                      write_latency=(400, 400)))
    assert result.passed, result.report()
    regs = constants_namespace(sim.cfg, sim.state_store)
    ops, _checks = step_operations(sim.cfg, steps, 0, [])
    kinds = [(k, a) for _i, k, a, _d in ops if k in "wrmb"]
    request = int(result.run.op_cycles[kinds.index(("w", regs.REG_CONTROL))])
    waited = int(result.run.op_cycles[kinds.index(("b", regs.REG_STATUS))])
    bursts = result.run.bursts
    reads = bursts[bursts[:, 1] == 0]
    last_read = int(reads[reads[:, 0] <= request, 0].max())
    assert waited >= last_read + 400 + sim.state_store.burst_beats
    # the restarted prefetcher's first read, the one it issues first after aresetn
    again = reads[(reads[:, 0] > request) & (reads[:, 2] == reads[0, 2])]
    assert last_read + 400 + sim.state_store.burst_beats <= again[0, 0] <= waited


def test_state_base_is_taken_at_the_next_soft_reset():
    """STATE_BASE refuses an unaligned address and one whose frame would pass 2**32; a
    written base is used from the next soft reset on (STATE_BASE_ACTIVE), every burst
    before it in the build's region, every burst after it in the new one."""
    sim = store_build(base_address=0)
    store = sim.state_store
    regs = constants_namespace(sim.cfg, store)
    new = 2 * store.burst_bytes * (-(-store.frame_bytes // store.burst_bytes))
    top = 2**32 - store.frame_bytes
    beats = beats_of(6)
    steps = [{"bus": [["w", regs.REG_STATE_BASE, new, 0xF, OKAY],
                      ["w", regs.REG_STATE_BASE, new + 8, 0xF, SLVERR],
                      ["w", regs.REG_STATE_BASE, top - top % store.burst_bytes
                       + store.burst_bytes, 0xF, SLVERR],
                      ["r", regs.REG_STATE_BASE, OKAY, new],
                      ["r", regs.REG_STATE_BASE_ACTIVE, OKAY, 0]], "stop": 3 * FRAME + 20},
             {"soft_reset": "now", "bus": [["r", regs.REG_STATE_BASE_ACTIVE, OKAY, new],
                                          ["r", regs.REG_ERROR, OKAY,
                                           regs.ERROR_WRITE_REFUSED_MASK]],
              "stop": len(beats)}]
    result = check_axi(sim, beats, steps, memory=dict(span=new + store.frame_bytes,
                                                      latency=(0, 30)))
    assert result.passed, result.report()
    ops, _checks = step_operations(sim.cfg, steps, 0, [])
    kinds = [(k, a) for _i, k, a, _d in ops if k in "wrmb"]
    request = int(result.run.op_cycles[kinds.index(("w", regs.REG_CONTROL))])
    waited = int(result.run.op_cycles[kinds.index(("b", regs.REG_STATUS))])
    bursts = result.run.bursts
    before, after = bursts[bursts[:, 0] <= request], bursts[bursts[:, 0] > waited]
    assert len(before) and len(after)
    assert before[:, 2].max() < store.frame_bytes
    assert after[:, 2].min() >= new and after[:, 2].max() < new + store.frame_bytes


def _lists(words: np.ndarray, flags: np.ndarray) -> list[list[int]]:
    """The delivered words cut into lists at ``tlast``."""
    out, current = [], []
    for word, flag in zip(words, flags):
        current.append(int(word))
        if flag & 2:
            out.append(current)
            current = []
    return out


@pytest.mark.parametrize("kind, code", [("read", "SLVERR"), ("write", "SLVERR"),
                                        ("read", "DECERR"), ("write", "DECERR")])
def test_error_responses_are_counted_flagged_interrupt_and_the_lists_recover(kind, code):
    """Every burst whose address is taken in cycles [500, 560) answered with SLVERR or
    DECERR, each the same way (docs/integration.md, "Error responses"): the stream never
    stops (every beat taken, every list sent), ERROR.state_<kind> and the fault interrupt
    rise one cycle after the first error beat / response, the counter counts what the
    memory sent, and every list of a segment that neither it nor the segment before
    touched the error window is the model's."""
    sim = store_build()
    cfg, store = sim.cfg, sim.state_store
    regs = constants_namespace(cfg, store)
    beats = beats_of(12, seed=2)
    reads = ["ERROR", "IRQ_STATUS", "STATE_READ_ERRORS", "STATE_WRITE_ERRORS", "LISTS"]
    ops = [(0, "w", regs.REG_IRQ_ENABLE, regs.IRQ_ENABLE_FAULT_MASK),
           (len(beats), "i", 400, 0),
           *[(len(beats), "r", getattr(regs, f"REG_{name}"), 0) for name in reads]]
    memory = {f"{kind}_error": 1.0, "error_cycles": (500, 560), "error_response": code}
    run = run_axi(sim, beats, ops, memory=memory)
    assert run.status == "done" and run.counters["accepted"] == len(beats)
    assert run.counters["violations"] == 0 and run.counters["memory_idle"] == 1
    got = dict(zip(reads, (int(v) for v in run.op_data[1:])))
    sent = {"read": run.counters["read_error_beats"], "write": run.counters["write_error_bursts"]}
    assert sent[kind] > 0 and sent[{"read": "write", "write": "read"}[kind]] == 0
    assert run.counters[f"{kind}_decerrs"] == (sent[kind] if code == "DECERR" else 0)
    assert got["ERROR"] == getattr(regs, f"ERROR_STATE_{kind.upper()}_MASK")
    assert got["IRQ_STATUS"] == regs.IRQ_STATUS_FAULT_MASK | regs.IRQ_STATUS_SEGMENT_DONE_MASK
    assert (got["STATE_READ_ERRORS"], got["STATE_WRITE_ERRORS"]) == (
        sent["read"], sent["write"])
    first = run.counters[f"first_{kind}_error"]
    # the register block registers the error pulse, then sets the pending bit
    assert int(run.irq_cycles[0]) == first + 2 and len(run.irq_cycles) == 1
    expected = list_words(cfg, expected_outputs(cfg, beats, [{"stop": len(beats)}]).lists)
    delivered = _lists(run.out_words, run.out_flags)
    assert len(delivered) == len(expected) == got["LISTS"] == 6
    # segment s (frames 2s, 2s + 1) is clean if its pixels were all taken before cycle 500
    # or all after 560 (docs/integration.md, "State store in external memory")
    segment = 2 * FRAME
    clean = [run.accept_cycles[(s + 1) * segment - 1] < 500
             or run.accept_cycles[s * segment] >= 560 for s in range(6)]
    exact = [j for j in range(6) if clean[j] and (j == 0 or clean[j - 1])]
    assert len(exact) >= 3 and exact[-1] == 5 and not all(clean)
    for j in exact:
        assert delivered[j] == expected[j], j


def test_memory_settings_need_a_store_build_and_known_keys():
    sim = store_build()
    beats = beats_of(1)
    with pytest.raises(ValueError, match=whole(
            "memory key 'delay': the keys are latency, write_latency, error_cycles, "
            "axi_ready, axi_valid, read_error, write_error, base, span, error_response")):
        run_axi(sim, beats, [], memory={"delay": 3})
    with pytest.raises(ValueError, match=whole(
            "memory error_response 'OKAY': the responses are SLVERR, DECERR")):
        run_axi(sim, beats, [], memory={"error_response": "OKAY"})
    with pytest.raises(ValueError, match=whole(
            "state_store applies to design 'axi' without mutations only")):
        V.build(sim.cfg, "dp", state_store=sim.state_store)
    with pytest.raises(ValueError, match=whole(
            "state_store was made for another configuration than cfg")):
        V.build(make_config(), "axi", state_store=sim.state_store)
