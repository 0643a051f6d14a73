"""``dptbd_dp`` at P = 2 and 4 pixels per clock on Verilator (``hw/wide/``): bit for
bit against the golden model, exact cycle counts, payloads wider than 64 bits (the harness's
multi-word beats), the external store of random contents, LUT writes, valid gaps and ready
back-pressure, resets mid-frame scored per pixel by ``check_stream``."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import dptbd.sim.rtl.check as rtl_check
from dptbd.hw.wide import pack_beat, unpack_beat_states, wide_state_layout
from dptbd.hw.layouts import pack, pack_states
from dptbd.sim import verilator as V
from dptbd.sim.rtl.check import Stimulus, beat_state_words, check_frames, split_beats
from helpers.hw_harness import assert_states_equal, lut_writes_for, reference_states
from helpers.verilator_harness import built, make_config, needs_verilator
from helpers.wide_harness import frames_to_beats

pytestmark = needs_verilator

#: (config, payload words per beat in, out): P = 2 in one word; P = 4 with B_in = 16 in two
NARROW = dict(pixels_per_clock=2)                               # 16 x 12, K = 3
WIDE = dict(pixels_per_clock=4, input_bits=16, energy_bits=18)  # 65-bit beats in, 91 out


def beats_in(cfg, sim, frames):
    values = [pack_beat(cfg, pixels, first) for pixels, first in frames_to_beats(cfg, frames)]
    return V.beat_words(values, V.payload_words(sim, "pixels"))


def states_out(cfg, raw):
    return [s for value in V.beat_values(raw.out_words) for s in unpack_beat_states(cfg, value)]


def random_frames(cfg, n, seed):
    return np.random.default_rng(seed).integers(0, cfg.pixel_max + 1,
                                                size=(n, cfg.height, cfg.width))


@pytest.mark.parametrize("kw, words", [(NARROW, (1, 1)), (WIDE, (2, 2))], ids=["p2", "p4-wide"])
@pytest.mark.parametrize("design", ["dp", "core"])
def test_exact_cycles_and_bits(kw, words, design):
    """valid and ready held high: one beat per clock, the first states exactly L cycles
    after the first acceptance, T*W*H/P + L cycles from the first acceptance to the last
    (inclusive)."""
    cfg = make_config(**kw)
    sim = built(cfg, design)
    assert (V.payload_words(sim, "pixels"), V.payload_words(sim, "states")) == words
    assert sim.latency == 14
    frames = random_frames(cfg, 4, seed=7)
    raw = V.run(sim, beats_in(cfg, sim, frames), store_init="random")
    beats = 4 * cfg.frame_beats
    assert raw.status == "done" and len(raw.out_words) == beats == 4 * 192 // cfg.pixels_per_clock
    accept = raw.accept_cycles.astype(np.int64)
    out = raw.out_cycles.astype(np.int64)
    assert accept[0] == 3                                     # rst in cycles 0, 1; ready in 3
    assert (np.diff(accept) == 1).all() and (np.diff(out) == 1).all()
    assert out[0] - accept[0] == 14
    assert out[-1] - accept[0] + 1 == beats + 14
    assert raw.counters["events_frame_done"] == 4 and raw.counters["events_segment_done"] == 1
    assert_states_equal(states_out(cfg, raw), reference_states(cfg, frames))
    if design == "core":
        assert raw.counters["store_faults"] == 0


@pytest.mark.parametrize("kw", [NARROW, WIDE], ids=["p2", "p4-wide"])
def test_gaps_back_pressure_and_lut_writes(kw):
    """The core build of the test above (one build for both): random valid gaps and ready
    back-pressure, the whole LUT rewritten in beat 5 of frame 1 with random codes."""
    cfg = make_config(**kw)
    sim = built(cfg, "core")
    p = cfg.pixels_per_clock
    rng = np.random.default_rng(p)
    old = cfg.weight_codes.astype(np.int64)
    new = rng.integers(0, (1 << cfg.weight_frac_bits) + 1, size=old.shape)
    switch = cfg.width * cfg.height + 5 * p                   # beat 5 of frame 1
    frames = random_frames(cfg, 5, seed=p)
    writes = [(switch // p, a, d) for a, d in lut_writes_for(cfg, old, new)]
    raw = V.run(sim, beats_in(cfg, sim, frames), valid_gap=0.3, ready_pause=0.4, seed=3,
                lut_writes=writes, store_init="random")
    assert raw.status == "done" and raw.counters["lut_writes"] == len(writes) > 0
    assert raw.counters["stalled_input_cycles"] > 0 and raw.counters["paused_output_cycles"] > 0
    expected = reference_states(cfg, frames, [(switch, new)])
    assert not np.array_equal(expected, reference_states(cfg, frames))
    assert_states_equal(states_out(cfg, raw), expected)


def test_refusals(tmp_path):
    sim = built(make_config(**WIDE), "dp")
    with pytest.raises(ValueError, match=r"^words must be a \(beats, 2\) integer array of "
                                         r"uint64 words for this build's 65\.\.128-bit pixels "
                                         r"payloads, got uint64 \(4,\)$"):
        V.run(sim, np.zeros(4, dtype=np.uint64))


def test_beat_words_round_trip():
    values = [0, 1, (1 << 64) | 5, (1 << 90) - 1]
    words = V.beat_words(values, 2)
    assert words.shape == (4, 2) and words[2].tolist() == [5, 1]
    assert V.beat_values(words) == values
    assert V.beat_values(V.beat_words([3, 4], 1)) == [3, 4]


# ---- resets at P > 1: the checker's promise, per pixel ------------------------------------

def mid_frame_resets(cfg, rng, n, span):
    """``n`` resets (cycle, hold 1..5), one in each of ``n`` equal parts of cycles
    20 … 0.6 * span (far enough apart for every epoch to see states), none on a frame
    boundary of the beats accepted at full rate."""
    beats, edges = cfg.frame_beats, np.linspace(20, 0.6 * span, n + 1).astype(int)
    cycles = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        c = int(rng.integers(lo, hi - 20))
        while (c - 3) % beats in (0, beats - 1):
            c += 2
        cycles.append(c)
    return tuple((c, int(rng.integers(1, 6))) for c in cycles)


@pytest.mark.parametrize("kw", [NARROW, WIDE], ids=["p2", "p4-wide"])
@pytest.mark.parametrize("design", ["dp", "core"])
@pytest.mark.parametrize("seed", range(2))
def test_resets_mid_frame_with_gaps_and_back_pressure(kw, design, seed):
    """rst mid-frame under random valid gaps and ready back-pressure: before each reset a
    prefix of the model's states for the pixels accepted before it, after the last one
    exactly the model's for the pixels accepted after it (a new segment), compared per
    pixel (``check_stream`` at P > 1)."""
    cfg = make_config(**kw)
    sim = built(cfg, design)
    frames = random_frames(cfg, 6, seed=10 + seed)
    rng = np.random.default_rng(seed)
    span = int(6 * cfg.frame_beats / (0.7 * 0.6))
    resets = mid_frame_resets(cfg, rng, 2 + seed, span)
    stim = Stimulus(valid_gap=0.3, ready_pause=0.4, seed=seed, resets=resets,
                    store_init="random")
    result = check_frames(sim, frames, stim)
    assert result.passed, result.report
    assert result.epochs == len(resets) + 1
    assert result.words_in == frames.size
    size = cfg.width * cfg.height
    starts = [a for a, _, _ in result.scored]
    # the epochs start on beat boundaries, some mid-frame, and each compared states
    assert all(a % cfg.pixels_per_clock == 0 for a in starts)
    assert any(a % size for a in starts[1:])
    assert all(board.count > 0 for _, _, board in result.scored)
    assert result.words_out == sum(board.count for _, _, board in result.scored)


def test_a_flipped_state_after_a_reset_is_located_in_its_epoch(monkeypatch):
    """At P = 2: state 1 (the second lane) of a beat after the reset flipped in its energy
    is found at its pixel, counted from the first pixel accepted after the reset."""
    cfg = make_config(**NARROW)
    sim = built(cfg, "dp")
    frames = random_frames(cfg, 4, seed=5)
    stim = Stimulus(resets=((200, 2),))
    clean = check_frames(sim, frames, stim)
    assert clean.passed, clean.report
    first_after = int(np.searchsorted(clean.raw.out_cycles, 200))
    local = 2 * 40 + 1                                    # beat 40 after the reset, lane 1
    real = rtl_check.run

    def run(*args, **kwargs):
        raw = real(*args, **kwargs)
        out = raw.out_words.copy()
        out[first_after + local // 2] ^= np.uint64(1 << (cfg.energy_bits + cfg.direction_bits))
        return dataclasses.replace(raw, out_words=out)

    monkeypatch.setattr(rtl_check, "run", run)
    result = check_frames(sim, frames, stim)
    assert not result.passed
    assert result.report.startswith("after reset 1 (cycle 200): first mismatch at output "
                                    f"{local}: ")
    assert "field energy: " in result.report
    assert result.words_out == clean.scored[0][2].count + local


def test_beats_split_per_pixel():
    cfg = make_config(**WIDE)
    sim = built(cfg, "dp")
    beats = [((1, 2, 3, 4), True), ((5, 6, 7, 65535), False)]
    words = V.beat_words([pack_beat(cfg, px, f) for px, f in beats], V.payload_words(sim, "pixels"))
    pixels, first = split_beats(cfg, words)
    assert pixels.tolist() == [1, 2, 3, 4, 5, 6, 7, 65535]
    assert first.tolist() == [True, False, False, False, False, False, False, False]
    fields = {"energy_0": 9, "direction_0": 1, "energy_1": 0, "direction_1": 0,
              "energy_2": 0, "direction_2": 0, "energy_3": 7, "direction_3": 3,
              "end_of_line": 1, "end_of_frame": 1, "end_of_segment": 0}
    value = pack(wide_state_layout(cfg), fields, "beat")
    got = beat_state_words(cfg, V.beat_words([value], 2))
    want = pack_states(cfg, energy=np.array([9, 0, 0, 7]), direction=np.array([1, 0, 0, 3]),
                       end_of_line=np.array([0, 0, 0, 1]), end_of_frame=np.array([0, 0, 0, 1]),
                       end_of_segment=np.zeros(4, dtype=np.int64))
    assert got.tolist() == want.tolist()
