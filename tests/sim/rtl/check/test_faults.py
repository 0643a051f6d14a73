"""Compiled RTL runs scored against the golden model (:mod:`dptbd.sim.rtl.check`): every fault
class against the promise of docs/gateware.md ("Reset and resynchronisation", "Weight LUT
write protocol"): resets at random cycles, framing faults, LUT and settings writes at run
time, a random external store."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

import dptbd.sim.rtl.check as rtl_check
from dptbd.hw.candidate_layout import unpack_candidate
from dptbd.sim import verilator as V
from dptbd.sim.rtl.check import Stimulus, check_stream, lut_change_words
from dptbd.sim.scenarios import make_frames
from dptbd.sim.scoreboard import expected_words
from dptbd.sim.stimulus import pixel_words
from dptbd.sim.stream_model import expected_stream, split_words

from helpers.verilator_harness import SEG, assert_passed, built, make_config, scene_words

pytestmark = pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")

BASE = make_config(**SEG)


def random_resets(rng, span, n):
    cycles = np.sort(rng.choice(np.arange(20, span), size=n, replace=False))
    return tuple((int(c), int(rng.integers(1, 6))) for c in cycles)


@pytest.mark.parametrize("seed", range(6))
def test_dp_reset_at_random_cycles_prefix_before_exact_after(seed):
    """Checked here without check_stream: the outputs before each reset are a prefix of the
    model's output for the words accepted before it, and the outputs after the last reset
    equal the model's for the words accepted after it, from a new segment."""
    cfg = BASE
    sim = built(cfg)
    words = scene_words(cfg)
    rng = np.random.default_rng(seed)
    gap, pause = [(0.0, 0.0), (0.2, 0.3)][seed % 2]
    span = int(words.size / ((1 - gap) * (1 - pause)))
    resets = random_resets(rng, span, 1 + seed % 3)
    raw = V.run(sim, words, valid_gap=gap, ready_pause=pause, seed=seed, resets=resets)
    assert raw.status == "done"
    accept = raw.accept_cycles
    assert (accept != rtl_check.NEVER).all()
    pixels, first = split_words(cfg, words)
    bounds = [0] + [c for c, _ in resets] + [2**63]
    words_before = 0
    for e in range(len(bounds) - 1):
        lo, hi = bounds[e], bounds[e + 1]
        took = (accept >= lo) & (accept < hi)
        idx = np.flatnonzero(took)
        assert idx.size == 0 or (idx[0] == words_before and np.all(np.diff(idx) == 1))
        words_before += idx.size
        came = raw.out_words[(raw.out_cycles >= lo) & (raw.out_cycles < hi)]
        want = expected_stream(cfg, pixels[idx], first[idx]).words
        if e < len(bounds) - 2:
            assert came.size <= want.size
            np.testing.assert_array_equal(came, want[:came.size])
        else:
            np.testing.assert_array_equal(came, want)
    assert words_before == words.size
    result = check_stream(sim, words, Stimulus(gap, pause, seed, resets))
    assert_passed(result)
    assert result.epochs == len(resets) + 1


@pytest.mark.parametrize("seed", range(4))
def test_segmenter_reset_at_random_cycles(seed):
    cfg = BASE
    sim = built(cfg, "segmenter")
    words = scene_words(cfg, n_frames=12, seed=seed)
    rng = np.random.default_rng(100 + seed)
    resets = random_resets(rng, words.size, 1 + seed % 2)
    result = check_stream(sim, words, Stimulus(0.2, 0.3, seed, resets))
    assert_passed(result)
    assert result.epochs == len(resets) + 1 and result.words_in == words.size


def test_segmenter_reset_in_a_scored_frame_after_records():
    """A reset while the scored frame's records stream out: the records before it are a
    prefix of that list; the next list is unprimed."""
    cfg = BASE
    sim = built(cfg, "segmenter")
    words = scene_words(cfg, n_frames=12, seed=1)
    clean = V.run(sim, words)
    kinds = [unpack_candidate(cfg, int(w))[0] for w in clean.out_words]
    # the first record of segment 2's list (lists 0, 1 end with trailers before it)
    trailers = [i for i, k in enumerate(kinds) if k == "trailer"]
    record = trailers[1] + 1
    assert kinds[record] == "record" and kinds[record + 1] == "record"
    cycle = int(clean.out_cycles[record + 1]) + 1            # after two records came out
    result = check_stream(sim, words, Stimulus(resets=((cycle, 3),)))
    assert_passed(result)
    assert result.report.startswith(f"{record + 2} of ")


@pytest.mark.parametrize("design", ["dp", "segmenter"])
@pytest.mark.parametrize("fault", ["first-mid-frame", "short-frame", "long-frame",
                                   "first-on-second-word", "no-first-flags"])
@pytest.mark.parametrize("seed", range(2))
def test_framing_faults(design, fault, seed):
    cfg = BASE
    size = cfg.width * cfg.height
    sim = built(cfg, design)
    words = scene_words(cfg, n_frames=9, seed=seed)
    rng = np.random.default_rng(seed)
    at = int(rng.integers(1, 6)) * size + int(rng.integers(1, size - 1))
    one = np.uint64(1 << cfg.input_bits)
    if fault == "first-mid-frame":
        words = words.copy()
        words[at] |= one
    elif fault == "short-frame":
        words = np.concatenate([words[:at], words[at + int(rng.integers(1, 40)):]])
    elif fault == "long-frame":
        extra = words[at:at + int(rng.integers(1, 40))] & ~one
        words = np.concatenate([words[:at], extra, words[at:]])
    elif fault == "first-on-second-word":
        words = words.copy()
        words[1] |= one
    else:
        words = words & ~one
    pixels, first = split_words(cfg, words)
    runs = expected_stream(cfg, pixels, first).runs
    complete = all(r.complete for r in runs)
    assert complete == (fault == "no-first-flags")
    result = check_stream(sim, words, Stimulus(0.2, 0.4, seed))
    assert_passed(result)
    assert result.words_in == words.size


def random_codes(cfg, rng):
    return rng.integers(0, (1 << cfg.weight_frac_bits) + 1, size=(cfg.n_moves + 1, cfg.n_moves))


@pytest.mark.parametrize("design", ["dp", "segmenter"])
@pytest.mark.parametrize("where", ["between-frames", "mid-frame", "both", "with-reset"])
def test_run_time_lut_writes(design, where):
    cfg = BASE
    size = cfg.width * cfg.height
    sim = built(cfg, design)
    words = scene_words(cfg, n_frames=9, seed=2)
    rng = np.random.default_rng(len(where))
    a, b = random_codes(cfg, rng), random_codes(cfg, rng)
    changes = {
        "between-frames": lut_change_words([(1, a), (4, b)], size),
        "mid-frame": ((size + 77, a), (4 * size + 5, b)),
        "both": ((2 * size, a), (2 * size + 100, b), (7 * size, cfg.weight_codes)),
        "with-reset": ((size + 30, a), (6 * size, b)),
    }[where]
    resets = ((900, 2),) if where == "with-reset" else ()
    result = check_stream(sim, words, Stimulus(0.1, 0.3, 3, resets, changes))
    assert_passed(result)
    assert result.raw.counters["lut_writes"] == len(changes) * cfg.lut_entries
    if design == "dp" and not resets:        # the writes do show in the words
        frames = make_frames("two-targets", cfg, 9, seed=2)
        plain = expected_words(cfg, frames).ravel()
        first_change = min(i for i, _ in changes)
        np.testing.assert_array_equal(result.raw.out_words[:first_change], plain[:first_change])
        assert not np.array_equal(result.raw.out_words, plain)


def settings_changes(cfg, size, rng, n_frames):
    """Run-time (K, n, s) written at random words (between and inside frames): each takes
    effect at the next segment start."""
    from dptbd.model.settings import SegmentSettings

    at = np.sort(rng.choice(np.arange(1, n_frames * size), size=6, replace=False))
    at[:2] = (size, 4 * size)                      # two at frame starts
    return tuple((int(i), SegmentSettings(int(rng.integers(1, cfg.k_max + 1)),
                                          int(rng.integers(0, cfg.record_capacity + 1)),
                                          int(rng.integers(0, cfg.energy_bits))))
                 for i in np.sort(at))


@pytest.mark.parametrize("design", ["dp", "segmenter"])
@pytest.mark.parametrize("resets", [False, True])
def test_run_time_settings(design, resets):
    """K, n and s changed between segments and mid-segment: every output word equals the
    stream model's, and (without resets) so do the counts of the event pulses."""
    cfg = BASE
    size = cfg.width * cfg.height
    sim = built(cfg, design)
    rng = np.random.default_rng(7 + resets)
    words = pixel_words(cfg, make_frames("two-targets", cfg, 14, seed=4))
    changes = settings_changes(cfg, size, rng, 14)
    stimulus = Stimulus(0.2, 0.4, 5, ((1500, 3),) if resets else (),
                        settings_changes=changes)
    result = check_stream(sim, words, stimulus)
    assert_passed(result)
    counters = result.raw.counters
    pixels, first = split_words(cfg, words)
    exp = expected_stream(cfg, pixels, first, settings_changes=dict(changes))
    assert len({tuple(row) for row in exp.settings}) >= 3      # several settings in force
    if not resets:
        assert counters["events_frame_done"] == 14
        assert counters["events_segment_done"] == exp.fields[:, 4].sum() >= 4
        if design == "segmenter":
            assert counters["events_list_done"] == counters["events_segment_done"]
            assert result.words_out > counters["events_list_done"]      # records too


@pytest.mark.parametrize("after", [1, 3, 12])
def test_settings_of_a_segment_cut_at_once_by_a_resync(after):
    """Segment 1 begins at word 576 with K = 1, n = 2, s = 3; other settings are written
    at word 577 and a resync comes ``after`` words into segment 1, while its first word is
    still in the DP pipeline. The segmenter takes segment 1's settings at its first word
    (docs/arithmetic.md §6.5a), not the resync segment's, which began later at the DP
    input: every word equals the stream model's."""
    from dptbd.model.settings import SegmentSettings

    cfg = BASE
    sim = built(cfg, "segmenter")
    words = pixel_words(cfg, make_frames("two-targets", cfg, 9, seed=5))
    start = 3 * cfg.width * cfg.height
    words[start + after] |= np.uint64(1 << cfg.input_bits)
    changes = ((start, SegmentSettings(1, 2, 3)), (start + 1, SegmentSettings(2, 9, 0)))
    pixels, first = split_words(cfg, words)
    exp = expected_stream(cfg, pixels, first, settings_changes=dict(changes))
    assert [tuple(exp.settings[i]) for i in (start, start + after)] == [(1, 2, 3), (2, 9, 0)]
    result = check_stream(sim, words, Stimulus(0.2, 0.4, after, settings_changes=changes))
    assert_passed(result)


def test_core_random_store_with_faults():
    cfg = BASE
    sim = built(cfg, "core")
    words = scene_words(cfg, n_frames=7, seed=4).copy()
    words[3 * 192 + 40] |= np.uint64(1 << cfg.input_bits)
    result = check_stream(sim, words, Stimulus(0.3, 0.3, 9, ((500, 2),), (), "random"))
    assert_passed(result)
