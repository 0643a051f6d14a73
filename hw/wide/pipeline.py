"""DPPipelineWide: :class:`~dptbd.hw.wide.core.DPCoreWide` with its on-chip state store (the
``dptbd_dp`` top at P > 1), and :func:`dp_pipeline`, which picks the pipeline by P."""

from __future__ import annotations

from amaranth.hdl import Module
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.dp_core import lut_write_members, run_time_k_members
from dptbd.hw.wide.core import DPCoreWide
from dptbd.hw.wide.layouts import wide_pixel_layout, wide_state_layout
from dptbd.hw.wide.state_store import WideStateStore


class DPPipelineWide(wiring.Component):
    """:class:`DPCoreWide` plus its on-chip :class:`WideStateStore`: the ``dptbd_dp`` top
    at P = 2 or 4. Members as :class:`~dptbd.hw.dp_pipeline.DPPipeline`'s with the beats'
    layouts (:func:`wide_pixel_layout`, :func:`wide_state_layout`)."""

    def __init__(self, cfg: DPConfig, *, output_fifo_depth: int | None = None,
                 lut_style: str = "auto", **core_options):
        self._core = DPCoreWide(cfg, output_fifo_depth=output_fifo_depth, lut_style=lut_style,
                                **core_options)
        self._cfg = cfg
        super().__init__({
            "pixels": In(stream.Signature(wide_pixel_layout(cfg))),
            "states": Out(stream.Signature(wide_state_layout(cfg))),
            **lut_write_members(cfg),
            **run_time_k_members(cfg),
        })

    config = property(lambda self: self._cfg, doc="The configuration.")
    schedule = property(lambda self: self._core.schedule, doc="Cycle offsets of every stage.")
    latency = property(lambda self: self._core.latency,
                       doc="Cycles from a beat's acceptance to its states on ``states``.")
    output_fifo_depth = property(lambda self: self._core.output_fifo_depth,
                                 doc="Output FIFO entries.")
    resync = property(lambda self: self._core.resync, doc=":attr:`DPCoreWide.resync`.")
    core_options = property(lambda self: self._core.core_options,
                            doc=":attr:`DPCoreWide.core_options`.")
    lut_style = property(lambda self: self._core.lut_style, doc="The weight LUTs' storage.")

    def elaborate(self, platform):
        m = Module()
        m.submodules.core = core = self._core
        m.submodules.state_store = store = WideStateStore(self._cfg)
        wiring.connect(m, core.state_store, store.bus)
        wiring.connect(m, wiring.flipped(self.pixels), core.pixels)
        wiring.connect(m, core.states, wiring.flipped(self.states))
        m.d.comb += [
            core.lut_addr.eq(self.lut_addr),
            core.lut_data.eq(self.lut_data),
            core.lut_we.eq(self.lut_we),
            core.segment_frames.eq(self.segment_frames),
            self.segment_begin.eq(core.segment_begin),
            self.events.eq(core.events),
        ]
        return m


def dp_pipeline(cfg: DPConfig, **options):
    """The ``dptbd_dp`` top for ``cfg``: :class:`~dptbd.hw.dp_pipeline.DPPipeline` at P = 1,
    :class:`DPPipelineWide` at P = 2 or 4; ``options`` are passed on."""
    if cfg.pixels_per_clock == 1:
        from dptbd.hw.dp_pipeline import DPPipeline
        return DPPipeline(cfg, **options)
    return DPPipelineWide(cfg, **options)
