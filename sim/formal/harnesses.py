"""The formal harnesses: each wraps one component (or the ``dptbd_axi`` top) with the rules
of its environment (``Assume``), the properties it must keep (``Assert``) and cover
statements that show the properties are not vacuous (``Cover``). ``docs/gateware.md``
("Formal proofs") states each property and the build it is proven on.
"""

from __future__ import annotations

from amaranth.hdl import Assert, Assume, Cover, Module, ResetInserter, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.axi_lite import axi_lite_signature
from dptbd.hw.axi_top import AXITop
from dptbd.hw.axis_video import CandidatesToAxis, StatesToAxis, candidate_out_signature
from dptbd.hw.dp_pipeline import DPPipeline
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.input_credit import InputCredit
from dptbd.hw.thermometer_fifo import ThermometerFIFO
from dptbd.sim.formal.harness import Elaborated, Harness
from dptbd.hw.register_file import RegisterFile
from dptbd.sim.formal.properties import (axil_subordinate, axis_manager, axis_subordinate,
                                         packet_open)

__all__ = ["tiny_config", "CandidatesHarness", "StatesHarness", "DroppingCandidatesToAxis",
           "CreditFifoHarness", "RegistersHarness", "PipelineHarness", "AXITopHarness",
           "DroppingCandidatesHarness", "EagerAXILite", "EagerAXILiteHarness"]


def tiny_config(**overrides) -> DPConfig:
    """The small build the proofs run on: 5 x 4 frames (the smallest the read-ahead of
    r = 1 allows), 1-bit pixels, 4-bit energy, F = 1 (weight codes c / 2), K = 2, one
    candidate (C = 2), a 2-bin histogram."""
    return DPConfig(**{"width": 5, "height": 4, "segment_frames": 2, "input_bits": 1,
                       "energy_bits": 4, "weight_frac_bits": 1, "histogram_bits": 1,
                       "candidate_count": 1, **overrides})


def _count(flags):
    """Number of 1 bits of a thermometer code (its count)."""
    total = 0
    for bit in flags:
        total = total + bit
    return total


def _thermometer(m, flags, name: str) -> None:
    """Assert that ``flags`` is a thermometer code (``flags[k]`` implies ``flags[k - 1]``)."""
    for k in range(1, len(flags)):
        with m.If(flags[k]):
            m.d.comb += Assert(flags[k - 1], f"{name}: not a thermometer code")


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
        m.d.comb += [
            Cover(take & out.tlast & ~out.tuser[0]),                # a list of 2+ words
            Cover(adapter.restart & take & out.tlast & (out.tdata != src.payload.as_value())),
            Cover(busy_held & take & ~past.rst),    # a held word delivered after the request
            Cover(adapter.restart & ~take & ~opened),                  # restart, nothing open
        ]

    def invariants(self, m, dut, opened):
        m.d.comb += Assert(dut.signal("list_start") == ~opened,
                           "CandidatesToAxis: list_start disagrees with the open list")


class DroppingCandidatesToAxis(wiring.Component):
    """A deliberately broken ``m_axis_cand`` adapter (known-bad harness): the soft reset
    resets the core at once, dropping a word that is offered and not taken — the violation
    the outside testbench found before :class:`~dptbd.hw.axis_video.CandidatesToAxis`
    served the soft reset. It does not cut a list (a request while a list is open, or in a
    cycle a word is taken, is ignored), so only the dropped word breaks a rule."""

    def __init__(self, cfg: DPConfig):
        super().__init__({
            "candidates": In(stream.Signature(candidate_layout(cfg))),
            "cand": Out(candidate_out_signature(cfg)),
            "soft_reset": In(1), "hold": In(1), "restart": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        src, out = self.candidates, self.cand
        list_start = Signal(init=1)
        m.d.comb += [
            out.tdata.eq(src.payload.as_value()), out.tvalid.eq(src.valid),
            out.tlast.eq(src.payload.end_of_list), out.tuser[0].eq(list_start),
            src.ready.eq(out.tready),
            self.restart.eq(self.soft_reset & list_start & ~(src.valid & out.tready)),
        ]
        with m.If(self.restart):
            m.d.sync += list_start.eq(1)
        with m.Elif(out.tvalid & out.tready):
            m.d.sync += list_start.eq(out.tlast)
        return m


class DroppingCandidatesHarness(CandidatesHarness):
    """:class:`CandidatesHarness` on :class:`DroppingCandidatesToAxis`: must FAIL."""

    adapter = DroppingCandidatesToAxis

    def invariants(self, m, dut, opened):
        pass


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


class CreditFifoHarness(Harness):
    """The DP core's output path: :class:`~dptbd.hw.input_credit.InputCredit` in front of a
    pipeline of ``latency`` cycles (no stall) into a
    :class:`~dptbd.hw.thermometer_fifo.ThermometerFIFO` of ``depth`` words, as in
    :class:`~dptbd.hw.dp_core.DPCore` (depth = latency + 2 by default), the consumer's
    ``ready`` free. Each accepted word carries its sequence number.

    Asserted: a word leaving the pipeline always finds room (no overflow); the FIFO never
    offers a word it does not hold (no underflow); words accepted − words handed out ==
    words in flight <= depth; after a reset nothing is offered before a word is accepted;
    with ``order``: words come out in order (their sequence numbers, bounded proof).
    """

    def __init__(self, latency: int = 2, depth: int | None = None, order: bool = False):
        super().__init__()
        self.latency = latency
        self.depth = depth if depth is not None else latency + 2
        self.order = order

    def check(self, m, past):
        seq_bits = 4
        credit = Elaborated(InputCredit(self.depth))
        fifo = Elaborated(ThermometerFIFO(seq_bits, self.depth))
        m.submodules.credit, m.submodules.fifo = credit.fragment, fifo.fragment
        c, f = credit.component, fifo.component
        valid, ready = self.free(1, "in_valid"), self.free(1, "out_ready")
        accept = valid & c.ready
        hand_out = f.r.valid & ready
        pipe_valid = [accept]
        seq_in, seq_out = Signal(seq_bits), Signal(seq_bits)
        pipe_data = [seq_in]
        for stage in range(self.latency):
            v, d = Signal(name=f"pipe{stage}_valid"), Signal(seq_bits, name=f"pipe{stage}_seq")
            m.d.sync += [v.eq(pipe_valid[-1]), d.eq(pipe_data[-1])]
            pipe_valid.append(v)
            pipe_data.append(d)
        with m.If(accept):
            m.d.sync += seq_in.eq(seq_in + 1)
        with m.If(hand_out):
            m.d.sync += seq_out.eq(seq_out + 1)
        m.d.comb += [f.w.valid.eq(pipe_valid[-1]), f.w.payload.eq(pipe_data[-1]),
                     f.r.ready.eq(ready), c.accept.eq(accept), c.handed_out.eq(hand_out)]
        # conservation
        in_flight = Signal(range(2 * self.depth + 2))
        m.d.sync += in_flight.eq(in_flight + accept - hand_out)
        stored = Signal(range(2 * self.depth + 2))       # written to the FIFO, not handed out
        m.d.sync += stored.eq(stored + (f.w.valid & f.w.ready) - hand_out)
        piped = _count(pipe_valid[1:])
        started = Signal()                               # a word accepted since the reset
        with m.If(accept):
            m.d.sync += started.eq(1)
        with m.If(f.w.valid):
            m.d.comb += Assert(f.w.ready, "FIFO overflow: a word left the pipeline without room")
        with m.If(f.r.valid):
            m.d.comb += Assert(stored != 0, "FIFO underflow: a word offered that it does not hold")
        with m.If(~started):
            m.d.comb += Assert(~f.r.valid, "an output word before any input was accepted")
        m.d.comb += [
            Assert(in_flight == piped + stored, "accepted - handed out != words in flight"),
            Assert(in_flight <= self.depth, "more words in flight than the FIFO holds"),
        ]
        if self.order:
            with m.If(f.r.valid):
                m.d.comb += Assert(f.r.payload == seq_out, "FIFO output out of order")
        # invariants of the thermometer counters (what k-induction needs)
        committed = credit.sub("committed").component.at_least
        level = fifo.sub("level").component.at_least
        _thermometer(m, committed, "InputCredit")
        _thermometer(m, level, "ThermometerFIFO level")
        m.d.comb += [
            Assert(_count(committed) == in_flight, "credit count != words in flight"),
            Assert(_count(level) + f.r.valid == stored, "FIFO level != words stored"),
            Assert(c.ready == (past(_count(committed) < self.depth - 1, "past_room") & ~past.rst),
                   "credit ready != room a cycle earlier"),
        ]
        m.d.comb += [
            Cover(in_flight == self.depth),
            Cover(hand_out & (seq_out == 3)),
            Cover(valid & ~c.ready & started),
        ]


class RegistersHarness(Harness):
    """The AXI4-Lite port and the register block (:class:`~dptbd.hw.register_file.
    RegisterFile`, its :class:`~dptbd.hw.axi_lite.AXILiteSubordinate` inside), any event
    pulses, any manager that keeps the AXI4-Lite rules.

    Asserted: the AXI4-Lite subordinate rules (:func:`~dptbd.sim.formal.properties.
    axil_subordinate`: B and R held until taken and stable, no response without its request,
    a write response only after both AW and W, one transaction at a time); a refused write
    (SLVERR on a register that stores: a setting out of its limits, an unaligned address, a
    LUT word out of range or not fully strobed) changes no setting, no enable bit, clears no
    sticky / interrupt bit and writes no LUT entry; a sticky / interrupt bit (W1C) goes from
    1 to 0 only in the cycle after an accepted write of a 1 to it.
    """

    def __init__(self, cfg: DPConfig | None = None):
        super().__init__()
        self.cfg = cfg or tiny_config()

    def check(self, m, past):
        regs = Elaborated(RegisterFile(self.cfg))
        m.submodules.regs = regs.fragment
        rf = regs.component
        self.free_inputs(m, rf, "regs")
        aw_out, w_out, ar_out = axil_subordinate(m, past, rf.axil)
        bus = regs.sub("axil").component.bus
        regmap = rf.register_map
        refused = past(bus.w_stb & bus.w_err, "past_refused")
        past_addr = past(bus.addr, "past_addr")
        past_data = past(bus.w_data, "past_w_data")
        past_strb = past(bus.w_strb, "past_w_strb")
        past_write = past(bus.w_stb, "past_w_stb")
        for reg in regmap.registers:
            for field in reg.fields:
                if field.kind == "setting":
                    value = getattr(rf, field.name)
                elif field.kind in ("enable", "sticky", "interrupt"):
                    value = regs.signal(f"{reg.name}_{field.name}".lower())
                else:
                    continue
                before = past(value, f"past_{reg.name}_{field.name}".lower())
                what = f"{reg.name}.{field.name}"
                with m.If(refused & ~past.rst):
                    if field.kind in ("sticky", "interrupt"):
                        m.d.comb += Assert((before & ~value) == 0,
                                           f"{what}: cleared by a refused write")
                    else:
                        m.d.comb += Assert(value == before,
                                           f"{what}: changed by a refused write")
                if field.kind in ("sticky", "interrupt"):
                    for bit in range(field.width):
                        at = field.lsb + bit
                        ones = (past_write & ~refused & (past_addr == reg.address)
                                & past_strb[at // 8] & past_data[at])
                        with m.If(before[bit] & ~value[bit] & ~past.rst):
                            m.d.comb += Assert(ones, f"{what}[{bit}]: cleared without a "
                                                     f"written 1 (W1C)")
        with m.If(refused & ~past.rst):
            m.d.comb += Assert(~rf.lut_we, "LUT: written by a refused write")
        b, r = rf.axil.b, rf.axil.r
        m.d.comb += [
            Cover(b.bvalid & b.bready & (b.bresp == 0)),
            Cover(b.bvalid & b.bready & (b.bresp == 2) & refused),     # a refused write
            Cover(r.rvalid & r.rready & (r.rresp == 0)),
        ]
        for reg in regmap.registers:                    # an accepted write of a setting
            if reg.kind == "setting":
                m.d.comb += Cover(past_write & ~refused & (past_addr == reg.address))
                break
        port = regs.sub("axil")
        m.d.comb += [
            Assert(aw_out == port.signal("have_aw") + b.bvalid, "AW outstanding != held"),
            Assert(w_out == port.signal("have_w") + b.bvalid, "W outstanding != held"),
            Assert(ar_out == r.rvalid, "AR outstanding != rvalid"),
        ]
        irq_status = next(reg for reg in regmap.registers if reg.name == "IRQ_STATUS")
        field = irq_status.fields[0]
        bit = regs.signal(f"irq_status_{field.name}")
        m.d.comb += Cover(past(bit, "past_irq_bit") & ~bit & ~past.rst)      # a W1C clear


class PipelineHarness(Harness):
    """:class:`~dptbd.hw.dp_pipeline.DPPipeline` on the tiny build: any pixel stream (the
    stream rules assumed), any consumer, any run-time K; no LUT write (the flow control
    does not depend on the weights; their writes only make the solver slower).

    Asserted: the ``states`` stream keeps the stream rules; never more state words out than
    pixels accepted; pixels accepted − state words out <= the output FIFO's depth (the
    credit); nothing offered after a reset before a pixel is accepted.
    """

    def __init__(self, cfg: DPConfig | None = None):
        super().__init__()
        self.cfg = cfg or tiny_config()

    def check(self, m, past):
        m.submodules.dut = dut = DPPipeline(self.cfg)
        self.free_inputs(m, dut, "dut", skip=("lut_addr", "lut_data", "lut_we"))
        src, out = dut.pixels, dut.states
        axis_subordinate(m, past, tvalid=src.valid, tready=src.ready,
                         payload=[src.payload.as_value()], name="pixels")
        axis_manager(m, past, tvalid=out.valid, tready=out.ready,
                     payload=[out.payload.as_value()], name="states")
        accepted = src.valid & src.ready
        taken = out.valid & out.ready
        in_flight = Signal(range(-4, 2 * dut.output_fifo_depth + 4))
        m.d.sync += in_flight.eq(in_flight + accepted - taken)
        started = Signal()
        with m.If(accepted):
            m.d.sync += started.eq(1)
        m.d.comb += [
            Assert(in_flight >= 0, "states: more words out than pixels accepted"),
            Assert(in_flight <= dut.output_fifo_depth,
                   "states: more pixels in flight than the output FIFO holds"),
        ]
        with m.If(~started):
            m.d.comb += Assert(~out.valid, "states: a word before any pixel was accepted")
        with m.If(taken):
            m.d.comb += Assert(in_flight > 0, "states: a word without an accepted pixel")
        m.d.comb += [Cover(taken & (in_flight == 1) & started),
                     Cover(in_flight == dut.output_fifo_depth)]


class AXITopHarness(Harness):
    """``dptbd_axi`` (:class:`~dptbd.hw.axi_top.AXITop`, ``state_output=True``) on the tiny
    build: any video manager and AXI4-Lite manager that keep their protocol's rules, any
    ``tready`` on both outputs, ``aresetn`` at any time.

    Asserted: the AXI4-Stream manager rules on ``m_axis_cand`` and ``m_axis_state`` (through
    soft resets written over AXI4-Lite); ``tuser[0]`` of ``m_axis_cand`` on exactly a list's
    first word; the core is reset (soft reset) only with no list and no line open; the
    AXI4-Lite subordinate rules; no output word after ``aresetn`` before a pixel is
    accepted; never more state words (fillers aside) than pixels accepted since the last
    reset.
    """

    defines_sync = False

    def __init__(self, cfg: DPConfig | None = None):
        super().__init__()
        self.cfg = cfg or tiny_config()

    def check(self, m, past):
        top = Elaborated(AXITop(self.cfg, state_output=True))
        m.submodules.dut = top.fragment
        t = top.component
        m.d.comb += [t.aclk.eq(self.clk), t.aresetn.eq(~self.rst)]
        self.free_inputs(m, t, "dut", skip=("aclk", "aresetn"))
        restart = top.sub("cand_out").component.restart
        lut = t.register_map.window("LUT")
        m.d.comb += Assume(~t.s_axil_awvalid | (t.s_axil_awaddr < lut.base)
                           | (t.s_axil_awaddr >= lut.end))      # no LUT write (solver time)
        axis_subordinate(m, past, tvalid=t.s_axis_video_tvalid, tready=t.s_axis_video_tready,
                         payload=[t.s_axis_video_tdata, t.s_axis_video_tuser,
                                  t.s_axis_video_tlast], name="s_axis_video")
        opens = []
        for port in ("m_axis_cand", "m_axis_state"):
            tvalid, tready, tlast = (getattr(t, f"{port}_{n}") for n in ("tvalid", "tready",
                                                                         "tlast"))
            axis_manager(m, past, tvalid=tvalid, tready=tready,
                         payload=[getattr(t, f"{port}_tdata"), getattr(t, f"{port}_tuser"),
                                  tlast], name=port)
            opened, after = packet_open(m, tvalid=tvalid, tready=tready, tlast=tlast,
                                        name=port)
            with m.If(restart):
                m.d.sync += opened.eq(0)
                m.d.comb += Assert(~after, f"{port}: soft reset of the core with a packet open")
            opens.append(opened)
        with m.If(t.m_axis_cand_tvalid):
            m.d.comb += Assert(t.m_axis_cand_tuser[0] == ~opens[0],
                               "m_axis_cand: tuser[0] not on exactly a list's first word")
        axil_subordinate(m, past, _AxilView(t))
        accepted = t.s_axis_video_tvalid & t.s_axis_video_tready
        started = Signal()
        with m.If(accepted):
            m.d.sync += started.eq(1)
        with m.If(~started):
            m.d.comb += Assert(~t.m_axis_cand_tvalid & ~t.m_axis_state_tvalid,
                               "an output word after aresetn before any pixel was accepted")
        state_word = t.m_axis_state_tvalid & t.m_axis_state_tready & ~t.m_axis_state_tuser[3]
        pending = Signal(8)                  # pixels accepted - state words, since a reset
        with m.If(restart):
            m.d.sync += pending.eq(0)
        with m.Else():
            m.d.sync += pending.eq(pending + accepted - state_word)
        with m.If(state_word):
            m.d.comb += Assert(pending != 0, "m_axis_state: a word without an accepted pixel")
        # reachable within the bounded depth (a list needs two frames: the adapters' own
        # harnesses cover lists and lines)
        m.d.comb += [
            Cover(restart & started),                        # a soft reset after a pixel
            Cover(t.s_axil_bvalid & t.s_axil_bready),        # a write response
            Cover(state_word),                               # a state word out
        ]


class _AxilView:
    """The flat ``s_axil_*`` ports of the top as the channels :func:`axil_subordinate`
    reads (``axil.aw.awvalid`` …)."""

    def __init__(self, top):
        class Channel:
            pass
        for channel, names in (("aw", ("awaddr", "awprot", "awvalid", "awready")),
                               ("w", ("wdata", "wstrb", "wvalid", "wready")),
                               ("b", ("bresp", "bvalid", "bready")),
                               ("ar", ("araddr", "arprot", "arvalid", "arready")),
                               ("r", ("rdata", "rresp", "rvalid", "rready"))):
            view = Channel()
            for name in names:
                setattr(view, name, getattr(top, f"s_axil_{name}"))
            setattr(self, channel, view)


class EagerAXILite(wiring.Component):
    """A deliberately broken AXI4-Lite subordinate (known-bad harness): it answers a write
    as soon as its address is accepted, without waiting for the data (W)."""

    def __init__(self):
        super().__init__({"axil": In(axi_lite_signature(4))})

    def elaborate(self, platform):
        m = Module()
        aw, w, b = self.axil.aw, self.axil.w, self.axil.b
        m.d.comb += [aw.awready.eq(~b.bvalid), w.wready.eq(1)]
        with m.If(aw.awvalid & aw.awready):
            m.d.sync += b.bvalid.eq(1)
        with m.Elif(b.bready):
            m.d.sync += b.bvalid.eq(0)
        return m


class EagerAXILiteHarness(Harness):
    """The AXI4-Lite subordinate checks on :class:`EagerAXILite`: must FAIL."""

    def check(self, m, past):
        m.submodules.dut = dut = EagerAXILite()
        self.free_inputs(m, dut, "dut")
        axil_subordinate(m, past, dut.axil)
