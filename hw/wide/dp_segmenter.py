"""DPSegmenterWide: the ``dptbd_seg`` top at P = 2 or 4 pixels per clock — the P-pixel
DP pipeline (:class:`~dptbd.hw.wide.pipeline.DPPipelineWide`, on-chip state store) feeding
:class:`~dptbd.hw.wide.segmenter.SegmenterWide` (``docs/gateware.md``, "P pixels per
clock"). :func:`dp_segmenter` picks it or the P = 1
:class:`~dptbd.hw.dp_segmenter_top.DPSegmenter` by P."""

from __future__ import annotations

from typing import Mapping

from amaranth.hdl import Module, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.controller import clamped
from dptbd.hw.dp_core import lut_write_members
from dptbd.hw.layouts import event_layout
from dptbd.hw.segmenter import segmenter_setting_members
from dptbd.hw.wide.layouts import wide_pixel_layout
from dptbd.hw.wide.pipeline import DPPipelineWide
from dptbd.hw.wide.segmenter import SegmenterWide

__all__ = ["DPSegmenterWide", "dp_segmenter"]


class DPSegmenterWide(wiring.Component):
    """:class:`DPPipelineWide` feeding :class:`SegmenterWide`: pixels in as beats of P
    (:func:`~dptbd.hw.wide.layouts.wide_pixel_layout`), the P = 1 candidate lists out.

    Members, parameters and properties as
    :class:`~dptbd.hw.dp_segmenter_top.DPSegmenter`'s (without ``state_output`` and
    ``external_state_store``, not built at P > 1); the run-time settings are sampled when
    a segment's first beat is accepted on ``pixels``. :attr:`latency` counts from a beat's
    acceptance to the record of its first selected pixel.
    """

    def __init__(self, cfg: DPConfig, *, fifo_depth: int = 8,
                 core_options: Mapping[str, str] | None = None):
        cfg.require_paper001_datapath("the segmenter top (dptbd.hw.wide.dp_segmenter)")
        self._cfg = cfg
        self._dp = DPPipelineWide(cfg, **dict(core_options or {}))
        # As DPSegmenter: fewer beats in flight between the DP input and the segmenter
        # than a frame, so the latched settings reach the segment they were latched for.
        assert self._dp.output_fifo_depth < cfg.frame_beats
        options = self._dp.core_options
        self._segmenter = SegmenterWide(cfg, fifo_depth=fifo_depth,
                                        histogram_style=options["histogram_style"],
                                        control_style=options["control_style"])
        super().__init__({
            "pixels": In(stream.Signature(wide_pixel_layout(cfg))),
            "candidates": Out(stream.Signature(candidate_layout(cfg))),
            **lut_write_members(cfg),
            **segmenter_setting_members(cfg),
            "events": Out(event_layout(cfg)),
        })

    config = property(lambda self: self._cfg, doc="The configuration.")
    schedule = property(lambda self: self._dp.schedule, doc="The DP pipeline's schedule.")
    core_options = property(lambda self: self._dp.core_options,
                            doc="The DP core's implementation options.")
    external_state_store = property(lambda self: False, doc="On chip at P > 1.")
    scan_cycles = property(lambda self: self._segmenter.scan_cycles,
                           doc=":attr:`SegmenterWide.scan_cycles`.")

    @property
    def latency(self) -> int:
        """Cycles from a beat's acceptance to the record of its first selected pixel on
        ``candidates`` (no stalls): the DP pipeline's L plus the segmenter's 4."""
        return self._dp.latency + SegmenterWide.RECORD_LATENCY

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        m.submodules.dp = dp = self._dp
        m.submodules.segmenter = seg = self._segmenter
        wiring.connect(m, wiring.flipped(self.pixels), dp.pixels)
        wiring.connect(m, dp.states, seg.states)
        wiring.connect(m, seg.candidates, wiring.flipped(self.candidates))
        m.d.comb += [
            dp.lut_addr.eq(self.lut_addr),
            dp.lut_data.eq(self.lut_data),
            dp.lut_we.eq(self.lut_we),
            dp.segment_frames.eq(self.segment_frames),
        ]
        # DPSegmenter.elaborate's settings hand-over, per beat
        for name, lo, hi in (("segment_frames", 1, cfg.k_max),
                             ("candidate_count", 0, cfg.record_capacity),
                             ("histogram_shift", 0, cfg.energy_bits - 1)):
            port = getattr(self, name)
            latched = Signal.like(port, name=f"input_{name}")
            with m.If(dp.segment_begin & ~dp.resync):
                m.d.sync += latched.eq(clamped(port, lo, hi))
            m.d.comb += getattr(seg, name).eq(latched)
            if name == "segment_frames":
                # K == 1 latched with K: the segmenter's scored / ready does not compare
                one = Signal(init=cfg.segment_frames == 1, name="input_segment_frames_one")
                with m.If(dp.segment_begin & ~dp.resync):
                    m.d.sync += one.eq(clamped(port, lo, hi) == 1)
                m.d.comb += seg.segment_frames_one.eq(one)
        trailer_out = (self.candidates.valid & self.candidates.ready
                       & self.candidates.payload.end_of_list)
        m.d.comb += [
            self.events.frame_done.eq(dp.events.frame_done),
            self.events.segment_done.eq(dp.events.segment_done),
            self.events.saturated.eq(dp.events.saturated),
            self.events.list_done.eq(trailer_out),
        ]
        return m


def dp_segmenter(cfg: DPConfig, **options):
    """The ``dptbd_seg`` top for ``cfg``: :class:`~dptbd.hw.dp_segmenter_top.DPSegmenter`
    at P = 1, :class:`DPSegmenterWide` at P = 2 or 4; ``options`` are passed on."""
    if cfg.pixels_per_clock == 1:
        from dptbd.hw.dp_segmenter_top import DPSegmenter
        return DPSegmenter(cfg, **options)
    return DPSegmenterWide(cfg, **options)
