"""The harnesses of the AXI4-Stream output adapters of ``dptbd_axi``: ``m_axis_cand``
(:class:`CandidatesHarness`) and ``m_axis_state`` (:class:`StatesHarness`), each behind a core
stream that keeps the stream rules until the core's reset (a soft reset)."""

from __future__ import annotations

from amaranth.hdl import Assert, Assume, Cover, ResetInserter

from dptbd.config import DPConfig
from dptbd.hw.axis_video import CandidatesToAxis, StatesToAxis
from dptbd.sim.formal.harness import Elaborated, Harness
from dptbd.sim.formal.harnesses.tiny import tiny_config
from dptbd.sim.formal.properties import axis_manager, packet_open

__all__ = ["CandidatesHarness", "StatesHarness"]


def _core_stream(m, past, src, restart, name):
    """Assume the core's stream keeps the stream rules, except across a ``restart`` (the
    core is reset then)."""
    stall = past(src.valid & ~src.ready & ~restart, f"{name}_past_stall")
    held = past(src.payload.as_value(), f"{name}_past_payload")
    with m.If(stall & ~past.rst):
        m.d.comb += [Assume(src.valid), Assume(src.payload.as_value() == held)]


class CandidatesHarness(Harness):
    """``m_axis_cand`` as :class:`~dptbd.hw.axis_video.CandidatesToAxis` drives it, behind a
    core stream that keeps the stream rules (until a ``restart`` resets it), with any
    ``soft_reset`` / ``hold`` / ``tready`` sequence.

    Asserted: the AXI4-Stream manager rules (also through a soft reset); ``tuser[0]`` on
    exactly the first word of each list; ``restart`` (the core's reset) only when no list is
    open after this cycle: every list ends with ``tlast``.
    """

    adapter = CandidatesToAxis

    def __init__(self, cfg: DPConfig | None = None):
        super().__init__()
        self.cfg = cfg or tiny_config()

    def check(self, m, past):
        dut = Elaborated(self.adapter(self.cfg))
        m.submodules.dut = dut.fragment
        adapter = dut.component
        self.free_inputs(m, adapter, "dut")
        out, src = adapter.cand, adapter.candidates
        _core_stream(m, past, src, adapter.restart, "core")
        axis_manager(m, past, tvalid=out.tvalid, tready=out.tready,
                     payload=[out.tdata, out.tuser, out.tlast], name="m_axis_cand")
        opened, after = packet_open(m, tvalid=out.tvalid, tready=out.tready,
                                    tlast=out.tlast, name="cand")
        with m.If(adapter.restart):
            m.d.sync += opened.eq(0)     # a word of this cycle after the restart: none
            m.d.comb += Assert(~after, "m_axis_cand: core reset with a list open")
        with m.If(out.tvalid):
            m.d.comb += Assert(out.tuser[0] == ~opened,
                               "m_axis_cand: tuser[0] not on exactly a list's first word")
        self.invariants(m, dut, opened)
        take = out.tvalid & out.tready
        busy_held = past(out.tvalid & ~out.tready & adapter.soft_reset, "soft_reset_on_held")
        # a trailer other than the core's word (the cut trailer) taken, the cycle before a
        # restart (registered: nothing is offered in its own cycle)
        cut_taken = past(take & out.tlast & (out.tdata != src.payload.as_value()), "cut_taken")
        m.d.comb += [
            Cover(take & out.tlast & ~out.tuser[0]),                # a list of 2+ words
            Cover(adapter.restart & cut_taken & ~past.rst),
            Cover(busy_held & take & ~past.rst),    # a held word delivered after the request
            Cover(adapter.restart & ~take & ~opened),                  # restart, nothing open
        ]

    def invariants(self, m, dut, opened):
        m.d.comb += Assert(dut.signal("list_start") == ~opened,
                           "CandidatesToAxis: list_start disagrees with the open list")


class StatesHarness(Harness):
    """``m_axis_state`` as :class:`~dptbd.hw.axis_video.StatesToAxis` drives it: the core's
    states stream keeps the stream rules; ``closing`` (a soft reset) is held until the
    ``restart``, which comes only when the adapter is ``closed`` (as in ``dptbd_axi``) and
    resets the adapter and the core.

    Asserted: the AXI4-Stream manager rules; no line open at a ``restart``; a filler word
    (``tuser[3]``) only while closing.
    """

    def __init__(self, cfg: DPConfig | None = None):
        super().__init__()
        self.cfg = cfg or tiny_config()

    def check(self, m, past):
        restart = self.free(1, "restart")
        dut = Elaborated(ResetInserter({"sync": restart})(StatesToAxis(self.cfg)))
        m.submodules.dut = dut.fragment
        adapter = dut.component
        self.free_inputs(m, adapter, "dut")
        out, src = adapter.state, adapter.states
        m.d.comb += Assume(~restart | (adapter.closing & adapter.closed))
        closing = past(adapter.closing & ~restart, "past_closing")
        with m.If(closing & ~past.rst):
            m.d.comb += Assume(adapter.closing)
        _core_stream(m, past, src, restart, "core")
        axis_manager(m, past, tvalid=out.tvalid, tready=out.tready,
                     payload=[out.tdata, out.tuser, out.tlast], name="m_axis_state")
        opened, after = packet_open(m, tvalid=out.tvalid, tready=out.tready,
                                    tlast=out.tlast, name="state")
        with m.If(restart):
            m.d.sync += opened.eq(0)
            m.d.comb += Assert(~after, "m_axis_state: adapter reset with a line open")
        with m.If(out.tvalid & out.tuser[3]):
            m.d.comb += Assert(adapter.closing, "m_axis_state: a filler word while not closing")
        m.d.comb += Assert(dut.signal("line_open") == opened,
                           "StatesToAxis: line_open disagrees with the open line")
        take = out.tvalid & out.tready
        m.d.comb += [
            Cover(take & out.tuser[3] & out.tlast),                  # a line closed by fillers
            Cover(restart & take & out.tlast),
            Cover(take & out.tlast & ~out.tuser[3] & opened),
            # a line closed by W fillers: its words since the last tlast were a multiple of W
            Cover(take & out.tuser[3] & (dut.signal("column") == 0)),
        ]
