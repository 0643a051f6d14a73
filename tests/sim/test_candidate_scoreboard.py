"""The candidate scoreboard (no simulator): expected words, and reports that name the
first mismatching segment, record or trailer, and field."""

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import pack_record, pack_trailer
from dptbd.model.segmentation import segment_stream
from dptbd.sim.scenarios import make_frames
from dptbd.sim.candidate_scoreboard import (
    CandidateScoreboard,
    expected_lists,
    list_words,
    state_stream,
)

CFG = DPConfig(width=8, height=6, segment_frames=2, candidate_count=4, histogram_bits=5)


def lists_and_words():
    frames = make_frames("random", CFG, 8, seed=1)
    lists = expected_lists(CFG, frames)
    assert [lst.count for lst in lists] == [0, 0, 3, 7]
    return frames, lists, [w for ws in list_words(CFG, lists) for w in ws]


def test_expected_lists_equal_the_stream_model():
    frames, lists, _ = lists_and_words()
    by_stream = segment_stream(state_stream(CFG, frames), CFG)
    assert list_words(CFG, lists) == list_words(CFG, by_stream)
    assert len(lists) == 4 and sum(lst.count for lst in lists) > 4


def test_words_are_records_then_one_trailer():
    _, lists, _ = lists_and_words()
    words = list_words(CFG, lists)
    lst = lists[2]
    r = lst.records[0]
    assert words[2][0] == pack_record(CFG, r["row"], r["col"], r["energy"], r["direction"])
    assert words[2][-1] == pack_trailer(CFG, **lst.trailer, cut=0)
    assert [len(ws) for ws in words] == [lst.count + 1 for lst in lists]


def test_bit_exact_and_incomplete_and_extra():
    _, lists, words = lists_and_words()
    board = CandidateScoreboard(CFG, lists)
    for w in words[:-1]:
        assert board.receive(w)
    assert not board.done and "incomplete" in board.report()
    board.receive(words[-1])
    assert board.done and board.report().startswith("bit-exact: 4 lists")
    board.receive(words[0])
    assert board.failed and "beyond the" in board.report()


def test_report_names_segment_record_and_field():
    _, lists, words = lists_and_words()
    index = 1 + 1 + 1                       # segment 2, record 1 (two empty lists before)
    board = CandidateScoreboard(CFG, lists)
    for w in words[:index]:
        board.receive(w)
    assert not board.receive(words[index] ^ 1)          # row bit 0
    text = board.report()
    assert "first mismatch at output word 3: segment 2, record 1, field row" in text


def test_report_names_trailer_fields_and_kind():
    _, lists, words = lists_and_words()
    trailer = lists[0].count                  # segment 0's trailer
    board = CandidateScoreboard(CFG, lists)
    for w in words[:trailer]:
        board.receive(w)
    bad = pack_trailer(CFG, **{**lists[0].trailer, "threshold": 3}, cut=0)
    board.receive(bad)
    assert "segment 0, trailer (after 0 records), field threshold" in board.report()
    board = CandidateScoreboard(CFG, lists)
    board.receive(pack_record(CFG, 0, 0, 0, 0))
    assert "segment 0, trailer (after 0 records): expected a trailer" in board.report()


def test_corrupt_word_makes_the_right_word_fail():
    _, lists, words = lists_and_words()
    board = CandidateScoreboard(CFG, lists)
    board.corrupt_word(2, 1)
    results = [board.receive(w) for w in words[:3]]
    assert results == [True, True, False]
    assert np.all([board.mismatch.index == 2])
