"""``dptbd_axi`` at P = 2 or 4 pixels per clock, on-chip state store: :class:`AXITopWide`
(``docs/integration.md``, ``docs/gateware.md`` "P pixels per clock").

The ports are :class:`~dptbd.hw.axi_top.AXITop`'s except ``s_axis_video``, which carries P
pixels per beat (:func:`~dptbd.hw.wide.axis_video.video_in_signature_wide`: pixel 0 in the
low lane, ``tuser[0]`` on a frame's first beat, ``tlast`` on a row's last beat). Inside, the
same blocks as at P = 1 around :class:`~dptbd.hw.wide.dp_segmenter.DPSegmenterWide`: the
register file, the candidate output adapter with its soft reset, and the frame monitor
built for the beat configuration (W/P beats per line), so its fault classes count beats.
``m_axis_state`` (``state_output``) and the external state store are not built at P > 1;
the AXI4 state store is (:class:`~dptbd.hw.axi_store.top.AXITopStore`, on these blocks).
"""

from __future__ import annotations

from typing import Mapping

from amaranth.hdl import ClockDomain, Module, ResetInserter
from amaranth.lib import wiring
from amaranth.lib.wiring import Out

from dptbd.config import DPConfig
from dptbd.hw.axi_lite import axi_lite_signature
from dptbd.hw.axi_top import CORE_EVENTS, AXITop, _flat
from dptbd.hw.axis_video import CandidatesToAxis, candidate_out_signature
from dptbd.hw.frame_monitor import FrameMonitor
from dptbd.hw.register_file import RegisterFile
from dptbd.hw.register_map import ADDRESS_BITS, FAULTS, register_map
from dptbd.hw.wide.axis_video import AxisToBeats, video_in_signature_wide
from dptbd.hw.wide.dp_segmenter import DPSegmenterWide

__all__ = ["AXITopWide", "axi_top", "wide_bundle_signatures"]


def wide_bundle_signatures(cfg: DPConfig) -> dict[str, wiring.Signature]:
    """The AXI bundles of ``dptbd_axi`` at P > 1 (flattened with their prefixes): the
    video input of P pixels per beat, the candidate lists, the register port."""
    return {
        "s_axis_video": video_in_signature_wide(cfg).flip(),
        "m_axis_cand": candidate_out_signature(cfg),
        "s_axil": axi_lite_signature(ADDRESS_BITS).flip(),
    }


class AXITopWide(AXITop):
    """``dptbd_axi`` at P = 2 or 4 (module doc). Members, properties and ``core_options``
    as :class:`~dptbd.hw.axi_top.AXITop`'s (no ``state_output``, no external store);
    ``s_axis_video_tdata`` is P byte lanes wide."""

    def __init__(self, cfg: DPConfig, *, core_options: Mapping[str, str] | None = None):
        if cfg.pixels_per_clock == 1:
            raise ValueError("AXITopWide takes pixels_per_clock 2 or 4; at 1 use "
                             "dptbd.hw.axi_top.AXITop (dptbd.hw.wide.axi_top.axi_top picks by P)")
        self._cfg = cfg
        self._state_output = False
        self._external = False
        self._core = DPSegmenterWide(cfg, core_options=core_options)
        self._bundles = wide_bundle_signatures(cfg)
        self._register_map = register_map(cfg)
        members = {"aclk": wiring.In(1), "aresetn": wiring.In(1)}
        for prefix, signature in self._bundles.items():
            members.update(_flat(prefix, signature))
        members["irq"] = Out(1)
        wiring.Component.__init__(self, members)

    def elaborate(self, platform):
        # AXITop.elaborate without m_axis_state and the external store, with the beat
        # adapter and the frame monitor counting beats
        m = Module()
        cfg = self._cfg
        m.domains.sync = sync = ClockDomain("sync")
        m.d.comb += [sync.clk.eq(self.aclk), sync.rst.eq(~self.aresetn)]
        m.submodules.regs = regs = RegisterFile(cfg, self._register_map)
        m.submodules.cand_out = cand_out = CandidatesToAxis(cfg)
        restart = {"sync": cand_out.restart}
        m.submodules.video_in = video_in = AxisToBeats(cfg)
        m.submodules.monitor = monitor = ResetInserter(restart)(
            FrameMonitor(cfg.beat_config()))
        m.submodules.core = core = ResetInserter(restart)(self._core)
        busy = cand_out.busy
        self._connect_flat(m, "s_axil", regs.axil)
        self._connect_flat(m, "s_axis_video", video_in.video)
        self._connect_flat(m, "m_axis_cand", cand_out.cand)
        m.d.comb += [
            self.irq.eq(regs.irq),
            core.pixels.payload.eq(video_in.pixels.payload),
            core.pixels.valid.eq(video_in.pixels.valid & ~busy),
            video_in.pixels.ready.eq(core.pixels.ready & ~busy),
            monitor.accept.eq(video_in.accepted),
            monitor.first.eq(self.s_axis_video_tuser[0]),
            monitor.last.eq(self.s_axis_video_tlast),
            monitor.no_sof.eq(regs.no_sof),
            cand_out.candidates.payload.eq(core.candidates.payload),
            cand_out.candidates.valid.eq(core.candidates.valid),
            core.candidates.ready.eq(cand_out.candidates.ready),
            cand_out.soft_reset.eq(regs.soft_reset),
            regs.soft_reset_busy.eq(cand_out.busy),
            core.lut_addr.eq(regs.lut_addr),
            core.lut_data.eq(regs.lut_data),
            core.lut_we.eq(regs.lut_we),
        ]
        for name in ("segment_frames", "candidate_count", "histogram_shift"):
            m.d.comb += getattr(core, name).eq(getattr(regs, name))
        for name in CORE_EVENTS:
            m.d.comb += regs.events[name].eq(core.events[name])
        for name in FAULTS:
            m.d.comb += regs.events[name].eq(monitor.faults[name])
        m.d.comb += [
            regs.events.input_stall.eq(self.s_axis_video_tvalid & ~self.s_axis_video_tready),
            regs.events.output_stall.eq(cand_out.stalled),
        ]
        return m


def axi_top(cfg: DPConfig, *, core_options: Mapping[str, str] | None = None, **options):
    """``dptbd_axi`` for ``cfg``: :class:`~dptbd.hw.axi_top.AXITop` at P = 1 (``options``
    passed on), :class:`AXITopWide` at P = 2 or 4 (``state_output`` and
    ``external_state_store`` refused there)."""
    if cfg.pixels_per_clock == 1:
        return AXITop(cfg, core_options=core_options, **options)
    given = sorted(name for name, value in options.items() if value)
    if given:
        raise ValueError(f"{', '.join(given)}: not built at pixels_per_clock="
                         f"{cfg.pixels_per_clock}; dptbd_axi at P > 1 has the on-chip state "
                         f"store and no m_axis_state")
    return AXITopWide(cfg, core_options=core_options)
