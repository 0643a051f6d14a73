"""The complete DP pipeline: :class:`~dptbd.hw.dp_core.DPCore` plus its on-chip state store.

This is the top level that ``dptbd.hw.flow.verilog`` converts to Verilog (module
``dptbd_dp``) and that the cocotb harness drives. ``docs/gateware.md`` documents its ports.
"""

from __future__ import annotations

from amaranth.hdl import Module
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.dp_core import (DPCore, family_write_members, family_write_ports,
                               lut_write_members, run_time_k_members)
from dptbd.hw.layouts import pixel_layout, state_layout
from dptbd.hw.schedule import PipelineSchedule
from dptbd.hw.read_ahead_store import ReadAheadStore, check_read_ahead_store

__all__ = ["DPPipeline"]


class DPPipeline(wiring.Component):
    """Streaming direction-weighted DP (paper 001 eqs (8)-(11)), one pixel per clock.

    Parameters
    ----------
    cfg : DPConfig
        The configuration (refused with :class:`~dptbd.errors.ConfigError` if the gateware
        does not implement it, see :func:`~dptbd.hw.schedule.check_supported`, or if the
        frame is too small for the on-chip store's read-ahead,
        :func:`~dptbd.hw.read_ahead_store.check_read_ahead_store`).
    output_fifo_depth : int or None
        See :class:`~dptbd.hw.dp_core.DPCore`.
    lut_style : {"auto", "bram", "logic"}
        Storage of the weight LUT, see :class:`~dptbd.hw.dp_core.DPCore`. The default
        ``"auto"`` puts the r = 1 table in logic, which is what lets the 64 x 64 top level
        fit the iCE40-HX8K's 32 block RAMs (``docs/gateware.md``, "Weight LUT storage").
    **core_options
        ``line_buffer_style``, ``sideband_delay``, ``max_tree``: options of
        :class:`~dptbd.hw.dp_core.DPCore`, passed on; ``state_store_style``: the on-chip
        store's block RAM (:class:`~dptbd.hw.read_ahead_store.ReadAheadStore`).

    Members
    -------
    pixels : In(stream.Signature(pixel_layout(cfg)))
        Input pixels, raster order, ``first`` on pixel (0, 0) of each frame.
    states : Out(stream.Signature(state_layout(cfg)))
        New (E, d) of every pixel of every frame, raster order, with end flags.
    lut_addr : In(range((M+1)*M))
        Weight LUT entry ``cfg.lut_address(p, m)`` (``p * M + m``) to write.
    lut_data : In(F+1)
        Code to write.
    lut_we : In(1)
        Write enable; a write in cycle c applies to every pixel accepted in cycle c or later.
    merit_addr, merit_data, merit_we : In(B_in), In(signed(B_P)), In(1)
        Merit LUT write port, only when the merit LUT is built (paper 000's family,
        ``docs/arithmetic.md`` §8.1): the pixel code and its new merit; same timing rule
        as ``lut_we``.
    penalty_addr, penalty_data, penalty_we : In(range((M+1)*M)), In(B_Q), In(1)
        Penalty LUT write port, only when the penalty LUT is built (§8.2): entry
        ``cfg.lut_address(p, m)`` and its new code; same timing rule as ``lut_we``.
    segment_frames : In(range(1, K_max + 1), init=K)
        Run-time K, sampled when a segment's first pixel is accepted (``docs/gateware.md``,
        "Run-time settings").
    segment_begin : Out(1)
        Pulse: the pixel accepted in this cycle begins a segment.
    events : Out(event_layout(cfg))
        ``frame_done``, ``segment_done``, ``saturated`` with the ``states`` handshake
        (:func:`~dptbd.hw.layouts.event_layout`; ``list_done`` is 0).
    """

    def __init__(self, cfg: DPConfig, *, output_fifo_depth: int | None = None,
                 lut_style: str = "auto", **core_options):
        self._core = DPCore(cfg, output_fifo_depth=output_fifo_depth, lut_style=lut_style,
                            **core_options)
        check_read_ahead_store(cfg, self._core.schedule.write_latency)
        self._cfg = cfg
        super().__init__({
            "pixels": In(stream.Signature(pixel_layout(cfg))),
            "states": Out(stream.Signature(state_layout(cfg))),
            **lut_write_members(cfg),
            **family_write_members(cfg),
            **run_time_k_members(cfg),
        })

    @property
    def config(self) -> DPConfig:
        """The configuration this pipeline was built for."""
        return self._cfg

    @property
    def schedule(self) -> PipelineSchedule:
        """Cycle offsets of every stage."""
        return self._core.schedule

    @property
    def latency(self) -> int:
        """Cycles from a pixel's acceptance to its result on ``states`` (no back-pressure).

        ``L = 6 + ceil(log2(F + 2)) + ceil(log2(M))`` for F >= 1 (``7 + ceil(log2(M))``
        for F = 0); 14 for r = 1, F = 8 and 15 for r = 2, F = 8. Paper 000's family adds
        ``penalty_levels + forgetting_levels`` (:class:`PipelineSchedule`).
        """
        return self._core.latency

    @property
    def output_fifo_depth(self) -> int:
        """Entries of the output FIFO."""
        return self._core.output_fifo_depth

    @property
    def resync(self):
        """Not a port: :attr:`DPCore.resync`."""
        return self._core.resync

    @property
    def core_options(self) -> dict:
        """The core's storage options (:attr:`DPCore.core_options`)."""
        return self._core.core_options

    @property
    def lut_style(self) -> str:
        """The weight LUT's resolved storage: ``"bram"`` or ``"logic"``."""
        return self._core.lut_style

    def elaborate(self, platform):
        m = Module()
        m.submodules.core = core = self._core
        m.submodules.state_store = store = ReadAheadStore(
            self._cfg, style=self._core.core_options["state_store_style"])
        wiring.connect(m, core.state_store, store.bus)
        m.d.comb += store.next_read_addr.eq(core.next_read_addr)
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
        for name in family_write_ports(self._cfg):  # paper 000's merit / penalty LUT writes
            m.d.comb += getattr(core, name).eq(getattr(self, name))
        return m
