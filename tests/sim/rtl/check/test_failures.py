"""The checker of :mod:`dptbd.sim.rtl.check` can fail: a flipped bit, an extra word, a missing
word, a timeout, a corrupted record or a missing trailer reported with frame, row, column and
field (segment, record and field for candidate lists)."""

from __future__ import annotations

import dataclasses
import shutil

import numpy as np
import pytest

import dptbd.sim.rtl.check as rtl_check
from dptbd.hw.candidate_layout import unpack_candidate
from dptbd.hw.layouts import unpack_state
from dptbd.sim import verilator as V
from dptbd.sim.rtl.check import Stimulus, check_frames, check_stream
from dptbd.sim.scenarios import make_frames
from dptbd.sim.scoreboard import expected_words
from dptbd.sim.candidate_scoreboard import expected_lists, list_words
from dptbd.sim.stream_model import expected_stream, split_words

from helpers.verilator_harness import SEG, built, make_config, scene_words

pytestmark = pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")

BASE = make_config(**SEG)


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
