"""``SegmenterWide`` (P = 2, 4) against the word-by-word model ``segment_stream`` — the
lists the P = 1 ``Segmenter`` gives on the same states, bit for bit: random state streams
with input gaps and output back-pressure, the cap and overflow, the clamped top bin,
resynchronised streams, run-time settings per segment, reset; and its exact timing."""

import numpy as np
import pytest

from dptbd.hw.segmenter import Segmenter, scan_cycles
from dptbd.hw.wide.layouts import wide_state_layout
from dptbd.hw.layouts import pack
from dptbd.hw.wide.segmenter import SegmenterWide, segmenter
from dptbd.model.segmentation import segment_stream
from dptbd.model.settings import SegmentSettings as S
from helpers.dp16kd_model import DP16KDModel
from helpers.hw_harness import refused, simulate
from helpers.refusals import whole
from helpers.seg_harness import (SEGMENTER_CASES, check_reset_in_a_scored_frame, make_config,
                                 misaligned_settings_stream, pack_state_rows, run_lists,
                                 scheduled_states, settings_driver, synthetic_states,
                                 truncated_stream)


def pack_state_beats(cfg, states) -> list[int]:
    """``states`` beats of P consecutive rows of ``states`` (the flags of each beat's last
    state; a beat never straddles a flag)."""
    p = cfg.pixels_per_clock
    rows = np.asarray(states)
    assert len(rows) % p == 0 and not rows.reshape(-1, p, 5)[:, :-1, 2:].any()
    layout = wide_state_layout(cfg)
    out = []
    for group in rows.reshape(-1, p, 5):
        fields = {}
        for k, (energy, direction, *_rest) in enumerate(group):
            fields[f"energy_{k}"] = int(energy)
            fields[f"direction_{k}"] = int(direction)
        eol, eof, eos = (int(v) for v in group[-1, 2:])
        out.append(pack(layout, {**fields, "end_of_line": eol, "end_of_frame": eof,
                                 "end_of_segment": eos}, "beat"))
    return out


#: The builds: the generic one and the ECP5 family's (DP16KD banks through a behavioural
#: model, the held increments apart, the emitter's registered cap and staged FIFO).
STYLES = {"generic": {}, "ecp5": {"histogram_style": "dp16kd", "control_style": "registered"}}


def check(cfg, states, *, valid=0.7, ready=0.5, seed=0, settings=None, on_cycle=None,
          style="generic"):
    lists = segment_stream(states, cfg, settings)
    options = STYLES[style]
    dut = SegmenterWide(cfg, **options,
                        dp16kd=DP16KDModel if options.get("histogram_style") == "dp16kd" else None)
    result = run_lists(cfg, dut, dut.states, dut.candidates, pack_state_beats(cfg, states),
                       lists, valid_probability=valid, ready_probability=ready, seed=seed,
                       on_cycle=None if on_cycle is None else on_cycle(dut))
    return lists, result


#: The P = 1 cases (``SEGMENTER_CASES``) at W = 12, lines of whole beats at P = 2 and 4
#: ("k2-all-pixels": C = W x H), with these frame counts
FRAMES = {"k3-n4-narrow-E": 12, "k2-n6-cap6-shift2": 8, "k1-n3-ties": 5, "k4-n0": 8,
          "k2-e12-clamped-top-bin": 8, "k2-all-pixels": 6}


def wide_case(name):
    """(config, frames, E range) of case ``name`` for the wide segmenter."""
    kw, _frames, energies = SEGMENTER_CASES[name]
    kw = dict(kw, width=12)
    if name == "k2-all-pixels":
        kw["candidate_count"] = kw["width"] * kw["height"]
    return kw, FRAMES[name], energies


@pytest.mark.parametrize("style", list(STYLES))
@pytest.mark.parametrize("lanes", [2, 4])
@pytest.mark.parametrize("name", list(FRAMES))
def test_random_streams_match_model(name, lanes, style):
    kw, n_frames, (low, high, *bottom) = wide_case(name)
    cfg = make_config(**kw, pixels_per_clock=lanes)
    rng = np.random.default_rng(len(name) + lanes)
    states = synthetic_states(cfg, n_frames, rng, low=low, high=high,
                              low_fraction=bottom[0] if bottom else 0.0)
    lists, _ = check(cfg, states, seed=len(name) + lanes, style=style)
    assert len(lists) == n_frames // cfg.segment_frames
    assert all(lst.primed and lst.aligned and not lst.missed for lst in lists[1:])
    if name == "k2-n6-cap6-shift2":
        assert any(lst.overflow for lst in lists) and max(lst.count for lst in lists) == 6
    if name == "k2-all-pixels":
        assert [lst.count for lst in lists[1:]] == [48, 48]


def test_heavy_back_pressure():
    cfg = make_config(width=12, height=6, segment_frames=2, candidate_count=16,
                      histogram_bits=4, histogram_shift=4, pixels_per_clock=4)
    states = synthetic_states(cfg, 8, np.random.default_rng(9), high=255)
    lists, _ = check(cfg, states, valid=0.9, ready=0.08, seed=4)
    assert sum(lst.count for lst in lists) > 40


@pytest.mark.parametrize("lanes", [2, 4])
def test_resynchronised_streams_match_model(lanes):
    cfg = make_config(width=12, height=4, segment_frames=3, candidate_count=3,
                      histogram_bits=4, histogram_shift=4, pixels_per_clock=lanes)
    rng = np.random.default_rng(12 + lanes)
    flags = set()
    for pre, keep in [(1, 3), (2, 7), (4, 5), (3, 1), (5, 6)]:
        states = truncated_stream(cfg, rng, pre, keep * lanes, 9, high=255)
        lists, _ = check(cfg, states, valid=0.8, ready=0.6, seed=pre)
        flags |= {(lst.aligned, lst.missed) for lst in lists}
    assert {(False, False), (True, True), (True, False)} <= flags


# ---- run-time settings (docs/gateware.md, "Run-time settings") ---------------------------

@pytest.mark.parametrize("style", list(STYLES))
@pytest.mark.parametrize("lanes", [2, 4])
def test_run_time_settings_per_segment(lanes, style):
    cfg = make_config(width=12, height=4, segment_frames=2, max_segment_frames=4,
                      candidate_count=3, candidate_capacity=6, histogram_bits=4,
                      histogram_shift=4, pixels_per_clock=lanes)
    schedule = [S(2, 3, 4), S(3, 5, 2), S(1, 2, 3), S(4, 0, 5), S(2, 6, 0), S(1, 6, 4),
                S(3, 1, 4)]
    states, settings = scheduled_states(cfg, schedule, np.random.default_rng(lanes), high=255)
    lists, _ = check(cfg, states, valid=0.8, ready=0.6, seed=lanes, settings=settings,
                     on_cycle=settings_driver(cfg, states, settings, lanes), style=style)
    assert len(lists) == len(schedule)
    assert len({lst.threshold for lst in lists}) >= 3


@pytest.mark.parametrize("k, one", [(1, 0), (2, 1)])
def test_first_beat_scored_by_segment_frames_one(k, one):
    """Whether a segment's first beat is scored is ``segment_frames_one``, not a comparison
    of ``segment_frames``: after reset the scan clears the histogram (busy), and the first
    beat waits for it only if ``segment_frames_one`` says it is scored."""
    cfg = make_config(width=12, height=4, segment_frames=2, max_segment_frames=3,
                      histogram_bits=4, pixels_per_clock=2)
    dut = SegmenterWide(cfg)
    readies = []

    async def bench(ctx):
        ctx.set(dut.segment_frames, k)
        ctx.set(dut.segment_frames_one, one)
        ctx.set(dut.states.valid, 1)
        readies.append(ctx.get(dut.states.ready))

    simulate(dut, bench)
    assert readies == [not one]


def test_settings_kept_at_a_misaligned_segment_start():
    """As the P = 1 test of the same name: a cut frame, then segments of K = 3; the
    counters' own segment starts keep K = 1, n = 4, s = 4 until the resync segment's
    end_of_segment."""
    cfg = make_config(width=12, height=4, segment_frames=1, max_segment_frames=3,
                      candidate_count=4, histogram_bits=4, histogram_shift=4,
                      pixels_per_clock=2)
    states, settings = misaligned_settings_stream(cfg, 12)
    lists, _ = check(cfg, states, valid=0.8, ready=0.6, seed=21, settings=settings,
                     on_cycle=settings_driver(cfg, states, settings, 21))
    assert [(lst.aligned, lst.missed) for lst in lists][:2] == [(True, False), (False, False)]
    assert lists[-1].aligned


def test_reset_in_a_scored_frame_clears_the_histogram():
    cfg = make_config(width=12, height=4, segment_frames=2, candidate_count=4,
                      histogram_bits=4, histogram_shift=4, pixels_per_clock=4)
    check_reset_in_a_scored_frame(cfg, SegmenterWide(cfg), pack_state_beats, 12 + 5)


# ---- timing (docs/gateware.md, "P pixels per clock") ---------------------------------------

def expected_timing(cfg, states, lists):
    """Accept cycle of every beat (from the first) and output cycle of every word, valid and
    ready always high and no stall for the scan. A scored beat's lanes to hand out are its
    selected lanes and, on a list's last beat, lane P-1. It is accepted when the selection
    stage is free (empty, or its beat moving on in this cycle), moves on to the funnel at
    the earliest in the next cycle, when the funnel is free (empty, or handing out its last
    lane, not a list's end: max(1, lanes) cycles after it took its beat, one more on a list's
    end); the funnel hands the lanes out one per cycle from the next cycle, each record 2
    cycles after its hand-out, the trailer 3. A beat of another frame is accepted in the
    next cycle."""
    p = cfg.pixels_per_clock
    frame = cfg.width * cfg.height
    k = cfg.segment_frames
    selected = {}
    for s, lst in enumerate(lists):
        base = (s * k + k - 1) * frame
        for r in lst.records:
            selected[base + int(r["row"]) * cfg.width + int(r["col"])] = True
    accepts, outputs = [], []
    cycle, stage_free_at, funnel_free_at = 0, 0, 0
    for beat in range(len(states) // p):
        first = beat * p
        in_scored = (first // frame) % k == k - 1
        if in_scored:
            cycle = max(cycle, stage_free_at)
        accepts.append(cycle)
        if in_scored:
            lanes = [j for j in range(p) if selected.get(first + j)]
            end = bool(states[first + p - 1, 3])
            hand = sorted(set(lanes) | ({p - 1} if end else set()))
            moves = max(cycle + 1, funnel_free_at)
            for i, j in enumerate(hand):
                if j in lanes:
                    outputs.append(moves + 1 + i + 2)
            if end:
                outputs.append(moves + 1 + len(hand) + 2)
            stage_free_at = moves
            funnel_free_at = moves + max(1, len(hand)) + end
        cycle += 1
    return accepts, outputs


@pytest.mark.parametrize("style", list(STYLES))
@pytest.mark.parametrize("lanes", [2, 4])
def test_exact_cycles_k2(lanes, style):
    """K = 2, valid and ready always high: every beat's acceptance and every output word's
    cycle as :func:`expected_timing` says (the scan never stalls: W*H/P >= scan_cycles + P)."""
    cfg = make_config(width=16, height=7, segment_frames=2, candidate_count=30,
                      candidate_capacity=64, histogram_bits=4, histogram_shift=4,
                      pixels_per_clock=lanes)
    assert cfg.frame_beats >= scan_cycles(cfg) + lanes
    states = synthetic_states(cfg, 8, np.random.default_rng(lanes), high=255)
    lists, result = check(cfg, states, valid=1.0, ready=1.0, style=style)
    accepts, outputs = expected_timing(cfg, states, lists)
    start = result.accept_cycles[0]
    assert [c - start for c in result.accept_cycles] == accepts
    assert [c - start for c in result.output_cycles] == outputs
    assert sum(lst.count for lst in lists) > 10
    assert any(b - a > 1 for a, b in zip(accepts, accepts[1:]))   # beats of > 1 record held it


@pytest.mark.parametrize("style", list(STYLES))
@pytest.mark.parametrize("lanes", [2, 4])
def test_k1_stalls_for_the_scan(lanes, style):
    """K = 1: the next frame's first beat waits 2**b + 5 cycles after the last beat at P = 2
    (one more than at P = 1: the banked histogram's merge register), 2**b + 6 at P = 4 (its
    pairs' register too)."""
    cfg = make_config(width=12, height=5, segment_frames=1, candidate_count=0,
                      histogram_bits=4, pixels_per_clock=lanes)
    states = synthetic_states(cfg, 4, np.random.default_rng(3), high=255)
    _, result = check(cfg, states, valid=1.0, ready=1.0, style=style)
    beats = cfg.frame_beats
    accepts = result.accept_cycles
    gaps = [accepts[t * beats] - accepts[t * beats - 1] for t in range(1, 4)]
    assert gaps == [scan_cycles(cfg)] * 3 == [cfg.n_bins + {2: 5, 4: 6}[lanes]] * 3


def test_segmenter_picks_by_p():
    assert isinstance(segmenter(make_config(width=8, height=4)), Segmenter)
    assert isinstance(segmenter(make_config(width=12, height=4, pixels_per_clock=2)),
                      SegmenterWide)


def test_refuses_an_unknown_control_style():
    with refused(ValueError, whole("control_style must be one of ('generic', 'registered'), "
                                   "got 'ecp5'")):
        SegmenterWide(make_config(width=8, height=4, pixels_per_clock=2), control_style="ecp5")


def test_refuses_one_pixel_per_clock():
    with refused(ValueError, whole(
            "SegmenterWide takes pixels_per_clock 2 or 4; at 1 use "
            "dptbd.hw.segmenter.Segmenter (dptbd.hw.wide.segmenter.segmenter picks by P)")):
        SegmenterWide(make_config(width=8, height=4))


@pytest.mark.parametrize("lanes", [2, 4])
def test_same_words_as_the_one_pixel_segmenter(lanes):
    """The P = 1 ``Segmenter`` and ``SegmenterWide`` on the same states (a resync
    included): the same candidate words, in the same order."""
    cfg = make_config(width=12, height=4, segment_frames=2, candidate_count=5,
                      candidate_capacity=6, histogram_bits=4, histogram_shift=4,
                      pixels_per_clock=lanes)
    one = cfg.replace(pixels_per_clock=1)
    states = truncated_stream(cfg, np.random.default_rng(30 + lanes), 3, 5 * lanes, 8,
                              high=255)
    lists = segment_stream(states, cfg)
    narrow = Segmenter(one)
    a = run_lists(one, narrow, narrow.states, narrow.candidates,
                  pack_state_rows(one, states), lists, valid_probability=0.9,
                  ready_probability=0.7, seed=1)
    _, b = check(cfg, states, valid=0.6, ready=0.4, seed=2)
    assert a.outputs == b.outputs and sum(lst.count for lst in lists) > 10
    assert any(lst.overflow for lst in lists) and not all(lst.aligned for lst in lists)
