"""``CandidatesToAxis``: the candidate lists on AXI4-Stream, and the soft reset's close of
an open list.

``ref_*`` say what each beat must carry (the layouts' own pack/unpack), ``rtl_*`` run the
adapter with random ``tvalid`` gaps and ``tready`` back-pressure.
"""

import random

import pytest

from dptbd.hw.axis_video import CandidatesToAxis
from dptbd.hw.candidate_layout import (pack_cut_trailer, pack_record, pack_trailer,
                                       unpack_candidate)
from helpers.axis_harness import (check_axis_rules, config, packets, rtl_adapter_beats,
                                  soft_reset_trace)
from helpers.hw_harness import simulate


def ref_candidate_beats(words):
    """(tdata, tuser, tlast) per word: tuser[0] on a list's first word, tlast on trailers."""
    out, start = [], 1
    for word, trailer in words:
        out.append((word, start, trailer))
        start = trailer
    return out


def rtl_candidate_beats(cfg, words, seed=1):
    dut = CandidatesToAxis(cfg)
    return rtl_adapter_beats(dut, dut.candidates, dut.cand, [w for w, _ in words], seed)


def test_candidates_out_marks_list_start_and_trailer():
    cfg = config()
    trailer = dict(count=2, threshold=3, overflow=0, primed=1, aligned=1, missed=0, cut=0)
    empty = dict(trailer, count=0)
    words = [(pack_record(cfg, 1, 2, 300, 4), 0), (pack_record(cfg, 5, 7, 9, 9), 0),
             (pack_trailer(cfg, **trailer), 1), (pack_trailer(cfg, **empty), 1),
             (pack_record(cfg, 0, 0, 1, 0), 0), (pack_trailer(cfg, **dict(trailer, count=1)), 1)]
    want = ref_candidate_beats(words)
    assert [w[1] for w in want] == [1, 0, 0, 1, 1, 0]          # the empty list: one beat
    got, stalls = rtl_candidate_beats(cfg, words)
    assert got == want
    assert stalls > 0                                           # back-pressure was exercised


def soft_reset_lists(cfg):
    """Lists of (payload, is_trailer): two records, an empty list, one record, three."""
    def trailer(count):
        return pack_trailer(cfg, count=count, threshold=3, overflow=0, primed=1, aligned=1,
                            missed=0, cut=0)
    lists = []
    for count in (2, 0, 1, 3):
        lists.append([(pack_record(cfg, i, count, 100 + i, 1), 0) for i in range(count)]
                     + [(trailer(count), 1)])
    return lists


def rtl_soft_reset(cfg, lists, at, seed):
    """Run ``CandidatesToAxis`` with a source that behaves like the core's FIFO (a word
    offered stays offered until taken; on ``restart`` it is reset: an offered word is gone
    and a list it was in the middle of is dropped) and random ``tready``; ``soft_reset`` in
    cycle ``at`` (never if None): :func:`helpers.axis_harness.soft_reset_trace`."""
    dut = CandidatesToAxis(cfg)
    flat = [(w, i == 0) for lst in lists for i, (w, _t) in enumerate(lst)]
    return soft_reset_trace(dut, dut.candidates, dut.cand, flat, at, seed, offer=0.6, tail=3)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_soft_reset_closes_the_list_in_every_cycle(seed):
    """A soft reset in every cycle of one run of four lists (random tready and source gaps,
    the same up to the request):
    the AXI4-Stream rules hold in every cycle; a word offered before the request is still
    delivered; a list left open is closed by the cut trailer (cut = 1, count = records
    sent, tlast); restart pulses once, registered — in the cycle after the request's when
    nothing is in flight, else in the cycle after the one the list is closed in, offering
    and taking nothing; busy from the request to restart; every list is delivered whole or
    cut (a prefix and its cut trailer), in order, and no list is lost."""
    cfg = config()
    lists = soft_reset_lists(cfg)
    words = [[w for w, _ in lst] for lst in lists]
    seen = {"cut": 0, "whole": 0, "waited": 0}
    span = len(rtl_soft_reset(cfg, lists, at=None, seed=seed))
    for at in range(0, span):
        trace = rtl_soft_reset(cfg, lists, at, seed=seed)
        check_axis_rules(trace)
        got = packets(trace)
        assert len(got) == len(lists)
        cuts = 0
        for want, packet in zip(words, got):
            data = [w for w, _ in packet]
            assert [u for _, u in packet] == [1] + [0] * (len(packet) - 1)
            if data != want:
                k = len(data) - 1
                assert 1 <= k < len(want) and data[:k] == want[:k]
                assert data[k] == pack_cut_trailer(cfg, k)
                cuts += 1
        assert cuts <= 1
        # when the request found a list open (or a record waiting), it was cut; the restart
        restarts = [c for c, row in enumerate(trace) if row["restart"]]
        assert len(restarts) == 1 and restarts[0] > at
        assert not trace[restarts[0]]["tvalid"] and not trace[restarts[0]]["taken"]
        busy = [c for c, row in enumerate(trace) if row["busy"]]
        assert busy == list(range(at, restarts[0] + 1))
        taken = [c for c, row in enumerate(trace) if row["tvalid"] and row["tready"]]
        before = [c for c in taken if c < at]
        held = at > 0 and trace[at - 1]["tvalid"] and not trace[at - 1]["tready"]
        open_list = bool(before) and not trace[before[-1]]["tlast"]
        during = [c for c in taken if at <= c <= restarts[0]]
        if held:
            first = during[0]                    # the waiting word goes first, unchanged
            assert trace[first]["tdata"] == trace[at - 1]["tdata"]
            seen["waited"] += 1
            closes = not trace[first]["tlast"]
        else:
            closes = open_list
        assert cuts == int(closes)
        if closes:
            closed = restarts[0] - 1
            assert trace[closed]["tvalid"] and trace[closed]["tready"]
            assert unpack_candidate(cfg, trace[closed]["tdata"])[1]["cut"] == 1
            seen["cut"] += 1
        elif not held:
            assert restarts[0] == at + 1 and during == []
            seen["whole"] += 1
        else:
            assert restarts[0] == during[0] + 2 and len(during) == 1
    assert min(seen.values()) > 0, seen


@pytest.mark.parametrize("seed", range(3))
def test_busy_next_is_the_next_cycles_busy(seed):
    """``CandidatesToAxis(busy_ahead=True)``: ``busy_next`` is ``busy`` of the next cycle,
    given ``soft_reset_ahead`` (the next cycle's ``soft_reset``), under soft resets at any
    time (during a list, a held word, a close, back to back), ``hold`` and back-pressure;
    and every output is the generic build's (its request from a register of its own)."""
    cfg = config()
    cycles = 600
    rng = random.Random(seed)
    soft = [0] + [int(rng.random() < 0.04) for _ in range(cycles)]    # 0 after reset
    draws = [(rng.random() < 0.6, rng.random() < 0.3, rng.random() < 0.5, rng.random() < 0.3)
             for _ in range(cycles)]

    def run(ahead):
        dut = CandidatesToAxis(cfg, busy_ahead=ahead)
        trace = []

        async def bench(ctx):
            for cycle, (valid, end, tready, hold) in enumerate(draws):
                ctx.set(dut.candidates.valid, valid)
                ctx.set(dut.candidates.payload.end_of_list, end)
                ctx.set(dut.cand.tready, tready)
                ctx.set(dut.hold, hold)
                ctx.set(dut.soft_reset, soft[cycle])
                if ahead:
                    ctx.set(dut.soft_reset_ahead, soft[cycle + 1])
                trace.append(tuple(ctx.get(s) for s in (
                    dut.busy, dut.restart, dut.stalled, dut.candidates.ready, dut.cand.tvalid,
                    dut.cand.tdata, dut.cand.tlast, dut.cand.tuser))
                    + ((ctx.get(dut.busy_next),) if ahead else ()))
                await ctx.tick()

        simulate(dut, bench)
        return trace

    trace = run(True)
    assert [t[-1] for t in trace[:-1]] == [t[0] for t in trace[1:]]
    assert [t[:-1] for t in trace] == run(False)
    assert sum(t[1] for t in trace) > 10 and sum(soft) > 10
