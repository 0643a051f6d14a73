"""The harness of the whole ``dptbd_axi`` top level (:class:`AXITopHarness`): every port's
protocol, the soft reset over AXI4-Lite, pixels in against state words out."""

from __future__ import annotations

from amaranth.hdl import Assert, Assume, Cover, DomainRenamer, Mux, Signal

from dptbd.config import DPConfig
from dptbd.hw.axi_top import AXITop
from dptbd.sim.formal.harness import Elaborated, Harness
from dptbd.sim.formal.harnesses.tiny import tiny_config
from dptbd.sim.formal.properties import (axil_subordinate, axis_manager, axis_subordinate,
                                         packet_open)

__all__ = ["AXITopHarness", "TOP_INVARIANTS", "top_invariants"]

#: The invariant groups of :class:`AXITopHarness` (``drop``, :func:`top_invariants`), each
#: needed by its induction (``tests/sim/formal/test_runner.py``).
TOP_INVARIANTS = ("registers", "lists", "lines", "idle", "closed", "pending", "core")


class AXITopHarness(Harness):
    """``dptbd_axi`` (:class:`~dptbd.hw.axi_top.AXITop`, ``state_output=True``) on the tiny
    build: any video manager and AXI4-Lite manager that keep their protocol's rules, any
    ``tready`` on both outputs, ``aresetn`` at any time.

    Asserted: the AXI4-Stream manager rules on ``m_axis_cand`` and ``m_axis_state`` (through
    soft resets written over AXI4-Lite); ``tuser[0]`` of ``m_axis_cand`` on exactly a list's
    first word; the core is reset (soft reset) only with no list and no line open; the
    AXI4-Lite subordinate rules; no output word after ``aresetn`` before a pixel is
    accepted; never more state words (fillers aside) than pixels accepted since the last
    reset; and the invariants of :func:`top_invariants` that make all of it k-inductive,
    less those named in ``drop`` (:data:`TOP_INVARIANTS`; for the test that each is needed).
    ``core_options`` as :class:`~dptbd.hw.axi_top.AXITop`'s (e.g. the ECP5 build's
    ``control_style="registered"``; its ``histogram_style="dp16kd"`` built with the
    behavioural DP16KD, :func:`~dptbd.sim.dp16kd_model.modelled_dp16kd`). ``list_cover``:
    instead of the three covers of the default run, one of a whole candidate list with a
    record out of ``m_axis_cand``, in an
    environment that streams whole frames (the assumptions of ``_list_cover``, added to the
    proof's: a trace that reaches it is one of the proof's environment too).
    """

    def __init__(self, cfg: DPConfig | None = None, drop: tuple = (), core_options=None,
                 list_cover: bool = False):
        super().__init__()
        self.cfg = cfg or tiny_config()
        self.core_options = core_options
        self.list_cover = list_cover
        unknown = sorted(set(drop) - set(TOP_INVARIANTS))
        if unknown:
            raise ValueError(f"unknown dptbd_axi invariant group(s) {', '.join(unknown)}; the "
                             f"groups are {', '.join(TOP_INVARIANTS)}")
        self.drop = tuple(drop)

    def check(self, m, past):
        from dptbd.sim.dp16kd_model import modelled_dp16kd

        with modelled_dp16kd():         # the ECP5 histogram's DP16KDs: the behavioural model
            top = Elaborated(AXITop(self.cfg, state_output=True,
                                    core_options=self.core_options))
        # dptbd_axi defines its own sync domain from aclk / aresetn (driven from clk / rst
        # below): renamed, so that the harness's registers use the harness's own sync domain
        m.submodules.dut = DomainRenamer({"sync": "dut"})(top.fragment)
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
        aw_out, w_out, ar_out = axil_subordinate(m, past, _AxilView(t))
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
        top_invariants(m, past, top, opens, started, pending, aw_out, w_out, ar_out,
                       self.drop)
        if self.list_cover:
            self._list_cover(m, t, accepted)
            return
        # reachable within the cover depth (a whole list needs two segments: the
        # dptbd_axi_list task's cover; the adapters' own harnesses cover lists and lines)
        m.d.comb += [
            Cover(restart & started),                        # a soft reset after a pixel
            Cover(t.s_axil_bvalid & t.s_axil_bready),        # a write response
            Cover(state_word),                               # a state word out
        ]

    def _list_cover(self, m, t, accepted):
        """The environment of the whole-list cover: ``aresetn`` only in the first cycle, no
        AXI4-Lite request, both ``tready`` high, a pixel offered in every cycle with
        ``tuser`` on each frame's first and ``tlast`` on each line's last; covered: a whole
        list with a record on ``m_axis_cand`` (``tlast`` not on its first word)."""
        cfg = self.cfg
        pixel = Signal(range(cfg.width * cfg.height))
        column = Signal(range(cfg.width))
        with m.If(accepted):
            m.d.sync += [pixel.eq(Mux(pixel == cfg.width * cfg.height - 1, 0, pixel + 1)),
                         column.eq(Mux(column == cfg.width - 1, 0, column + 1))]
        first = Signal(init=1, reset_less=True)           # the first cycle (a reset)
        m.d.sync += first.eq(0)
        m.d.comb += [
            Assume(first | ~self.rst),
            Assume(~t.s_axil_awvalid & ~t.s_axil_wvalid & ~t.s_axil_arvalid),
            Assume(t.m_axis_cand_tready & t.m_axis_state_tready),
            Assume(t.s_axis_video_tvalid),
            Assume(t.s_axis_video_tuser[0] == (pixel == 0)),
            Assume(t.s_axis_video_tlast == (column == cfg.width - 1)),
            Cover(t.m_axis_cand_tvalid & t.m_axis_cand_tready & t.m_axis_cand_tlast
                  & ~t.m_axis_cand_tuser[0]),
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


def top_invariants(m, past, top: Elaborated, opens, started, pending, aw_out, w_out, ar_out,
                   drop: tuple = ()) -> None:
    """Assert what ``dptbd_axi``'s state means (``top``, elaborated), in terms of the
    harness's shadow state (``opens``: a list / a line open on ``m_axis_cand`` /
    ``m_axis_state``; ``started``: a pixel accepted since ``aresetn``; ``pending``: pixels
    accepted − state words since a reset; the AXI4-Lite outstanding counters), less the
    groups named in ``drop`` (:data:`TOP_INVARIANTS`):

    - ``registers``: the register block's
      (:func:`~dptbd.sim.formal.harnesses.registers.register_invariants`);
    - ``lists``, ``lines``: the output adapters' open list / line is the harness's (and
      the candidate adapter's copy of its request, with ``busy_ahead``, the request's);
    - ``idle``: before the first pixel no word is past the DP pipeline (the broadcast to
      the segmenter and to ``m_axis_state`` holds none, the segmenter emits none, its
      emitter's FIFO is empty);
    - ``closed``: before the first pixel no list or line is open, no state word held;
    - ``pending``: ``pending`` = the DP pipeline's words in flight + the word the
      broadcast holds for ``m_axis_state``;
    - ``core``: the DP core's flow control
      (:func:`~dptbd.sim.formal.harnesses.flow.dp_core_invariants`, its ``ready`` low after a
      soft reset too), in terms of its own pixels accepted − words out since a reset.
    """
    from dptbd.hw.thermometer_fifo import ThermometerFIFO
    from dptbd.sim.formal.harnesses.flow import dp_core_invariants
    from dptbd.sim.formal.harnesses.registers import register_invariants

    restart = top.sub("cand_out").component.restart
    core = top.sub("core")
    dp = core.sub("dp")
    accepted = dp.component.pixels.valid & dp.component.pixels.ready
    taken = dp.component.states.valid & dp.component.states.ready
    fork = core.sub("state_broadcast").signal("pending")
    in_flight = Signal(range(-4, 64), name="dp_in_flight")
    with m.If(restart):
        m.d.sync += in_flight.eq(0)
    with m.Else():
        m.d.sync += in_flight.eq(in_flight + accepted - taken)
    if "registers" not in drop:
        register_invariants(m, top.sub("regs"), aw_out, w_out, ar_out)
    if "lists" not in drop:
        cand_out = top.sub("cand_out")
        m.d.comb += Assert(cand_out.signal("list_start") == ~opens[0],
                           "CandidatesToAxis: list_start disagrees with the open list")
        if "busy_next" in cand_out.component.signature.members:     # busy_ahead
            m.d.comb += Assert(cand_out.signal("request_open_core")
                               == ~cand_out.signal("request"),
                               "CandidatesToAxis: request_open_core != ~request")
    if "lines" not in drop:
        m.d.comb += Assert(top.sub("state_out").signal("line_open") == opens[1],
                           "StatesToAxis: line_open disagrees with the open line")
    if "idle" not in drop:
        segmenter = core.sub("segmenter")
        emitter = segmenter.sub("emitter")
        fifo = emitter.sub("fifo")
        if isinstance(fifo.component, ThermometerFIFO):     # staged (registered control)
            empty = (~fifo.signal("staged") & ~fifo.sub("level").component.at_least.any()
                     & ~fifo.component.r.valid)
        else:
            empty = fifo.component.level == 0
        with m.If(~started):
            m.d.comb += [
                Assert((fork == 0) & ~segmenter.signal("valid_b")
                       & ~emitter.signal("trailer_pending") & empty,
                       "a word past the DP pipeline before the first pixel"),
            ]
    if "closed" not in drop:
        with m.If(~started):
            m.d.comb += [
                Assert(~opens[0] & ~opens[1] & ~top.sub("state_out").signal("held"),
                       "an output packet open before the first pixel"),
            ]
    if "pending" not in drop:
        m.d.comb += Assert(pending == in_flight + fork[1],
                           "pixels accepted - state words != DP words in flight + the one held")
    if "core" not in drop:
        m.d.comb += Assert(in_flight >= 0, "DP: more words out than pixels accepted")
        dp_core_invariants(m, past, dp.sub("core"), in_flight, started,
                           was_reset=past.rst | past(restart, "past_restart"))
