"""Compiled RTL runs scored against the golden model (:mod:`dptbd.sim.rtl.check`): whole
scenes bit for bit over parameter sets × input gaps × back-pressure, every fault class
against the promise of docs/gateware.md ("Reset and resynchronisation", "Weight LUT write
protocol"), and the checker's own failures (a flipped bit, an extra word, a missing word)
reported with frame, row, column and field."""

from __future__ import annotations

import dataclasses
import shutil

import numpy as np
import pytest

import dptbd.sim.rtl.check as rtl_check
from dptbd.hw.candidate_layout import unpack_candidate
from dptbd.hw.layouts import unpack_state
from dptbd.sim import verilator as V
from dptbd.sim.rtl.check import Stimulus, check_frames, check_stream, lut_change_words
from dptbd.sim.scenarios import make_frames
from dptbd.sim.scoreboard import expected_words
from dptbd.sim.candidate_scoreboard import expected_lists, list_words
from dptbd.sim.stimulus import pixel_words
from dptbd.sim.stream_model import expected_stream, split_words

from helpers.verilator_harness import SEG, built, make_config  # noqa: E402
from helpers.refusals import whole

pytestmark = pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")

BASE = make_config(**SEG)


def assert_passed(result):
    assert result.passed, result.report


# ---- bit-exact whole scenes: parameter sets × gaps × back-pressure ---------------------

def cases():
    """(id, config overrides, design, store_init, scenario, frames)."""
    return [
        ("dp", SEG, "dp", "zero", "two-targets", 7),
        ("core-zero", {}, "core", "zero", "mixed", 5),
        ("core-random", {}, "core", "random", "mixed", 5),
        ("segmenter", SEG, "segmenter", "zero", "two-targets", 9),
        ("dp-r2", {"radius": 2, "segment_frames": 2}, "dp", "zero", "edges", 5),
        ("dp-f0", {"weight_frac_bits": 0}, "dp", "zero", "noise", 5),
        ("dp-saturating", {"energy_bits": 9}, "dp", "zero", "saturating", 7),
        ("core-saturating", {"energy_bits": 9}, "core", "random", "saturating", 7),
        ("dp-13x7", {"width": 13, "height": 7}, "dp", "zero", "edges", 7),
        ("segmenter-13x7", {"width": 13, "height": 7, **SEG, "histogram_bits": 5,
                            "histogram_shift": 2},
         "segmenter", "zero", "two-targets", 9),
        ("dp-half-up-f3", {"rounding": "half_up", "weight_frac_bits": 3}, "dp", "zero",
         "ties", 5),
    ]


PAUSES = [(0.0, 0.0), (0.3, 0.0), (0.0, 0.6), (0.5, 0.5)]


@pytest.mark.parametrize("valid_gap,ready_pause", PAUSES, ids=lambda p: f"{p}")
@pytest.mark.parametrize("name,kw,design,store_init,scenario,n_frames", cases(),
                         ids=[c[0] for c in cases()])
def test_whole_scene_bit_exact(name, kw, design, store_init, scenario, n_frames, valid_gap,
                               ready_pause):
    cfg = make_config(**kw)
    sim = built(cfg, design)
    frames = make_frames(scenario, cfg, n_frames, seed=len(name))
    stimulus = Stimulus(valid_gap=valid_gap, ready_pause=ready_pause,
                        seed=int(valid_gap * 10 + ready_pause * 100), store_init=store_init)
    result = check_frames(sim, frames, stimulus)
    assert_passed(result)
    assert result.words_in == frames.size and result.epochs == 1
    assert result.raw.status == "done"
    if design == "segmenter":
        lists = expected_lists(cfg, frames)
        assert result.words_out == sum(lst.count + 1 for lst in lists)
        assert result.report == (f"bit-exact: {len(lists)} lists, "
                                 f"{sum(lst.count for lst in lists)} records, "
                                 f"{result.words_out} words")
    else:
        assert result.words_out == frames.size
        assert result.report == f"bit-exact: {frames.size} words ({n_frames} frames)"
        np.testing.assert_array_equal(result.raw.out_words, expected_words(cfg, frames).ravel())
    size = frames.size if design != "segmenter" else frames.size + 1
    if valid_gap == ready_pause == 0.0:
        assert result.cycles == size + sim.latency
    elif design == "segmenter":       # sparse candidates: back-pressure may cost nothing
        assert result.cycles >= size + sim.latency
    else:
        assert result.cycles > size + sim.latency


def test_segmenter_scenes_have_records():
    """The segmenter cases above are not vacuous: their lists carry records."""
    for name, kw, design, _, scenario, n_frames in cases():
        if design == "segmenter":
            cfg = make_config(**kw)
            lists = expected_lists(cfg, make_frames(scenario, cfg, n_frames, seed=len(name)))
            assert sum(lst.count for lst in lists) >= 5, name


# ---- fault classes against the promise -------------------------------------------------

def scene_words(cfg, n_frames=9, seed=1):
    return pixel_words(cfg, make_frames("two-targets", cfg, n_frames, seed=seed))


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


# ---- the checker can fail --------------------------------------------------------------

def tampered(monkeypatch, change):
    """Make check_stream see the run's output changed by ``change(raw) -> RawRun``."""
    real = rtl_check.run

    def run(*args, **kwargs):
        return change(real(*args, **kwargs))

    monkeypatch.setattr(rtl_check, "run", run)


def flip(index, bit):
    def change(raw):
        out = raw.out_words.copy()
        out[index] ^= np.uint64(1 << bit)
        return dataclasses.replace(raw, out_words=out)
    return change


def mismatch_report(cfg, index, frame, row, col, want, got):
    w, g = unpack_state(cfg, int(want)), unpack_state(cfg, int(got))
    fields = [k for k in w if w[k] != g[k]]
    return (f"first mismatch at output {index}: frame {frame}, row {row}, col {col}, field "
            f"{fields[0]}: expected {w[fields[0]]}, got {g[fields[0]]} (differing fields "
            f"{fields}; expected {w}, got {g})")


@pytest.mark.parametrize("bit,field", [(0, "energy"), (16, "direction"), (20, "end_of_line"),
                                       (21, "end_of_frame")])
def test_a_flipped_output_bit_is_reported_with_frame_row_col_field(monkeypatch, bit, field):
    cfg = BASE
    frames = make_frames("two-targets", cfg, 5, seed=1)
    index = 2 * 192 + 3 * 16 + 5                       # frame 2, row 3, col 5
    tampered(monkeypatch, flip(index, bit))
    result = check_frames(built(cfg), frames, Stimulus(0.2, 0.2, 1))
    want = expected_words(cfg, frames).ravel()[index]
    assert not result.passed
    assert result.report == mismatch_report(cfg, index, 2, 3, 5, want,
                                            want ^ np.uint64(1 << bit))
    assert f"field {field}:" in result.report
    assert result.words_out == index


def test_a_flipped_bit_after_a_reset_is_located_in_its_epoch(monkeypatch):
    """After a reset the counters start at the first word accepted after it (word 397, in
    the middle of the stream's frame 2): that word is frame 0, (0, 0); the `first` of the
    stream's frame 3 (local word 179) restarts them, so local word 231 is frame 1, row 3,
    col 4."""
    cfg = BASE
    sim = built(cfg)
    words = scene_words(cfg, n_frames=6, seed=1)
    stim = Stimulus(resets=((400, 2),))
    clean = V.run(sim, words, resets=stim.resets)
    first_after = int(np.searchsorted(clean.out_cycles, 400))
    n_in = int(np.searchsorted(clean.accept_cycles, 400))
    assert n_in == 397                                  # accepted from cycle 3, one a cycle
    local = 231
    tampered(monkeypatch, flip(first_after + local, 3))
    result = check_stream(sim, words, stim)
    pixels, first = split_words(cfg, words[n_in:])
    exp = expected_stream(cfg, pixels, first)
    assert tuple(exp.positions[local]) == (1, 3, 4)
    want = exp.words[local]
    assert not result.passed
    assert result.report == "after reset 1 (cycle 400): " + mismatch_report(
        cfg, local, 1, 3, 4, want, want ^ np.uint64(8))


def test_a_mid_frame_restart_is_located_by_the_counters(monkeypatch):
    """A `first` at word 13 of frame 1: the words after it are frame 2 (the stream's third
    frame run), row/col counted from the restart."""
    cfg = BASE
    words = scene_words(cfg, n_frames=4, seed=1).copy()
    words[192 + 13] |= np.uint64(1 << cfg.input_bits)
    index = 192 + 13 + 16 + 4                          # restart + row 1, col 4
    tampered(monkeypatch, flip(index, 1))
    result = check_stream(built(cfg), words)
    pixels, first = split_words(cfg, words)
    want = expected_stream(cfg, pixels, first).words[index]
    assert result.report == mismatch_report(cfg, index, 2, 1, 4, want, want ^ np.uint64(2))


def one_word_more(raw):
    return dataclasses.replace(
        raw, out_words=np.append(raw.out_words, raw.out_words[-1]),
        out_cycles=np.append(raw.out_cycles, raw.out_cycles[-1] + np.uint64(1)))


def one_word_less(raw):
    return dataclasses.replace(raw, out_words=raw.out_words[:-1], out_cycles=raw.out_cycles[:-1])


@pytest.mark.parametrize("change, report", [
    (one_word_more, "1 output word(s) beyond the 576 expected (3 frames)"),
    (one_word_less, "incomplete: 575 of 576 words received, all bit-exact"),
])
def test_an_extra_or_a_missing_output_word_is_reported(monkeypatch, change, report):
    cfg = BASE
    frames = make_frames("noise", cfg, 3, seed=1)
    tampered(monkeypatch, change)
    result = check_frames(built(cfg), frames)
    assert not result.passed
    assert result.report == report


def test_a_timeout_fails_the_check(monkeypatch):
    cfg = BASE
    sim = built(cfg)
    words = scene_words(cfg, n_frames=3)
    real = rtl_check.run
    monkeypatch.setattr(rtl_check, "run", lambda *a, **k: real(*a, **{**k, "max_cycles": 300}))
    result = check_stream(sim, words)
    assert result.raw.status == "timeout" and result.raw.cycles == 300
    assert not result.passed
    n_in = result.words_in
    assert 0 < n_in < words.size
    assert result.report == (f"incomplete: {result.words_out} of {n_in} words received, "
                             f"all bit-exact")


def test_a_segmenter_record_corrupted_is_reported_with_segment_record_field(monkeypatch):
    cfg = BASE
    frames = make_frames("two-targets", cfg, 9, seed=1)
    lists = expected_lists(cfg, frames)
    assert lists[1].count >= 2
    index = lists[0].count + 1 + 1                       # segment 1, record 1
    want = list_words(cfg, lists)[1][1]
    col_bit = 4 + 0                                      # row ⌈log2 12⌉ = 4 bits, then col
    tampered(monkeypatch, flip(index, col_bit))
    result = check_frames(built(cfg, "segmenter"), frames, Stimulus(0.2, 0.5, 2))
    _, w = unpack_candidate(cfg, want)
    _, g = unpack_candidate(cfg, want ^ (1 << col_bit))
    assert not result.passed
    assert result.report == (f"first mismatch at output word {index}: segment 1, record 1, "
                             f"field col: expected {w['col']}, got {g['col']} (differing "
                             f"fields ['col']; expected {w}, got {g})")


def test_a_segmenter_trailer_missing_is_reported(monkeypatch):
    cfg = BASE
    frames = make_frames("two-targets", cfg, 9, seed=1)
    lists = expected_lists(cfg, frames)

    def truncate(raw):
        return dataclasses.replace(raw, out_words=raw.out_words[:-1],
                                   out_cycles=raw.out_cycles[:-1])

    tampered(monkeypatch, truncate)
    result = check_frames(built(cfg, "segmenter"), frames)
    total = sum(lst.count + 1 for lst in lists)
    assert result.report == (f"incomplete: {total - 1} of {total} words received (2 of 3 "
                             f"lists), all bit-exact")


# ---- bad input refused before anything runs --------------------------------------------

def fake_build(tmp_path, cfg=BASE, design="dp"):
    return V.VerilatorBuild(cfg, design, tmp_path, tmp_path / "missing-executable",
                            {"latency": 14}, "0" * 64, 0.0, True, False)


def test_check_frames_refuses_a_wrong_frame_size(tmp_path):
    frames = np.zeros((2, 7, 13), dtype=np.uint8)
    with pytest.raises(ValueError, match=r"^scene frames are 13x7 \(W x H\) but the "
                                         r"configuration is width=16 x height=12$"):
        check_frames(fake_build(tmp_path), frames)


def test_check_frames_refuses_pixels_wider_than_b_in(tmp_path):
    frames = np.zeros((2, 12, 16), dtype=np.int64)
    frames[1, 3, 4] = 256
    frames[0, 0, 0] = -1
    with pytest.raises(ValueError, match=whole(
            "scene pixels must fit input_bits=8 (0 … 255); found 2 outside, e.g. [-1, 256]")):
        check_frames(fake_build(tmp_path), frames)


def test_check_frames_refuses_float_and_flat_scenes(tmp_path):
    with pytest.raises(ValueError, match=r"^scene pixels must be integers, got dtype float64$"):
        check_frames(fake_build(tmp_path), np.zeros((1, 12, 16)))
    with pytest.raises(ValueError, match=r"^scene must have shape \(frames, height, width\), "
                                         r"got shape \(192,\)$"):
        check_frames(fake_build(tmp_path), np.zeros(192, dtype=np.uint8))


def test_check_stream_refuses_bad_stimulus_before_running(tmp_path):
    sim = fake_build(tmp_path)
    words = np.zeros(10, dtype=np.uint64)
    with pytest.raises(ValueError, match=r"^store_init must be 'zero' or 'random', "
                                         r"got 'garbage'$"):
        check_stream(sim, words, Stimulus(store_init="garbage"))
    with pytest.raises(ValueError, match=r"^reset at cycle 1 for 2 cycles is outside the run: "
                                         r"cycles 2 … \d+, hold >= 1$"):
        check_stream(sim, words, Stimulus(resets=((1, 2),)))
    with pytest.raises(ValueError, match=r"^trace needs a build made with waves=True$"):
        check_stream(sim, words, trace=tmp_path / "t.fst")


@pytest.mark.parametrize("address", [89, 128])
def test_check_stream_refuses_a_stray_lut_write_inside_or_beyond_the_port(tmp_path, address):
    words = pixel_words(BASE, np.zeros((1, 12, 16), dtype=np.uint8))
    with pytest.raises(ValueError, match=whole(
            f"a stray LUT write goes beyond the table: address 90 … 127, got {address}")):
        check_stream(fake_build(tmp_path), words, Stimulus(stray_lut_writes=((0, address, 1),)))


def test_a_lut_write_beyond_the_table_is_ignored():
    frames = make_frames("two-targets", BASE, 4, seed=2)
    words = pixel_words(BASE, frames)
    stray = ((0, 90, 0), (len(words) // 2, 127, 0))
    result = check_stream(built(BASE, "dp"), words, Stimulus(stray_lut_writes=stray))
    assert result.passed, result.report
    assert result.raw.counters["lut_writes"] == 2
