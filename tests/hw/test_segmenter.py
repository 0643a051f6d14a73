"""``Segmenter`` against the word-by-word model ``segment_stream`` (docs/arithmetic.md §6):
random state streams with input gaps and output back-pressure, stale thresholds, the cap,
saturating counters, the clamped top bin, truncated and resynchronised streams, reset,
and the timing (no stall for K >= 2, the scan stall for K = 1)."""

import numpy as np
import pytest
from amaranth.hdl import ResetInserter, Signal

from dptbd.hw.segmenter import Segmenter, scan_cycles
from dptbd.model.segmentation import segment_stream, threshold_bin
from helpers.dp16kd_model import DP16KDModel
from helpers.hw_harness import refused, simulate
from helpers.refusals import whole
from helpers.seg_harness import (SEGMENTER_CASES, check_reset_in_a_scored_frame, make_config,
                                 misaligned_settings_stream, pack_state_rows, run_lists,
                                 scheduled_states, settings_driver, synthetic_states,
                                 truncated_stream)


def check(cfg, states, *, valid=0.7, ready=0.5, seed=0, **options):
    lists = segment_stream(states, cfg)
    dut = Segmenter(cfg, **options)
    result = run_lists(cfg, dut, dut.states, dut.candidates, pack_state_rows(cfg, states), lists,
                       valid_probability=valid, ready_probability=ready, seed=seed)
    return lists, result


#: the ECP5 build's histogram (DP16KDs, here a behavioural model) and control (the held
#: increment added in the threshold search, the registered cap and list ends), and the
#: registered control alone, besides the default
STYLES = {"memory": {},
          "dp16kd": {"histogram_style": "dp16kd", "control_style": "registered",
                     "dp16kd": DP16KDModel},
          "registered": {"control_style": "registered"}}


def test_refuses_an_unknown_control_style():
    with refused(ValueError, whole("control_style must be one of ('generic', 'registered'), "
                                   "got 'fast'")):
        Segmenter(make_config(width=4, height=3), control_style="fast")


@pytest.mark.parametrize("style", list(STYLES))
@pytest.mark.parametrize("name", list(SEGMENTER_CASES))
def test_random_streams_match_model(name, style):
    kw, n_frames, (low, high, *bottom) = SEGMENTER_CASES[name]
    cfg = make_config(**kw)
    rng = np.random.default_rng(len(name))
    states = synthetic_states(cfg, n_frames, rng, low=low, high=high,
                              low_fraction=bottom[0] if bottom else 0.0)
    lists, _ = check(cfg, states, seed=len(name), **STYLES[style])
    assert len(lists) == n_frames // cfg.segment_frames
    assert not lists[0].primed and lists[0].count == 0 and lists[0].threshold == cfg.n_bins
    assert all(lst.primed and lst.aligned and not lst.missed for lst in lists[1:])
    if name == "k3-n4-narrow-E":      # a one-segment-stale threshold overshoots n …
        assert any(lst.count > cfg.n_candidates for lst in lists)
        # … and the counters saturate (bitlen(C + 1) = 4 bits for C = 8: at 15) without
        # changing T
        assert cfg.bin_count_bits == 4 and lists[1].histogram[0] == 15
    if name == "k2-n6-cap6-shift2":
        assert any(lst.overflow for lst in lists) and max(lst.count for lst in lists) == 6
    if name == "k2-e12-clamped-top-bin":
        assert (states[:, 0] >> 3 > 15).any()
    if name == "k2-all-pixels":
        assert [lst.count for lst in lists[1:]] == [16, 16]


def test_heavy_back_pressure():
    cfg = make_config(width=8, height=6, segment_frames=2, candidate_count=10,
                      histogram_bits=4, histogram_shift=4)
    states = synthetic_states(cfg, 8, np.random.default_rng(9), high=255)
    lists, result = check(cfg, states, valid=0.9, ready=0.08, seed=4)
    assert sum(lst.count for lst in lists) > 20


def test_resynchronised_streams_match_model():
    """Truncated frames put the segmenter's counters off; it realigns at the next
    end_of_segment and flags the lists (aligned = 0, missed = 1) as the model does."""
    cfg = make_config(width=6, height=4, segment_frames=3, candidate_count=3,
                      histogram_bits=4, histogram_shift=4)
    rng = np.random.default_rng(12)
    flags = set()
    for pre, keep in [(1, 7), (2, 23), (4, 12), (3, 1), (5, 18)]:
        states = truncated_stream(cfg, rng, pre, keep, 9, high=255)
        lists, _ = check(cfg, states, valid=0.8, ready=0.6, seed=pre)
        flags |= {(lst.aligned, lst.missed) for lst in lists}
    assert {(False, False), (True, True), (True, False)} <= flags


def test_no_stall_for_k2_and_record_latency():
    """Valid and ready always high: one word per cycle, and each record comes out exactly
    RECORD_LATENCY cycles after its state word was accepted."""
    cfg = make_config(width=8, height=6, segment_frames=2, candidate_count=5,
                      histogram_bits=5)
    states = synthetic_states(cfg, 8, np.random.default_rng(2), high=255)
    lists, result = check(cfg, states, valid=1.0, ready=1.0)
    assert cfg.n_bins + 4 <= cfg.width * cfg.height * (cfg.segment_frames - 1)
    accepts = result.accept_cycles
    assert accepts == list(range(accepts[0], accepts[0] + len(states)))
    frame = cfg.width * cfg.height
    index = []
    for s, lst in enumerate(lists):
        base = (s * cfg.segment_frames + cfg.segment_frames - 1) * frame
        index += [base + int(r["row"]) * cfg.width + int(r["col"]) for r in lst.records]
        index.append(base + frame - 1)               # the trailer: one cycle after the last
    latency = [out - accepts[i] for out, i in zip(result.output_cycles, index)]
    trailers = np.cumsum([lst.count + 1 for lst in lists]) - 1
    assert sum(lst.count for lst in lists) > 5
    for n, lat in enumerate(latency):
        assert lat == Segmenter.RECORD_LATENCY + (1 if n in trailers else 0), n


def test_k1_stalls_for_the_scan():
    """K = 1: every frame is scored; the next frame waits 2**b + 4 cycles for its threshold."""
    cfg = make_config(width=6, height=5, segment_frames=1, candidate_count=3,
                      histogram_bits=4)
    states = synthetic_states(cfg, 4, np.random.default_rng(3), high=255)
    _, result = check(cfg, states, valid=1.0, ready=1.0)
    frame = cfg.width * cfg.height
    accepts = result.accept_cycles
    gaps = [accepts[t * frame] - accepts[t * frame - 1] for t in range(1, 4)]
    assert gaps == [scan_cycles(cfg)] * 3 == [cfg.n_bins + 4] * 3
    assert accepts[frame - 1] - accepts[0] == frame - 1


def test_reset_in_a_scored_frame_clears_the_histogram():
    """rst in the middle of a scored frame: afterwards the first list is unprimed again and
    everything matches the model of the stream sent after the reset."""
    cfg = make_config(width=6, height=4, segment_frames=2, candidate_count=4,
                      histogram_bits=4, histogram_shift=4)
    check_reset_in_a_scored_frame(cfg, Segmenter(cfg), pack_state_rows, 24 + 17)


# ---- run-time settings (docs/gateware.md, "Run-time settings") ---------------------------

def ref_segmenter_lists(cfg, states, settings):
    return segment_stream(states, cfg, settings)


def rtl_segmenter_lists(cfg, states, settings, lists, seed):
    dut = Segmenter(cfg)
    return run_lists(cfg, dut, dut.states, dut.candidates, pack_state_rows(cfg, states), lists,
                     valid_probability=0.8, ready_probability=0.6, seed=seed,
                     on_cycle=settings_driver(cfg, states, settings, seed)(dut))


def settings_cases():
    """(config, schedule): K, n and s change between segments, K = 1 included, n = 0 and
    n = C, s = 0 and large."""
    from dptbd.model.settings import SegmentSettings as S
    yield (dict(width=6, height=4, segment_frames=2, max_segment_frames=4, candidate_count=3,
                candidate_capacity=6, histogram_bits=4, histogram_shift=4),
           [S(2, 3, 4), S(3, 5, 2), S(1, 2, 3), S(4, 0, 5), S(2, 6, 0), S(1, 6, 4), S(3, 1, 4)])
    yield (dict(width=5, height=5, segment_frames=1, max_segment_frames=3, candidate_count=2,
                histogram_bits=3),
           [S(1, 2, 7), S(3, 4, 6), S(2, 1, 5), S(1, 3, 7), S(2, 4, 15)])


@pytest.mark.parametrize("case", range(2))
def test_run_time_settings_per_segment(case):
    kw, schedule = list(settings_cases())[case]
    cfg = make_config(**kw)
    states, settings = scheduled_states(cfg, schedule, np.random.default_rng(case), high=255)
    lists = ref_segmenter_lists(cfg, states, settings)
    rtl_segmenter_lists(cfg, states, settings, lists, seed=case)
    assert len(lists) == len(schedule)
    assert all(lst.primed and lst.aligned for lst in lists[1:])
    assert len({lst.threshold for lst in lists}) >= 3          # the settings made a difference


def test_settings_kept_at_a_misaligned_segment_start():
    """docs/arithmetic.md §6.5a: K = 1 until a frame is cut after 10 words, then a resync's
    segments of K = 3 (n = 1, s = 2). The counters' own segment starts (misaligned) keep
    K = 1, n = 4, s = 4 — the ports carry random values there — until the word after the
    resync segment's end_of_segment takes K = 3: one list per 24 words up to it."""
    cfg = make_config(width=6, height=4, segment_frames=1, max_segment_frames=3,
                      candidate_count=4, histogram_bits=4, histogram_shift=4)
    states, settings = misaligned_settings_stream(cfg, 10)
    lists = ref_segmenter_lists(cfg, states, settings)
    assert [(lst.aligned, lst.missed) for lst in lists] == (
        [(True, False)] + [(False, False)] * 4 + [(True, False)] * 2)
    assert [lst.threshold for lst in lists[1:6]] == [
        threshold_bin(lst.histogram, cfg, 4) for lst in lists[0:5]]
    assert lists[6].threshold == threshold_bin(lists[5].histogram, cfg, 1)
    rtl_segmenter_lists(cfg, states, settings, lists, seed=21)


# ---- the registered control cycle for cycle ----------------------------------------------

def lockstep_outputs(cfg, words, seed, **options):
    """``states.ready`` and ``candidates`` in every cycle of a ``Segmenter(**options)`` (with
    a reset input) under a random stimulus from ``seed``: words offered 80 % of cycles,
    taken 60 %, the settings ports random in range every cycle (``segment_frames_one``
    with K), a reset now and then."""
    rng = np.random.default_rng(seed)
    rst = Signal()
    dut = Segmenter(cfg, **options)
    top = ResetInserter({"sync": rst})(dut)
    trace = []

    async def bench(ctx):
        sent = 0
        while sent < len(words):
            k = int(rng.integers(1, cfg.k_max + 1))
            ctx.set(dut.segment_frames, k)
            ctx.set(dut.segment_frames_one, k == 1)
            ctx.set(dut.candidate_count, int(rng.integers(cfg.record_capacity + 1)))
            ctx.set(dut.histogram_shift, int(rng.integers(cfg.energy_bits)))
            ctx.set(rst, int(rng.random() < 0.001))
            offer = int(rng.random() < 0.8)
            ctx.set(dut.states.valid, offer)
            ctx.set(dut.states.payload.as_value(), words[sent])
            ctx.set(dut.candidates.ready, int(rng.random() < 0.6))
            ready = ctx.get(dut.states.ready)
            trace.append((ready, ctx.get(dut.candidates.valid),
                          ctx.get(dut.candidates.payload.as_value())))
            await ctx.tick()
            sent += offer & ready

    simulate(top, bench)
    return trace


@pytest.mark.parametrize("style", ["registered", "dp16kd"])
def test_registered_control_is_the_generic_cycle_for_cycle(style):
    """The ECP5 structure (``ready`` from registers computed a cycle ahead, …) gives
    ``states.ready`` and ``candidates`` the generic build's values in every cycle: K from 1
    to K_max changing at any time, resyncs (truncated frames) and resets."""
    cfg = make_config(width=5, height=4, segment_frames=2, max_segment_frames=3,
                      candidate_count=3, histogram_bits=3, histogram_shift=4)
    rng = np.random.default_rng(31)
    words = pack_state_rows(cfg, np.concatenate(
        [truncated_stream(cfg, rng, pre, keep, 4, high=255)
         for pre, keep in [(3, 7), (2, 13), (5, 1), (4, 19), (6, 0)]]))
    generic = lockstep_outputs(cfg, words, 7)
    assert lockstep_outputs(cfg, words, 7, **STYLES[style]) == generic
    # not vacuous: ready low (scans, a full FIFO) and records sent
    assert sum(1 - r for r, _v, _p in generic) > 50
    assert sum(v for _r, v, _p in generic) > 40
