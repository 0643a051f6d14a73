"""The compiled RTL simulator (:mod:`dptbd.sim.verilator`): exact cycle counts, the stimulus
the harness takes, and every bad input refused before anything is run. The build cache is
``test_cache.py``.
"""

from __future__ import annotations

import dataclasses
import math
import os
import shutil

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import unpack_candidate
from dptbd.sim import verilator as V
from dptbd.sim.rtl.check import Stimulus, check_frames, check_stream
from dptbd.sim.scenarios import make_frames
from dptbd.sim.scoreboard import expected_words
from dptbd.sim.stimulus import lut_writes, pixel_words

from helpers.verilator_harness import SEG, built, make_config  # noqa: E402

pytestmark = pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")

BASE = make_config(**SEG)


def dp_latency(cfg: DPConfig) -> int:
    """docs/gateware.md, "Latency and throughput"."""
    moves = (2 * cfg.radius + 1) ** 2
    if cfg.weight_frac_bits == 0:
        return 7 + math.ceil(math.log2(moves))
    return 6 + math.ceil(math.log2(cfg.weight_frac_bits + 2)) + math.ceil(math.log2(moves))


def fake_build(tmp_path, cfg=BASE, design="dp", waves=False) -> V.VerilatorBuild:
    """A build whose executable does not exist: any call that gets as far as running it
    fails with FileNotFoundError, so a ValueError proves the input was refused first."""
    return V.VerilatorBuild(cfg, design, tmp_path, tmp_path / "missing-executable",
                            {"latency": 14}, "0" * 64, 0.0, True, waves)


# ---- exact cycle counts ----------------------------------------------------------------

# SEG: BASE, the builds the other tests share (the segmenter's fields do not change dptbd_dp);
# radius 2 and F = 0: the dp builds are check/test_scenes.py's "dp-r2" and "dp-f0"
@pytest.mark.parametrize("design", ["dp", "core"])
@pytest.mark.parametrize("kw,n_frames", [(SEG, 7), ({"radius": 2, "segment_frames": 2}, 5),
                                         ({"weight_frac_bits": 0}, 4)])
def test_exact_cycles_dp_and_core(design, kw, n_frames):
    """valid and ready held high: one pixel per clock, the first result exactly L cycles
    after the first acceptance, T·W·H + L cycles from the first acceptance to the last
    result (inclusive), one result per clock."""
    cfg = make_config(**kw)
    sim = built(cfg, design)
    assert sim.latency == dp_latency(cfg)
    frames = make_frames("table1", cfg, n_frames, seed=2)
    raw = V.run(sim, pixel_words(cfg, frames))
    size = n_frames * cfg.width * cfg.height
    assert raw.status == "done" and len(raw.out_words) == size
    accept = raw.accept_cycles.astype(np.int64)
    out = raw.out_cycles.astype(np.int64)
    assert accept[0] == 3           # rst in cycles 0, 1; pixels.ready low in the next
    assert (np.diff(accept) == 1).all() and (np.diff(out) == 1).all()
    assert out[0] - accept[0] == sim.latency
    assert out[-1] - accept[0] + 1 == size + sim.latency
    assert raw.counters["stalled_input_cycles"] == 1      # cycle 2: ready still low
    assert raw.counters["paused_output_cycles"] == 0
    # segment_begin pulses with the first word of every K-th frame: how many, sum of index + 1
    begins = range(0, size, cfg.segment_frames * cfg.width * cfg.height)
    assert (raw.counters["segment_begins"], raw.counters["segment_begin_words"]) == \
        (len(begins), sum(i + 1 for i in begins))
    np.testing.assert_array_equal(raw.out_words, expected_words(cfg, frames).ravel())
    result = check_frames(sim, frames)
    assert result.passed and result.cycles == size + sim.latency


# 13 x 7: check/test_scenes.py's "segmenter-13x7" build
@pytest.mark.parametrize("kw,segments", [({}, 3), ({"width": 13, "height": 7,
                                                     "histogram_bits": 5,
                                                     "histogram_shift": 2}, 2)])
def test_exact_cycles_segmenter(kw, segments):
    """K >= 2 and (K-1)·W·H >= 2^b + 4: S·K·W·H + L + 1 cycles from the first pixel to the
    last trailer (docs/gateware.md, "Segmenter … Timing"); the first list (empty, unprimed)
    is complete K·W·H + L cycles after the first acceptance."""
    cfg = make_config(**{**SEG, **kw})
    k, size = cfg.segment_frames, cfg.width * cfg.height
    assert (k - 1) * size >= (1 << cfg.histogram_bits) + 4
    sim = built(cfg, "segmenter")
    assert sim.latency == dp_latency(cfg) + 3
    frames = make_frames("two-targets", cfg, segments * k, seed=3)
    raw = V.run(sim, pixel_words(cfg, frames))
    accept = raw.accept_cycles.astype(np.int64)
    out = raw.out_cycles.astype(np.int64)
    assert raw.status == "done" and (np.diff(accept) == 1).all()
    assert out[-1] - accept[0] + 1 == segments * k * size + sim.latency + 1
    kind, fields = unpack_candidate(cfg, int(raw.out_words[0]))
    assert kind == "trailer" and fields["primed"] == 0 and fields["count"] == 0
    assert out[0] - accept[0] == k * size + sim.latency
    result = check_frames(sim, frames)
    assert result.passed, result.report
    assert result.cycles == segments * k * size + sim.latency + 1


# ---- the stimulus the harness takes ----------------------------------------------------

def test_pauses_are_seeded_and_counted():
    cfg = BASE
    sim = built(cfg)
    words = pixel_words(cfg, make_frames("noise", cfg, 3, seed=1))
    a = V.run(sim, words, valid_gap=0.3, ready_pause=0.4, seed=5)
    b = V.run(sim, words, valid_gap=0.3, ready_pause=0.4, seed=5)
    c = V.run(sim, words, valid_gap=0.3, ready_pause=0.4, seed=6)
    np.testing.assert_array_equal(a.out_cycles, b.out_cycles)
    np.testing.assert_array_equal(a.accept_cycles, b.accept_cycles)
    assert not np.array_equal(a.out_cycles, c.out_cycles)
    np.testing.assert_array_equal(a.out_words, c.out_words)
    assert a.counters["paused_output_cycles"] > 0 and a.counters["stalled_input_cycles"] > 0
    # with pauses the count exceeds the no-pause figure
    assert a.out_cycles[-1] - a.accept_cycles[0] + 1 > words.size + sim.latency


def test_lut_writes_before_one_word_keep_their_order():
    """Two writes to one address before one word: the later one is in force (the harness
    writes them in the order given, one per cycle)."""
    cfg = BASE
    sim = built(cfg)
    frames = make_frames("noise", cfg, 2, seed=4)
    rng = np.random.default_rng(0)
    unity = 1 << cfg.weight_frac_bits
    a = rng.integers(0, unity + 1, size=(cfg.n_moves + 1, cfg.n_moves))
    b = unity - a
    writes = [(0, addr, code) for addr, code in lut_writes(cfg, a)] + \
             [(0, addr, code) for addr, code in lut_writes(cfg, b)]
    raw = V.run(sim, pixel_words(cfg, frames), lut_writes=writes)
    assert raw.counters["lut_writes"] == len(writes)
    np.testing.assert_array_equal(
        raw.out_words, expected_words(cfg.with_weight_codes(b), frames).ravel())
    # each run is a new process: the LUT powers up with cfg.weight_codes again
    raw = V.run(sim, pixel_words(cfg, frames))
    np.testing.assert_array_equal(raw.out_words, expected_words(cfg, frames).ravel())


@pytest.mark.parametrize("resets", [((300, 2), (300, 5)), ((300, 10), (303, 1)),
                                    ((300, 3), (303, 2))])
def test_overlapping_resets_hold_rst_for_their_union(resets):
    """Two resets starting in one cycle, one inside another, two back to back: rst is high
    from the first start to the last end, no word is taken meanwhile, and the run ends."""
    cfg = BASE
    sim = built(cfg)
    words = pixel_words(cfg, make_frames("noise", cfg, 3, seed=2))
    raw = V.run(sim, words, resets=resets)
    assert raw.status == "done"
    start = min(c for c, _ in resets)
    end = max(c + h for c, h in resets)              # first cycle with rst low
    accept = raw.accept_cycles.astype(np.int64)
    assert not ((accept >= start) & (accept <= end)).any()    # + 1 cycle after reset
    assert accept[np.searchsorted(accept, start)] == end + 1
    out = raw.out_cycles.astype(np.int64)
    assert not ((out >= start) & (out < end)).any()
    result = check_stream(sim, words, Stimulus(resets=resets))
    assert result.passed, result.report


def test_store_init_random_changes_nothing_on_core():
    cfg = BASE
    sim = built(cfg, "core")
    frames = make_frames("mixed", cfg, 4, seed=9)
    for seed in (1, 2):
        raw = V.run(sim, pixel_words(cfg, frames), store_init="random", seed=seed)
        np.testing.assert_array_equal(raw.out_words, expected_words(cfg, frames).ravel())
        assert raw.counters["store_faults"] == 0


def test_trace_writes_an_fst(tmp_path):
    cfg = make_config()            # the waves build of dptbd sim --waves (commands/test_sim.py)
    sim = V.build(cfg, "dp", waves=True)
    assert sim.waves and "waves" in sim.directory.name
    frames = make_frames("noise", cfg, 2, seed=1)
    path = tmp_path / "waves" / "run.fst"
    result = check_frames(sim, frames, trace=path)
    assert result.passed and path.stat().st_size > 0


# ---- the build cache -------------------------------------------------------------------


# ---- bad input refused before anything is built or run ---------------------------------

@pytest.mark.parametrize("name", ["valid_gap", "ready_pause"])
@pytest.mark.parametrize("value,shown", [(1.0, "1.0"), (1, "1"), (-0.1, "-0.1"), (True, "True"),
                                         (False, "False"), (1.5, "1.5"), (float("nan"), "nan"),
                                         ("0.5", "'0.5'"), (None, "None")])
def test_run_refuses_a_bad_probability(tmp_path, name, value, shown):
    sim = fake_build(tmp_path)
    with pytest.raises(ValueError, match=rf"^{name} must be a probability in \[0, 1\), "
                                         rf"got {shown}$"):
        V.run(sim, np.zeros(4, dtype=np.uint64), **{name: value})
    with pytest.raises(ValueError, match=rf"^{name} must be a probability in \[0, 1\), "
                                         rf"got {shown}$"):
        check_stream(sim, np.zeros(4, dtype=np.uint64), Stimulus(**{name: value}))


@pytest.mark.parametrize("value", [0.0, 0, 0.999, np.float64(0.5)])
def test_probabilities_in_range_pass_the_check(value):
    assert V._check_probability("valid_gap", value) == float(value)


@pytest.mark.parametrize("resets,shown", [
    ([(5000, 1)], "reset at cycle 5000 for 1 cycles"),
    ([(10, 1), (10**9, 3)], "reset at cycle 1000000000 for 3 cycles"),
    ([(1, 4)], "reset at cycle 1 for 4 cycles"),
    ([(0, 1)], "reset at cycle 0 for 1 cycles"),
    ([(100, 0)], "reset at cycle 100 for 0 cycles"),
    ([(100, -2)], "reset at cycle 100 for -2 cycles"),
])
def test_run_refuses_a_reset_outside_the_run(tmp_path, resets, shown):
    sim = fake_build(tmp_path)
    with pytest.raises(ValueError, match=rf"^{shown} is outside the run: cycles 2 … 4999, "
                                         rf"hold >= 1$"):
        V.run(sim, np.zeros(4, dtype=np.uint64), resets=resets, max_cycles=5000)


def test_run_refuses_a_reset_beyond_the_default_budget(tmp_path):
    sim = fake_build(tmp_path)
    words = np.zeros(10, dtype=np.uint64)
    budget = V.cycle_budget(10, 0.0, 0.0, 14 + 64 + 1)
    with pytest.raises(ValueError, match=rf"^reset at cycle {budget} for 1 cycles is outside "
                                         rf"the run: cycles 2 … {budget - 1}, hold >= 1$"):
        V.run(sim, words, resets=[(budget, 1)])


@pytest.mark.parametrize("index", [11, -1, 10**6])
def test_run_refuses_a_lut_write_beyond_the_stream(tmp_path, index):
    sim = fake_build(tmp_path)
    with pytest.raises(ValueError, match=rf"^LUT write before word {index}: the stream has "
                                         rf"10 words$"):
        V.run(sim, np.zeros(10, dtype=np.uint64), lut_writes=[(0, 1, 2), (index, 3, 4)])
    codes = BASE.weight_codes
    with pytest.raises(ValueError, match=rf"^LUT write before word {index}: the stream has "
                                         rf"10 words$"):
        check_stream(sim, np.zeros(10, dtype=np.uint64), Stimulus(lut_changes=((index, codes),)))


@pytest.mark.parametrize("value", ["ones", "Zero", "", None])
def test_run_refuses_an_unknown_store_init(tmp_path, value):
    sim = fake_build(tmp_path, design="core")
    with pytest.raises(ValueError, match=rf"^store_init must be 'zero' or 'random', "
                                         rf"got {repr(value)}$"):
        V.run(sim, np.zeros(4, dtype=np.uint64), store_init=value)


def test_run_refuses_a_trace_without_a_waves_build(tmp_path):
    sim = fake_build(tmp_path)
    with pytest.raises(ValueError, match=r"^trace needs a build made with waves=True$"):
        V.run(sim, np.zeros(4, dtype=np.uint64), trace=tmp_path / "x.fst")
    assert not (tmp_path / "x.fst").exists()


@pytest.mark.parametrize("words,shown", [(np.zeros(3), r"float64 \(3,\)"),
                                         (np.zeros((2, 2), dtype=np.uint64), r"uint64 \(2, 2\)")])
def test_run_refuses_words_that_are_not_a_1d_integer_array(tmp_path, words, shown):
    with pytest.raises(ValueError, match=rf"^words must be a 1-D integer array, got {shown}$"):
        V.run(fake_build(tmp_path), words)


def test_raw_run_rate():
    raw = V.RawRun("done", 100, *(np.zeros(0, dtype=np.uint64),) * 3, {}, 0.5, 1.0)
    assert raw.cycles_per_second == 200
    assert math.isnan(dataclasses.replace(raw, sim_seconds=0.0).cycles_per_second)
    assert os.path.basename(V.HARNESS) == "dptbd_harness.cpp" and V.HARNESS.exists()
