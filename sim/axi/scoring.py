"""Scoring a run of ``dptbd_axi`` (:func:`dptbd.sim.verilator.axi.check_axi`): the candidate
words against the model's lists, exactly (:func:`score_exact`) or in parts split at the
resets that found words in flight (:func:`score_in_parts`: ``soft_reset: "now"`` and
``aresetn`` with ``aresetn_wait``), the ``tuser[0]`` / ``tlast`` of every word, and the
LISTS counter against the lists delivered (:func:`delivered_lists`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dptbd.sim.axi.stimulus import CutList
from dptbd.sim.candidate_scoreboard import CandidateScoreboard, list_words

if TYPE_CHECKING:
    from dptbd.sim.verilator.axi import AxiRun

__all__ = ["flag_problems", "score_exact", "undrained_cuts", "score_in_parts",
           "delivered_lists"]


def flag_problems(cfg, lists, flags: np.ndarray) -> list[str]:
    """``tuser[0]`` on a list's first word, ``tlast`` on its trailer, for each word."""
    sizes = np.asarray([len(words) for words in list_words(cfg, lists)], dtype=np.int64)
    closed = np.asarray([getattr(lst, "closed", True) for lst in lists], dtype=bool)
    first = np.zeros(sum(sizes), dtype=bool)
    trailer = np.zeros(sum(sizes), dtype=bool)
    ends = np.cumsum(sizes)                         # int64 also with no list
    first[(ends - sizes)[sizes > 0]] = True
    trailer[(ends - 1)[closed & (sizes > 0)]] = True
    n = min(len(flags), len(first))
    got_first = (flags[:n] & np.uint64(1)).astype(bool)
    got_last = (flags[:n] >> np.uint64(1) & np.uint64(1)).astype(bool)
    bad = np.flatnonzero((got_first != first[:n]) | (got_last != trailer[:n]))
    return [f"list word {int(i)}: tuser[0] = {int(got_first[i])}, tlast = {int(got_last[i])}"
            for i in bad[:5]]


def score_exact(cfg, lists: list, open_records: tuple, words: np.ndarray):
    """The scoreboard of ``words`` against ``lists`` and the problem if the words after them
    are not ``open_records`` (the records of a list the stream's end leaves open)."""
    board = CandidateScoreboard(cfg, lists)
    n = sum(len(w) for w in list_words(cfg, lists))
    board.receive_array(words[:n])
    tail = [int(w) for w in words[n:]]
    problems = []
    if len(words) >= n and tail != list(open_records):
        problems.append(f"after the last list: {len(tail)} words {[hex(w) for w in tail[:4]]}, "
                        f"the open list's records {[hex(w) for w in open_records[:4]]}")
    return board, problems


def undrained_cuts(starts: set, checks: list, run: "AxiRun") -> list[tuple[int, int]]:
    """(beat, cycle) of each ``soft_reset: "now"`` and ``aresetn`` with words in flight
    that starts a piece of the model (a beat of ``starts``): the cycle its wait for
    ``STATUS.soft_reset_busy`` = 0 (its read of STATUS after ``aresetn``) ended (the old
    piece's words all came before it, the new piece's after: the input is held until then)."""
    waits = {}
    for index, (kind, _name, beat) in enumerate(checks):
        if kind in ("wait", "mark") and beat not in waits and index < len(run.op_cycles):
            waits[beat] = int(run.op_cycles[index])
    return sorted((beat, cycle) for beat, cycle in waits.items() if beat > 0 and beat in starts)


def score_in_parts(cfg, expected, run: "AxiRun", cuts: list[tuple[int, int]],
                   lost: set | frozenset = frozenset()):
    """Score the words in parts split at the undrained resets ``cuts``: each part but the
    last is its lists whole, then at most one list's first records closed by the cut
    trailer (``pack_cut_trailer``) or nothing more; before an ``aresetn`` with words in
    flight (a beat of ``lost``) the first records of at most one list, with no trailer; the
    last part exactly (:class:`CandidateScoreboard`). ``tuser[0]`` on each list's first
    word, ``tlast`` on each list's trailer (a list abandoned by ``aresetn`` has none)."""
    from dptbd.hw.candidate_layout import pack_cut_trailer

    problems, flags = [], []           # flags: (tuser[0], tlast) the words must carry

    def packet(words, closed=True):
        flags.extend((i == 0, closed and i == len(words) - 1) for i in range(len(words)))

    starts = np.asarray(expected.list_starts, dtype=np.int64)
    bounds = [0, *(beat for beat, _ in cuts)]
    edges = [0, *(cycle for _, cycle in cuts)]
    cycles = np.asarray(run.out_cycles, dtype=np.int64)
    got_flags = np.asarray(run.out_flags, dtype=np.uint64)
    for part, (lo_beat, hi_beat) in enumerate(zip(bounds, bounds[1:])):
        lists = [lst for lst, s0 in zip(expected.lists, starts) if lo_beat <= s0 < hi_beat]
        here = (cycles >= edges[part]) & (cycles < edges[part + 1])
        got = [int(w) for w in run.out_words[here]]
        open_list = None                 # the list the soft reset found open, if any
        if lists and isinstance(lists[-1], CutList) and not lists[-1].drained:
            open_list = lists.pop()
        want = list_words(cfg, lists)
        i = k = 0
        while k < len(want) and got[i:i + len(want[k])] == want[k]:
            packet(want[k], getattr(lists[k], "closed", True))
            i, k = i + len(want[k]), k + 1
        rest = got[i:]
        records = (want[k][:-1] if k < len(want) else
                   list_words(cfg, [open_list])[0][:len(open_list.records)]
                   if open_list is not None else [])
        if hi_beat in lost:                # aresetn: records sent, no trailer
            ok = len(rest) <= len(records) and rest == records[:len(rest)]
        else:
            ok = not rest or (len(rest) - 1 <= len(records)
                              and rest[:-1] == records[:len(rest) - 1]
                              and rest[-1] == pack_cut_trailer(cfg, len(rest) - 1))
        if ok:
            packet(rest, hi_beat not in lost)
        else:
            reset = "aresetn" if hi_beat in lost else "soft reset"
            problems.append(f"before the {reset} at beat {hi_beat}: after {k} whole lists "
                            f"of {len(want)}, words {[hex(w) for w in rest[:4]]} are not a "
                            "list's first records" + ("" if hi_beat in lost else
                                                      " closed by the cut trailer"))
            flags.extend((bool(f & np.uint64(1)), bool(f >> np.uint64(1) & np.uint64(1)))
                         for f in got_flags[here][i:])
    last = [lst for lst, s0 in zip(expected.lists, starts) if s0 >= bounds[-1]]
    board, more = score_exact(cfg, last, expected.open_records,
                               run.out_words[cycles >= edges[-1]])
    problems += more
    for lst, words in zip(last, list_words(cfg, last)):
        packet(words, getattr(lst, "closed", True))
    packet(list(expected.open_records), False)
    n = min(len(flags), len(got_flags))
    first = (got_flags[:n] & np.uint64(1)).astype(bool)
    tlast = (got_flags[:n] >> np.uint64(1) & np.uint64(1)).astype(bool)
    want = np.asarray(flags[:n], dtype=bool).reshape(-1, 2)
    bad = np.flatnonzero((first != want[:, 0]) | (tlast != want[:, 1]))
    problems += [f"word {int(j)}: tuser[0] = {int(first[j])}, tlast = {int(tlast[j])}"
                 for j in bad[:5]]
    return board, problems


def delivered_lists(cfg, run: "AxiRun", lo: int, hi: int) -> int:
    """The lists the core finished that came out in cycles ``[lo, hi)``: words with
    ``tlast`` that are not a cut trailer (the core counts those in LISTS)."""
    from dptbd.hw.candidate_layout import unpack_candidate

    cycles = np.asarray(run.out_cycles, dtype=np.int64)
    last = (np.asarray(run.out_flags, dtype=np.uint64) >> np.uint64(1) & np.uint64(1)) == 1
    count = 0
    for word in np.asarray(run.out_words)[last & (cycles >= lo) & (cycles < hi)]:
        kind, fields = unpack_candidate(cfg, int(word))
        count += not (kind == "trailer" and fields.get("cut"))
    return count
