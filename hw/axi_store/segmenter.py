"""The DP pipeline with its state in external memory feeding the segmenter:
:class:`~dptbd.hw.dp_segmenter_top.DPSegmenter` built on
:class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi` (``dptbd_axi --state-store axi``'s
core). The same streams, settings, latency and bits; the input is held back whenever the
external memory is behind. At P = 2 or 4 pixels per clock the pipeline is the wide one and the
segmenter :class:`~dptbd.hw.wide.segmenter.SegmenterWide`: beats of P pixels in, as
:class:`~dptbd.hw.wide.dp_segmenter.DPSegmenterWide`, the P = 1 candidate lists out.
"""

from __future__ import annotations

from typing import Mapping

from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import AxiStoreConfig
from dptbd.hw.axi_store.bus import connect_axi_ports, store_port_members
from dptbd.hw.axi_store.pipeline import DPPipelineAxi
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.dp_core import lut_write_members
from dptbd.hw.dp_segmenter_top import DPSegmenter
from dptbd.hw.layouts import event_layout, pixel_layout, state_layout
from dptbd.hw.segmenter import Segmenter, segmenter_setting_members
from dptbd.hw.wide.layouts import wide_pixel_layout
from dptbd.hw.wide.segmenter import SegmenterWide

__all__ = ["DPSegmenterAxi"]


class DPSegmenterAxi(DPSegmenter):
    """:class:`~dptbd.hw.dp_segmenter_top.DPSegmenter` with the state in external memory.

    Members
    -------
    pixels, candidates, lut_*, segment_frames, candidate_count, histogram_shift, events, states
        As for ``DPSegmenter``; at P = 2 or 4 ``pixels`` carries beats of P pixels
        (:func:`~dptbd.hw.wide.layouts.wide_pixel_layout`) and ``states`` is not built.
    m_axi_state_awid … m_axi_state_rready, state_base, read_error, write_error
        As for :class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi`.
    """

    def __init__(self, store: AxiStoreConfig, *, fifo_depth: int = 8,
                 state_output: bool = False, core_options: Mapping[str, str] | None = None):
        cfg = store.frame
        wide = cfg.pixels_per_clock > 1
        if wide and state_output:
            self._MustUse__silence = True      # refused: no "created but never used" warning
            raise ValueError(f"state_output: not built at pixels_per_clock="
                             f"{cfg.pixels_per_clock}; dptbd_axi at P > 1 has no m_axis_state")
        cfg.require_paper001_datapath("the segmenter top (dptbd.hw.dp_segmenter_top)")
        self._cfg = cfg
        self._store = store
        self._state_output = bool(state_output)
        self._external = False
        self._dp = DPPipelineAxi(store, **dict(core_options or {}))
        assert self._dp.output_fifo_depth < cfg.frame_beats     # as DPSegmenter's
        options = self._dp.core_options        # the histogram's and the control's
        self._segmenter = (SegmenterWide if wide else Segmenter)(
            cfg, fifo_depth=fifo_depth, histogram_style=options["histogram_style"],
            control_style=options["control_style"])
        wiring.Component.__init__(self, {
            "pixels": In(stream.Signature((wide_pixel_layout if wide else pixel_layout)(cfg))),
            "candidates": Out(stream.Signature(candidate_layout(cfg))),
            **lut_write_members(cfg),
            **segmenter_setting_members(cfg),
            "events": Out(event_layout(cfg)),
            **({"states": Out(stream.Signature(state_layout(cfg)))} if state_output else {}),
            **store_port_members(store),
        })

    @property
    def store(self) -> AxiStoreConfig:
        """The external memory layout."""
        return self._store

    @property
    def latency(self) -> int:
        """Cycles from a pixel's (beat's) acceptance to its record on ``candidates`` (no
        stalls): the DP pipeline's L plus its segmenter's ``RECORD_LATENCY`` (3 at P = 1,
        4 at P > 1), plus 1 with ``state_output``."""
        return (self._dp.latency + type(self._segmenter).RECORD_LATENCY
                + self._state_output)

    def elaborate(self, platform):
        m = super().elaborate(platform)
        dp = self._dp
        m.d.comb += connect_axi_ports(self._store, self, dp)
        m.d.comb += [dp.state_base.eq(self.state_base),
                     self.read_error.eq(dp.read_error),
                     self.write_error.eq(dp.write_error)]
        return m
