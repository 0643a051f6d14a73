"""The ``states`` scoreboard without a simulator: expected stream, comparison, mismatch
report, blocks and positions."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.hw.layouts import state_layout, unpack_state
from dptbd.model.fixed import run_fixed
from dptbd.sim.scoreboard import (
    Scoreboard,
    compare_word,
    expected_words,
)


def small(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**{"width": 8, "height": 6, "segment_frames": 3, **kw})


def frames_for(cfg, n=7, seed=0):
    return np.random.default_rng(seed).integers(0, cfg.pixel_max + 1,
                                                size=(n, cfg.height, cfg.width))


def test_expected_stream_ends_segments_like_the_model():
    cfg = small()
    frames = frames_for(cfg, n=7)
    words = expected_words(cfg, frames)
    f = {name: np.vectorize(lambda w, n=name: unpack_state(cfg, w)[n])(words)
         for name, _ in state_layout(cfg)}
    out = run_fixed(frames, cfg)                    # 2 whole segments of K = 3
    np.testing.assert_array_equal(f["energy"][[2, 5]], out.energy)
    np.testing.assert_array_equal(f["direction"][[2, 5]], out.direction)
    assert (f["direction"][[0, 3, 6]] == cfg.start_code).all()
    np.testing.assert_array_equal(f["energy"][6], frames[6])  # trailing partial segment
    assert f["end_of_line"][:, :, -1].all() and f["end_of_line"][:, :, :-1].sum() == 0
    assert f["end_of_frame"].sum() == 7 and f["end_of_frame"][:, -1, -1].all()
    assert f["end_of_segment"].sum() == 2
    assert f["end_of_segment"][2, -1, -1] and f["end_of_segment"][5, -1, -1]


def test_compare_word_reports_frame_row_col_field_expected_got():
    cfg = small()
    words = expected_words(cfg, frames_for(cfg)).ravel()
    index = 2 * 48 + 4 * 8 + 6                          # frame 2, row 4, col 6
    want = int(words[index])
    assert compare_word(cfg, index, want, want) is None
    got = want ^ (1 << state_layout(cfg)["direction"].offset)   # corrupt the direction
    mismatch = compare_word(cfg, index, got, want)
    assert (mismatch.frame, mismatch.row, mismatch.col) == (2, 4, 6)
    assert mismatch.fields == ("direction",)
    text = str(mismatch)
    assert "frame 2, row 4, col 6, field direction" in text
    assert f"expected {unpack_state(cfg, want)['direction']}, got " \
           f"{unpack_state(cfg, got)['direction']}" in text


def test_scoreboard_stops_at_the_first_mismatch_of_a_corrupted_expectation():
    """The self-check: a deliberately corrupted expected word is caught and located."""
    cfg = small()
    words = expected_words(cfg, frames_for(cfg)).ravel()
    corrupted = words.copy()
    corrupted[100] ^= np.uint64(1 << state_layout(cfg)["end_of_line"].offset)
    corrupted[200] ^= np.uint64(1)
    board = Scoreboard(cfg, corrupted)
    results = [board.receive(int(w)) for w in words]
    assert all(results[:100]) and not any(results[100:])
    assert board.failed and not board.done and board.count == 100
    frame, rest = divmod(100, 48)
    assert f"frame {frame}, row {rest // 8}, col {rest % 8}, field end_of_line" in board.report()
    # the genuine expectation passes
    board = Scoreboard(cfg, words)
    assert all(board.receive(int(w)) for w in words) and board.done
    assert board.report().startswith("bit-exact")


def test_scoreboard_reports_missing_and_extra_words_and_frames():
    cfg = small()
    words = expected_words(cfg, frames_for(cfg, n=2)).ravel()
    seen = []
    board = Scoreboard(cfg, words, on_frame=seen.append)
    for w in words[:50]:
        board.receive(int(w))
    assert seen == [0] and "incomplete: 50 of 96" in board.report()
    for w in words[50:]:
        board.receive(int(w))
    assert seen == [0, 1] and board.done
    assert not board.receive(int(words[0]))
    assert board.failed and "beyond the 96 expected" in board.report()


# ---- Scoreboard.receive_array and positions --------------------------------------------

def _outcome(board):
    return (board.count, board.extra, board.failed, board.done, str(board.mismatch),
            board.report())


def _per_word(cfg, expected, got, **kw):
    seen = []
    board = Scoreboard(cfg, expected, on_frame=seen.append, **kw)
    for w in got:
        if not board.receive(int(w)):
            break
    return _outcome(board), seen


def _in_blocks(cfg, expected, got, cuts, **kw):
    seen = []
    board = Scoreboard(cfg, expected, on_frame=seen.append, **kw)
    for block in np.split(np.asarray(got, dtype=np.uint64), cuts):
        board.receive_array(block)
    return _outcome(board), seen


@pytest.mark.parametrize("case", ["exact", "flip", "missing", "extra", "flip-then-extra"])
@pytest.mark.parametrize("seed", range(4))
def test_receive_array_has_the_outcome_of_receive_word_by_word(case, seed):
    """Any split of the output into blocks: same count, extra, mismatch, report and
    on_frame calls as one receive() per word (which stops at the first problem)."""
    cfg = small()
    rng = np.random.default_rng(seed)
    expected = expected_words(cfg, frames_for(cfg, n=3, seed=seed)).ravel()
    got = expected.copy()
    if case in ("flip", "flip-then-extra"):
        got[int(rng.integers(0, got.size))] ^= np.uint64(1 << int(rng.integers(0, 20)))
    if case == "missing":
        got = got[:-int(rng.integers(1, 60))]
    if case in ("extra", "flip-then-extra"):
        got = np.concatenate([got, got[:int(rng.integers(1, 5))]])
    reference = _per_word(cfg, expected, got)
    for _ in range(5):
        cuts = np.sort(rng.integers(0, got.size + 1, size=int(rng.integers(0, 6))))
        assert _in_blocks(cfg, expected, got, cuts) == reference
    outcome = reference[0]
    if case == "exact":
        assert outcome[3] and outcome[5] == f"bit-exact: {expected.size} words (3 frames)"
        assert reference[1] == [0, 1, 2]
    if case == "missing":
        assert not outcome[2] and outcome[5].startswith("incomplete: ")
    if case == "extra":
        assert outcome[:2] == (expected.size, 1)
        assert outcome[5] == f"1 output word(s) beyond the {expected.size} expected (3 frames)"


def test_receive_array_after_a_failure_takes_nothing():
    cfg = small()
    expected = expected_words(cfg, frames_for(cfg, n=1)).ravel()
    board = Scoreboard(cfg, expected)
    bad = expected.copy()
    bad[3] ^= np.uint64(1)
    assert not board.receive_array(bad)
    assert board.count == 3 and board.mismatch.index == 3
    assert not board.receive_array(expected[4:])
    assert board.count == 3
    assert board.receive_array(np.zeros(0, dtype=np.uint64)) is False


def test_positions_name_the_frame_row_and_col_of_irregular_streams():
    """With positions (a stream whose frames are not all W·H words), the report names the
    position given for that word, not the one its index would imply."""
    cfg = small()
    expected = expected_words(cfg, frames_for(cfg, n=2)).ravel()
    positions = np.zeros((expected.size, 3), dtype=np.int64)
    positions[:, 0] = 7
    positions[:, 1] = np.arange(expected.size) % 5
    positions[:, 2] = np.arange(expected.size) % 3
    got = expected.copy()
    got[50] ^= np.uint64(1 << 1)                        # energy bit 1
    board = Scoreboard(cfg, expected, positions=positions)
    assert not board.receive_array(got)
    want = unpack_state(cfg, int(expected[50]))
    seen = unpack_state(cfg, int(got[50]))
    assert board.report() == (
        f"first mismatch at output 50: frame 7, row 0, col 2, field energy: expected "
        f"{want['energy']}, got {seen['energy']} (differing fields ['energy']; expected "
        f"{want}, got {seen})")
    plain = Scoreboard(cfg, expected)
    assert not plain.receive_array(got)
    assert "frame 1, row 0, col 2, field energy" in plain.report()   # 50 = 48 + 2
