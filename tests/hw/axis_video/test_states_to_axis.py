"""``StatesToAxis``: the state words on AXI4-Stream, and the soft reset's close of an
open line.

``ref_*`` say what each beat must carry (the layouts' own pack/unpack), ``rtl_*`` run the
adapter with random ``tvalid`` gaps and ``tready`` back-pressure.
"""

import pytest

from amaranth.hdl import Module, ResetInserter, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.hw.axis_video import STATE_TUSER, StatesToAxis, state_out_signature
from dptbd.hw.layouts import pack_state_word, pack_states, state_layout
from helpers.axis_harness import (check_axis_rules, config, packets, rtl_adapter_beats,
                                  soft_reset_trace)


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
    ``at`` (never if None): :func:`helpers.axis_harness.soft_reset_trace`."""
    dut = StateCloser(cfg)
    flat = [(int(pack_states(cfg, **w)), i == 0) for words in frames
            for i, w in enumerate(words)]
    return soft_reset_trace(dut, dut.states, dut.state, flat, at, seed, offer=0.7,
                            tail=2 * cfg.width + 4)


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
