"""The AXI top level ``dptbd_axi``: the DP pipeline and segmenter behind AXI4-Stream video
ports and an AXI4-Lite register port (``docs/integration.md``).

:class:`AXITop` wraps the existing components unchanged:
:class:`~dptbd.hw.dp_segmenter_top.DPSegmenter` (pixels in, candidate lists out),
:class:`~dptbd.hw.axis_video.AxisToPixels` / :class:`~dptbd.hw.axis_video.CandidatesToAxis`
(the stream conventions), :class:`~dptbd.hw.frame_monitor.FrameMonitor` (frame-sync faults)
and :class:`~dptbd.hw.register_file.RegisterFile` (the register map of
:mod:`dptbd.hw.register_map`). Its ports are flat, with the names of the AXI convention:
``aclk``, ``aresetn`` (active low, synchronous), ``s_axis_video_*``, ``m_axis_cand_*``,
``s_axil_*`` and ``irq``; built with ``state_output=True`` also ``m_axis_state_*``, the
per-pixel (E, d) stream (:class:`~dptbd.hw.axis_video.StatesToAxis`), broadcast inside the
core to the segmenter and to this port (:class:`~dptbd.hw.axis_broadcast.StreamBroadcast`):
back-pressure on either output stalls the DP pipeline.

``CONTROL.soft_reset`` resets the core, the frame monitor and the output adapters, keeping
registers and counters, without breaking AXI4-Stream: from the request on the input is held
(``s_axis_video_tready`` low) and no new output word is offered; a word already offered is
delivered, a list left open is closed by a cut trailer with ``tlast``
(:class:`~dptbd.hw.axis_video.CandidatesToAxis`), a line of ``m_axis_state`` left open is
completed to W words by filler words, the last with ``tlast``
(:class:`~dptbd.hw.axis_video.StatesToAxis`), and only then, in the cycle after the one
the last of these is taken in on the later of the two outputs (after the request's own
cycle if nothing is in flight; the restart is registered), is the core reset.
"""

from __future__ import annotations

from typing import Mapping

from amaranth.hdl import ClockDomain, Module, ResetInserter, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.axi_lite import axi_lite_signature
from dptbd.hw.axis_video import (AxisToPixels, CandidatesToAxis, StatesToAxis,
                                 candidate_out_signature, state_out_signature,
                                 video_in_signature)
from dptbd.hw.dp_segmenter_top import DPSegmenter
from dptbd.hw.frame_monitor import FrameMonitor
from dptbd.hw.register_file import RegisterFile
from dptbd.hw.state_store import StateStoreSignature
from dptbd.hw.register_map import ADDRESS_BITS, FAULTS, register_map
from dptbd.hw.wide.axis_video import AxisToBeats

__all__ = ["AXI_MODULE_NAME", "BUNDLES", "AXITop"]

#: Name of the generated Verilog module.
AXI_MODULE_NAME = "dptbd_axi"

#: Prefixes of the flattened AXI bundles.
BUNDLES = ("s_axis_video", "m_axis_cand", "s_axil")

#: The core's event pulses counted by the register block (``DPSegmenter.events``).
CORE_EVENTS = ("frame_done", "segment_done", "list_done", "saturated")


def _bundle_signatures(cfg: DPConfig, state_output: bool) -> dict[str, wiring.Signature]:
    return {
        "s_axis_video": video_in_signature(cfg).flip(),
        "m_axis_cand": candidate_out_signature(cfg),
        **({"m_axis_state": state_out_signature(cfg)} if state_output else {}),
        "s_axil": axi_lite_signature(ADDRESS_BITS).flip(),
    }


def _flat(prefix: str, signature: wiring.Signature) -> dict:
    """``{prefix_<AXI name>: member}`` of every port of ``signature``."""
    return {f"{prefix}_{path[-1]}": member for path, member in signature.members.flatten()
            if member.is_port}


class AXITop(wiring.Component):
    """``dptbd_axi`` for ``cfg`` (see the module doc and ``docs/integration.md``).

    Members
    -------
    aclk, aresetn : In(1)
        Clock; synchronous active-low reset of everything, registers included.
    s_axis_video_tdata, _tvalid, _tready, _tuser, _tlast
        Pixel input, one pixel per beat (:func:`~dptbd.hw.axis_video.video_in_signature`).
    m_axis_cand_tdata, _tvalid, _tready, _tuser, _tlast
        Candidate lists, one record or trailer per beat.
    m_axis_state_tdata, _tvalid, _tready, _tuser, _tlast
        Only with ``state_output=True``: (E, d) of every pixel
        (:func:`~dptbd.hw.axis_video.state_out_signature`).
    s_axil_awaddr … s_axil_rready
        AXI4-Lite control port (12-bit byte addresses, 32-bit data).
    irq : Out(1)
        Level interrupt: any pending and enabled ``IRQ_STATUS`` bit.

    state_store_read_addr … state_store_write_en
        Only with ``external_state_store=True``: the DP core's state-store port
        (:class:`~dptbd.hw.state_store.StateStoreSignature`: one-cycle synchronous read,
        one write per cycle), the W*H-word store outside the module (an SRAM; for a device
        whose block RAM cannot hold it, such as the iCE40 HX8K at 128 x 128). Off by default.

    ``core_options`` (optional): the DP core's implementation options, passed on to
    :class:`~dptbd.hw.dp_segmenter_top.DPSegmenter` (``None``: DPCore's defaults;
    ``dptbd verilog --top axi --family`` passes the family's).
    """

    def __init__(self, cfg: DPConfig, *, state_output: bool = False,
                 core_options: Mapping[str, str] | None = None,
                 external_state_store: bool = False):
        self._cfg = cfg
        self._state_output = bool(state_output)
        self._external = bool(external_state_store)
        self._core = DPSegmenter(cfg, state_output=self._state_output,
                                 core_options=core_options,
                                 external_state_store=self._external)
        self._bundles = _bundle_signatures(cfg, self._state_output)
        if self._external:
            self._bundles["state_store"] = StateStoreSignature(cfg)
        self._register_map = register_map(cfg)
        members = {"aclk": In(1), "aresetn": In(1)}
        for prefix, signature in self._bundles.items():
            members.update(_flat(prefix, signature))
        members["irq"] = Out(1)
        super().__init__(members)

    @property
    def config(self) -> DPConfig:
        return self._cfg

    @property
    def register_map(self):
        """The :func:`~dptbd.hw.register_map.register_map` of this build."""
        return self._register_map

    @property
    def state_output(self) -> bool:
        """``m_axis_state`` is brought out."""
        return self._state_output

    @property
    def core(self) -> DPSegmenter:
        return self._core

    def _connect_flat(self, m, prefix: str, inner) -> None:
        for path, member in self._bundles[prefix].members.flatten():
            if not member.is_port:
                continue
            value = inner
            for part in path:
                value = getattr(value, part)
            outer = getattr(self, f"{prefix}_{path[-1]}")
            m.d.comb += value.eq(outer) if member.flow == In else outer.eq(value)

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        m.domains.sync = sync = ClockDomain("sync")
        m.d.comb += [sync.clk.eq(self.aclk), sync.rst.eq(~self.aresetn)]

        registered = self._core.core_options.get("control_style") == "registered"
        m.submodules.regs = regs = RegisterFile(cfg, self._register_map,
                                                pulses_ahead=registered,
                                                bounds_registered=registered,
                                                refusal_registered=registered,
                                                handshake_apart=registered,
                                                read_registered=self._core.core_options.get(
                                                    "register_read") == "two_level")
        # a soft reset: the output adapters close the list and the state line being sent,
        # then restart pulses (registered, a cycle later), which resets the core, the frame
        # monitor and m_axis_state's adapter
        m.submodules.cand_out = cand_out = CandidatesToAxis(cfg, busy_ahead=registered)
        restart = {"sync": cand_out.restart}
        m.submodules.video_in = video_in = self._video_adapter()
        m.submodules.monitor = monitor = ResetInserter(restart)(
            FrameMonitor(self._monitor_config(), registered=registered))
        m.submodules.core = core = ResetInserter(restart)(self._core)
        busy = busy_port = cand_out.busy
        if registered:
            # control_style="registered": the input is held from two registers of its own,
            # each cand_out.busy (computed a cycle ahead): one for s_axis_video_tready (the
            # port's pin pulls it), one, stored inverted so that synthesis keeps it apart,
            # for the core's accept
            busy_port = Signal(name="input_busy_port")
            open_core = Signal(init=1, name="input_open_core")
            m.d.comb += cand_out.soft_reset_ahead.eq(regs.soft_reset_ahead)
            m.d.sync += [busy_port.eq(cand_out.busy_next), open_core.eq(~cand_out.busy_next)]
            busy = ~open_core

        self._connect_flat(m, "s_axil", regs.axil)
        self._connect_flat(m, "s_axis_video", video_in.video)
        self._connect_flat(m, "m_axis_cand", cand_out.cand)
        m.d.comb += self.irq.eq(regs.irq)

        # pixels: adapter -> core, held off from the soft-reset request to the restart
        m.d.comb += [
            core.pixels.payload.eq(video_in.pixels.payload),
            core.pixels.valid.eq(video_in.pixels.valid & ~busy),
            video_in.pixels.ready.eq(core.pixels.ready & ~busy_port),
            monitor.accept.eq(video_in.accepted),
            monitor.first.eq(self.s_axis_video_tuser[0]),
            monitor.last.eq(self.s_axis_video_tlast),
            monitor.no_sof.eq(regs.no_sof),
        ]
        # candidates: core -> adapter (which serves the soft reset)
        m.d.comb += [
            cand_out.candidates.payload.eq(core.candidates.payload),
            cand_out.candidates.valid.eq(core.candidates.valid),
            core.candidates.ready.eq(cand_out.candidates.ready),
            cand_out.soft_reset.eq(regs.soft_reset),
            regs.soft_reset_busy.eq(cand_out.busy),
        ]
        state_stalled = self._state_port(m, core, cand_out)
        if self._external:
            self._connect_flat(m, "state_store", core.state_store)
        # run-time settings and the LUT write port
        m.d.comb += [core.lut_addr.eq(regs.lut_addr), core.lut_data.eq(regs.lut_data),
                     core.lut_we.eq(regs.lut_we)]
        for name in ("segment_frames", "candidate_count", "histogram_shift"):
            m.d.comb += getattr(core, name).eq(getattr(regs, name))
        # events
        for name in CORE_EVENTS:
            m.d.comb += regs.events[name].eq(core.events[name])
        for name in FAULTS:
            m.d.comb += regs.events[name].eq(monitor.faults[name])
        m.d.comb += [
            regs.events.input_stall.eq(self.s_axis_video_tvalid & ~self.s_axis_video_tready),
            regs.events.output_stall.eq(cand_out.stalled | state_stalled),
        ]
        return m

    def _video_adapter(self):
        """``s_axis_video`` to the core's ``pixels``: one pixel per beat, or at P > 1 the
        beats of P (:class:`~dptbd.hw.wide.axis_video.AxisToBeats`)."""
        if self._cfg.pixels_per_clock > 1:
            return AxisToBeats(self._cfg)
        return AxisToPixels(self._cfg)

    def _monitor_config(self) -> DPConfig:
        """The configuration whose frames the frame monitor counts: beats
        (:meth:`~dptbd.config.DPConfig.beat_config`; W/P of them a line, pixels at P = 1)."""
        return self._cfg.beat_config()

    def _state_port(self, m, core, cand_out):
        """``m_axis_state`` from the core's ``states``; its ``stalled`` (0 without it).

        From a soft reset's request on the adapter closes the stream (a word already offered
        is delivered, an open line is completed with filler words up to ``tlast``) and
        ``cand_out.hold`` delays the restart until it is closed.
        """
        if not self._state_output:
            return 0
        m.submodules.state_out = state_out = ResetInserter({"sync": cand_out.restart})(
            StatesToAxis(self._cfg))
        self._connect_flat(m, "m_axis_state", state_out.state)
        m.d.comb += [
            state_out.states.payload.eq(core.states.payload),
            state_out.states.valid.eq(core.states.valid),
            core.states.ready.eq(state_out.states.ready),
            state_out.closing.eq(cand_out.busy),
            cand_out.hold.eq(~state_out.closed),
        ]
        return state_out.stalled
