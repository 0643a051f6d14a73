"""``dptbd.sim.benches.soft_reset_check``: the per-iteration verdicts of the soft-reset sweep and the
AXI4-Stream rules of :class:`PortWatch`, on hand-made transfers."""

import types

from dptbd.hw.axis_video import STATE_TUSER
from dptbd.sim.benches.soft_reset_check import PortWatch, score_iteration, score_state_iteration
from helpers.seg_harness import make_config


def cut_trailer(cfg, k):
    return 1000 + k                       # a stand-in word: the verdict only compares it


def lists(*packets):
    """(tdata, tuser, tlast) transfers of whole lists, tuser[0] on each list's first word."""
    return [(w, int(i == 0), int(i == len(p) - 1)) for p in packets for i, w in enumerate(p)]


def test_score_iteration_verdicts():
    cfg = make_config(width=8, height=6, candidate_count=2)
    want = [[1], [2, 3, 4]]
    problems = []
    assert score_iteration(cfg, want, lists([1], [2, 3, 4]), True, cut_trailer, problems, 0) \
        == "whole"
    assert score_iteration(cfg, want, lists([1], [2, 1001]), False, cut_trailer, problems, 0) \
        == "cut 1"
    assert score_iteration(cfg, want, lists([1]), False, cut_trailer, problems, 0) == "dropped"
    assert problems == []
    assert score_iteration(cfg, want, lists([1], [2, 1002]), False, cut_trailer, problems,
                           7) == "mismatch"
    assert problems == ["iteration 7: cut list [2, 1002] is not a prefix of [2, 3, 4] closed "
                        "by the cut trailer"]
    problems.clear()
    assert score_iteration(cfg, want, lists([1], [2, 1001]), True, cut_trailer, problems, 3) \
        == "mismatch"
    assert problems == ["iteration 3: lists [[1], [2, 1001]] differ from the model's "
                        "[[1], [2, 3, 4]]"]


def test_score_state_iteration_wants_whole_lines_and_fillers_last():
    cfg = make_config(width=4, height=3, candidate_count=2)
    expected = types.SimpleNamespace(state_words=[], state_first=[])
    cut = 1 << STATE_TUSER["cut"]
    problems = []
    assert score_state_iteration(cfg, expected, [], False, problems, 0) == "whole"
    assert problems == []
    short = [(0, cut, 0), (0, cut, 0), (0, cut, 1)]         # a line of 3 words, W = 4
    assert score_state_iteration(cfg, expected, short, False, problems, 2) == "mismatch"
    assert problems[0] == "iteration 2: state word 2 is word 3 of its line, tlast = 1"


def test_port_watch_flags_a_dropped_valid_and_a_changed_word():
    handles = {f"m_{f}": types.SimpleNamespace(value=0)
               for f in ("tvalid", "tdata", "tuser", "tlast", "tready")}
    dut = types.SimpleNamespace(**handles)
    problems = []
    watch = PortWatch(dut, "m", 1.0, 1, problems)            # pause 1.0: tready always 0
    values = {}

    def value(handle):
        return values[id(handle)]

    watch.drive()
    values.update({id(handles["m_tvalid"]): 1, id(handles["m_tdata"]): 5,
                   id(handles["m_tuser"]): 0, id(handles["m_tlast"]): 0})
    watch.sample(value, 0, 0)
    watch.drive()
    values[id(handles["m_tdata"])] = 6                            # changed while waiting
    watch.sample(value, 1, 1)
    watch.drive()
    values[id(handles["m_tvalid"])] = 0                           # dropped without a handshake
    watch.sample(value, 2, 2)
    assert problems == ["cycle 1: m word changed while waiting",
                        "cycle 2: m_tvalid dropped without a handshake"]
    assert watch.words == []
