"""AXI4-Stream video adapters: ``AxisToPixels``, ``CandidatesToAxis`` and ``StatesToAxis``,
and the soft reset's close of an open list or line.

``ref_*`` say what each beat must carry (the layouts' own pack/unpack), ``rtl_*`` run the
adapters with random ``tvalid`` gaps and ``tready`` back-pressure.
"""

import random

import pytest

from amaranth.hdl import Module, ResetInserter, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out
from amaranth.sim import Simulator

from dptbd.hw.axis_video import (STATE_TUSER, AxisToPixels, CandidatesToAxis, StatesToAxis,
                                 byte_padded, state_out_signature)
from dptbd.hw.candidate_layout import (pack_cut_trailer, pack_record, pack_trailer,
                                       unpack_candidate)
from dptbd.hw.layouts import pack_pixel, pack_state_word, pack_states, state_layout
from helpers.hw_harness import simulate
from helpers.seg_harness import make_config


def config():
    return make_config(width=8, height=6, input_bits=10, candidate_count=3)


def test_byte_padded():
    assert [byte_padded(b) for b in (1, 8, 9, 16, 17)] == [8, 8, 16, 16, 24]


def test_video_in_maps_tuser0_and_low_tdata_bits():
    cfg = config()
    dut = AxisToPixels(cfg)
    beats = [(p, s) for p, s in zip([5, 1023, 0, 77], [1, 0, 0, 1])]
    got = []

    async def bench(ctx):
        ctx.set(dut.pixels.ready, 1)
        for pixel, sof in beats:
            ctx.set(dut.video.tdata, pixel | 0xF000)            # bits above B_in ignored
            ctx.set(dut.video.tuser, sof)
            ctx.set(dut.video.tvalid, 1)
            assert ctx.get(dut.video.tready) and ctx.get(dut.accepted)
            got.append(ctx.get(dut.pixels.payload.as_value()))
            await ctx.delay(1e-8)
        ctx.set(dut.pixels.ready, 0)
        assert not ctx.get(dut.video.tready) and not ctx.get(dut.accepted)

    sim = Simulator(dut)                                         # combinational: no clock
    sim.add_testbench(bench)
    sim.run()
    assert got == [pack_pixel(cfg, p, s) for p, s in beats]


def ref_candidate_beats(words):
    """(tdata, tuser, tlast) per word: tuser[0] on a list's first word, tlast on trailers."""
    out, start = [], 1
    for word, trailer in words:
        out.append((word, start, trailer))
        start = trailer
    return out


def rtl_adapter_beats(dut, inp, out, payloads, seed):
    """Feed ``payloads`` to ``inp`` with random gaps, take ``out`` with random back-pressure:
    the (tdata, tuser, tlast) of each transfer and the cycles ``dut.stalled`` was high
    (checked against tvalid and not tready in every cycle)."""
    rng = random.Random(seed)
    got, stalls = [], []

    async def source(ctx):
        for payload in payloads:
            ctx.set(inp.payload.as_value(), payload)
            ctx.set(inp.valid, 1)
            await ctx.tick().until(inp.ready)
            ctx.set(inp.valid, 0)
            while rng.random() < 0.3:
                await ctx.tick()

    async def sink(ctx):
        while len(got) < len(payloads):
            ready = rng.random() < 0.6
            ctx.set(out.tready, ready)
            stalls.append(ctx.get(dut.stalled))
            assert stalls[-1] == (ctx.get(out.tvalid) and not ready)
            if ready and ctx.get(out.tvalid):
                got.append((ctx.get(out.tdata), ctx.get(out.tuser), ctx.get(out.tlast)))
            await ctx.tick()

    simulate(dut, source, sink)
    return got, sum(stalls)


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


def state_cases(cfg):
    """Two frames of two lines of three pixels, the second ending a segment (the adapter
    only follows the flags, so the frame need not be the configuration's W x H)."""
    words = []
    for frame in range(2):
        for i in range(6):
            words.append(dict(energy=100 * frame + 7 * i, direction=i % cfg.n_moves,
                              end_of_line=int(i % 3 == 2), end_of_frame=int(i == 5),
                              end_of_segment=int(frame == 1 and i == 5)))
    return words


def ref_state_beats(cfg, words):
    """(tdata, tuser, tlast) per word: (E, d) as a state word; tuser = start of frame,
    end of frame, end of segment; tlast = end of line."""
    out, start = [], 1
    for w in words:
        user = (start << STATE_TUSER["start_of_frame"]
                | w["end_of_frame"] << STATE_TUSER["end_of_frame"]
                | w["end_of_segment"] << STATE_TUSER["end_of_segment"])
        out.append((pack_state_word(cfg, w["energy"], w["direction"]), user, w["end_of_line"]))
        start = w["end_of_frame"]
    return out


def rtl_state_beats(cfg, words, seed=3):
    dut = StatesToAxis(cfg)
    return rtl_adapter_beats(dut, dut.states, dut.state,
                             [int(pack_states(cfg, **w)) for w in words], seed)


def test_states_out_flags_frames_lines_and_segments():
    cfg = config()
    words = state_cases(cfg)
    want = ref_state_beats(cfg, words)
    assert [w[1] & 1 for w in want] == [1, 0, 0, 0, 0, 0] * 2
    got, stalls = rtl_state_beats(cfg, words)
    assert got == want and stalls > 0


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
    cycle ``at`` (never if None). Returns the per-cycle trace of the port and ``restart`` / ``busy``."""
    dut = CandidatesToAxis(cfg)
    flat = [(w, t, i == 0) for lst in lists for i, (w, t) in enumerate(lst)]
    rng = random.Random(seed)
    trace = []

    async def bench(ctx):
        index, offering, cycle = 0, False, 0
        while index < len(flat) or (at is not None and cycle <= at + 3):
            if not offering and index < len(flat) and rng.random() < 0.6:
                offering = True
            ctx.set(dut.candidates.valid, offering)
            if index < len(flat):
                ctx.set(dut.candidates.payload.as_value(), flat[index][0])
            ctx.set(dut.soft_reset, cycle == at)
            ctx.set(dut.cand.tready, rng.random() < 0.5)
            row = {name: ctx.get(getattr(dut.cand, name)) for name in
                   ("tvalid", "tready", "tdata", "tuser", "tlast")}
            row.update(restart=ctx.get(dut.restart), busy=ctx.get(dut.busy),
                       stalled=ctx.get(dut.stalled), taken=offering and
                       ctx.get(dut.candidates.ready))
            trace.append(row)
            if row["taken"]:
                index, offering = index + 1, False
            if row["restart"]:
                offering = False
                while index < len(flat) and not flat[index][2]:
                    index += 1                               # the core drops the list's rest
            await ctx.tick()
            cycle += 1
            assert cycle < 2000

    simulate(dut, bench)
    return trace


def check_axis_rules(trace):
    """AXI4-Stream on every cycle: tvalid never drops, and tdata / tuser / tlast never
    change, while a word waits for tready; ``stalled`` is tvalid and not tready."""
    for before, now in zip(trace, trace[1:]):
        if before["tvalid"] and not before["tready"]:
            assert now["tvalid"]
            assert [now[k] for k in ("tdata", "tuser", "tlast")] == \
                [before[k] for k in ("tdata", "tuser", "tlast")]
    for row in trace:
        assert row["stalled"] == (row["tvalid"] and not row["tready"])


def packets(trace):
    """The transfers, cut into packets at tlast: [[(tdata, tuser), …], …]."""
    out, current = [], []
    for row in trace:
        if row["tvalid"] and row["tready"]:
            current.append((row["tdata"], row["tuser"]))
            if row["tlast"]:
                out.append(current)
                current = []
    assert current == []                                    # every packet ends with tlast
    return out


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


class StateCloser(wiring.Component):
    """``StatesToAxis`` served as ``AXITop`` serves it: ``soft_reset`` (a one-cycle request)
    raises ``closing`` until ``restart`` (= closing and closed), which resets the adapter."""

    def __init__(self, cfg):
        self._cfg = cfg
        super().__init__({"states": In(stream.Signature(state_layout(cfg))),
                          "state": Out(state_out_signature(cfg)),
                          "soft_reset": In(1), "busy": Out(1), "restart": Out(1),
                          "stalled": Out(1)})

    def elaborate(self, platform):
        m = Module()
        m.submodules.adapter = adapter = ResetInserter(self.restart)(StatesToAxis(self._cfg))
        wiring.connect(m, wiring.flipped(self.states), adapter.states)
        wiring.connect(m, adapter.state, wiring.flipped(self.state))
        pending = Signal()
        m.d.comb += [self.busy.eq(self.soft_reset | pending), adapter.closing.eq(self.busy),
                     self.restart.eq(self.busy & adapter.closed),
                     self.stalled.eq(adapter.stalled)]
        m.d.sync += pending.eq(self.busy & ~self.restart)
        return m


def soft_reset_frames(cfg):
    """Three frames of two W-word lines (the adapter follows the flags only)."""
    frames = []
    for frame in range(3):
        words = []
        for i in range(2 * cfg.width):
            words.append(dict(energy=1000 * frame + 11 * i + 1, direction=(i + frame) % 7,
                              end_of_line=int(i % cfg.width == cfg.width - 1),
                              end_of_frame=int(i == 2 * cfg.width - 1),
                              end_of_segment=int(frame == 1 and i == 2 * cfg.width - 1)))
        frames.append(words)
    return frames


def rtl_state_soft_reset(cfg, frames, at, seed):
    """Run :class:`StateCloser` with a source that behaves like the core's broadcast (a word
    offered stays offered until taken; on ``restart`` the offered word and the rest of its
    frame are dropped, the next frame follows) and random ``tready``; ``soft_reset`` in cycle
    ``at`` (never if None). Returns the per-cycle trace of the port and ``restart`` / ``busy``."""
    dut = StateCloser(cfg)
    flat = [(int(pack_states(cfg, **w)), i == 0) for words in frames
            for i, w in enumerate(words)]
    rng = random.Random(seed)
    trace = []

    async def bench(ctx):
        index, offering, cycle = 0, False, 0
        while index < len(flat) or (at is not None and cycle <= at + 2 * cfg.width + 4):
            if not offering and index < len(flat) and rng.random() < 0.7:
                offering = True
            ctx.set(dut.states.valid, offering)
            if index < len(flat):
                ctx.set(dut.states.payload.as_value(), flat[index][0])
            ctx.set(dut.soft_reset, cycle == at)
            ctx.set(dut.state.tready, rng.random() < 0.5)
            row = {name: ctx.get(getattr(dut.state, name)) for name in
                   ("tvalid", "tready", "tdata", "tuser", "tlast")}
            row.update(restart=ctx.get(dut.restart), busy=ctx.get(dut.busy),
                       stalled=ctx.get(dut.stalled),
                       taken=offering and ctx.get(dut.states.ready))
            trace.append(row)
            if row["taken"]:
                index, offering = index + 1, False
            if row["restart"]:
                offering = False
                while index < len(flat) and not flat[index][1]:
                    index += 1                               # the core drops the frame's rest
            await ctx.tick()
            cycle += 1
            assert cycle < 2000

    simulate(dut, bench)
    return trace


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_soft_reset_closes_the_state_line_in_every_cycle(seed):
    """A soft reset in every cycle of three frames of states (random tready and source
    gaps, the same up to the request): the AXI4-Stream rules hold in every cycle; every
    packet is a line of W words ending with tlast; a word offered before the request is
    still delivered; a line left open is completed by fillers (tdata 0, tuser = cut only)
    up to W words; restart pulses once — in the request's cycle when nothing is in flight,
    else in the cycle the line's last word is taken; busy from the request to restart; the
    words that are not fillers are the reference's, in order, from each frame's start."""
    cfg = config()
    frames = soft_reset_frames(cfg)
    ref = [ref_state_beats(cfg, words) for words in frames]
    cut_user = 1 << STATE_TUSER["cut"]
    seen = {f"fill {k}": 0 for k in range(1, cfg.width)}
    seen.update(whole=0, waited=0)
    span = len(rtl_state_soft_reset(cfg, frames, at=None, seed=seed))
    for at in range(0, span):
        trace = rtl_state_soft_reset(cfg, frames, at, seed=seed)
        check_axis_rules(trace)
        lines = packets(trace)
        assert {len(line) for line in lines} == {cfg.width}
        taken = [c for c, row in enumerate(trace) if row["tvalid"] and row["tready"]]
        beats = [(trace[c]["tdata"], trace[c]["tuser"], trace[c]["tlast"]) for c in taken]
        fillers = [i for i, b in enumerate(beats) if b[1] & cut_user]
        assert all(beats[i] == (0, cut_user, int(i % cfg.width == cfg.width - 1))
                   for i in fillers)
        restarts = [c for c, row in enumerate(trace) if row["restart"]]
        assert len(restarts) == 1 and restarts[0] >= at
        busy = [c for c, row in enumerate(trace) if row["busy"]]
        assert busy == list(range(at, restarts[0] + 1))
        # the fillers are the cut line's tail, sent in the soft reset
        during = [i for i, c in enumerate(taken) if at <= c <= restarts[0]]
        assert fillers == during[len(during) - len(fillers):]
        # what is not a filler: the reference frames, the one the reset found begun a
        # prefix, the others whole
        data = [b for b in beats if not b[1] & cut_user]
        sent = len([c for c in taken if c <= restarts[0] and not trace[c]["tuser"] & cut_user])
        starts = [sum(len(r) for r in ref[:f]) for f in range(len(ref) + 1)]
        done = max(s for s in starts if s <= sent)                # the cut frame's start
        resume = min(s for s in starts if s >= sent)
        every = [b for r in ref for b in r]
        assert data == every[:sent] + every[resume:]
        # restart timing
        held = at > 0 and trace[at - 1]["tvalid"] and not trace[at - 1]["tready"]
        if held:
            first = taken[during[0]]
            assert trace[first]["tdata"] == trace[at - 1]["tdata"]
            seen["waited"] += 1
        if during:
            last = taken[during[-1]]
            assert trace[last]["tlast"] and restarts[0] == last
        else:
            assert restarts[0] == at and (sent - done) % cfg.width == 0
        if fillers:
            seen[f"fill {len(fillers)}"] += 1
            assert (sent - done) % cfg.width == cfg.width - len(fillers)
        else:
            seen["whole"] += 1
    assert min(seen.values()) > 0, seen


def test_soft_reset_after_a_resync_closes_the_line_without_tlast():
    """After a resync at the input (the interrupted frame's last line: 1 word, no tlast) the
    words since the last tlast reach W in the middle of the next line; a soft reset there
    must still close the open line (W fillers, the last with tlast) before the restart: in
    every cycle of the run, the words taken up to the restart end with tlast. (Found by the
    formal proof of m_axis_state, ``dptbd verify --formal``: the adapter closed only lines
    whose word count was not a multiple of W.)"""
    cfg = config()
    frames = soft_reset_frames(cfg)
    cut_user = 1 << STATE_TUSER["cut"]
    frames[0] = frames[0][:cfg.width + 1]                 # line 2 of frame 0: one word
    frames[0][-1] = dict(frames[0][-1], end_of_line=0, end_of_frame=0, end_of_segment=0)
    seen = 0
    span = len(rtl_state_soft_reset(cfg, frames, at=None, seed=0))
    for at in range(span):
        trace = rtl_state_soft_reset(cfg, frames, at, seed=0)
        check_axis_rules(trace)
        restart = [c for c, row in enumerate(trace) if row["restart"]][0]
        taken = [c for c, row in enumerate(trace[:restart + 1])
                 if row["tvalid"] and row["tready"]]
        assert not taken or trace[taken[-1]]["tlast"], at
        fillers = [c for c in taken if trace[c]["tuser"] & cut_user]
        seen += len(fillers) == cfg.width
    assert seen > 0                                       # the resync case was hit


@pytest.mark.parametrize("seed", range(3))
def test_busy_next_is_the_next_cycles_busy(seed):
    """``CandidatesToAxis(busy_ahead=True)``: ``busy_next`` is ``busy`` of the next cycle,
    given ``soft_reset_ahead`` (the next cycle's ``soft_reset``), under soft resets at any
    time (during a list, a held word, a close, back to back), ``hold`` and back-pressure."""
    cfg = config()
    dut = CandidatesToAxis(cfg, busy_ahead=True)
    rng = random.Random(seed)
    cycles = 600
    soft = [int(rng.random() < 0.04) for _ in range(cycles + 1)]
    trace = []

    async def bench(ctx):
        for cycle in range(cycles):
            ctx.set(dut.candidates.valid, rng.random() < 0.6)
            ctx.set(dut.candidates.payload.end_of_list, rng.random() < 0.3)
            ctx.set(dut.cand.tready, rng.random() < 0.5)
            ctx.set(dut.hold, rng.random() < 0.3)
            ctx.set(dut.soft_reset, soft[cycle])
            ctx.set(dut.soft_reset_ahead, soft[cycle + 1])
            trace.append((ctx.get(dut.busy), ctx.get(dut.busy_next), ctx.get(dut.restart)))
            await ctx.tick()

    simulate(dut, bench)
    assert [n for _b, n, _r in trace[:-1]] == [b for b, _n, _r in trace[1:]]
    assert sum(r for _b, _n, r in trace) > 10 and sum(soft) > 10
