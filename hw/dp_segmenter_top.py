"""DP pipeline plus segmenter: pixels in, one candidate point list per segment out.

:class:`DPSegmenter` is what the FPGA of paper 001 hands the DSP: instead of every pixel's
(E, d) it emits, per segment, at most C records (row, col, E, d) and a trailer
(``docs/gateware.md`` "Segmenter"). :mod:`dptbd.hw.flow.segmenter_verilog` converts it to
the Verilog module ``dptbd_seg`` with a JSON manifest, like :mod:`dptbd.hw.flow.verilog` does
for ``dptbd_dp``; the cocotb harness (:mod:`dptbd.sim.benches.segmenter`) drives that module.
"""

from __future__ import annotations

from typing import Mapping

from amaranth.hdl import Module, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.dp_core import DPCore, lut_write_members
from dptbd.hw.dp_pipeline import DPPipeline
from dptbd.hw.controller import clamped
from dptbd.hw.axis_broadcast import StreamBroadcast
from dptbd.hw.layouts import event_layout, pixel_layout, state_layout
from dptbd.hw.state_store import StateStoreSignature
from dptbd.hw.segmenter import Segmenter, segmenter_setting_members

__all__ = ["DPSegmenter"]


class DPSegmenter(wiring.Component):
    """:class:`~dptbd.hw.dp_pipeline.DPPipeline` feeding a :class:`~dptbd.hw.segmenter.Segmenter`.

    Members
    -------
    pixels : In(stream.Signature(pixel_layout(cfg)))
        As for ``DPPipeline``.
    candidates : Out(stream.Signature(candidate_layout(cfg)))
        Records and trailers (:func:`~dptbd.hw.candidate_layout.candidate_layout`).
    lut_addr, lut_data, lut_we : In
        The DP pipeline's weight LUT write port.
    segment_frames : In(range(1, K_max + 1), init=K)
        Run-time K.
    candidate_count : In(range(C + 1), init=n)
        Run-time n.
    histogram_shift : In(range(B_E), init=s)
        Run-time s. All three are sampled in the cycle the first pixel of a segment is
        accepted on ``pixels`` and hold for that segment (clamped to their ranges):
        K is its length, s bins its scored frame, n thresholds its histogram, which makes
        the next segment's list (``docs/gateware.md``, "Run-time settings"). The segmenter,
        misaligned after a resync, keeps its settings until it realigns (same section).
    states : Out(stream.Signature(state_layout(cfg)))
        Only with ``state_output=True``: the DP pipeline's per-pixel (E, d) stream, which is
        then broadcast to it and to the segmenter
        (:class:`~dptbd.hw.axis_broadcast.StreamBroadcast`: one register stage, so the
        latency grows by one; back-pressure on either consumer stalls the DP pipeline).

    Parameters
    ----------
    core_options : Mapping[str, str], optional
        :class:`~dptbd.hw.dp_core.DPCore`'s implementation options
        (:data:`~dptbd.hw.dp_core.CORE_OPTIONS`), passed on to the DP pipeline; ``None``
        (the default) builds DPCore's defaults. ``dptbd verilog --family`` passes a family's
        (:attr:`~dptbd.hw.flow.family.Family.core_options`); ``max_tree="split"`` adds its
        cycles to :attr:`latency`.
    external_state_store : bool
        Build :class:`~dptbd.hw.dp_core.DPCore` without the on-chip store and bring its
        state-store port out as the member ``state_store``
        (:class:`~dptbd.hw.state_store.StateStoreSignature`, the W*H-word store outside, e.g.
        an SRAM: a device too small for the store on chip, such as the iCE40 HX8K at
        128 x 128). Off by default (the on-chip :class:`~dptbd.hw.dp_pipeline.DPPipeline`).
    events : Out(event_layout(cfg))
        One-cycle pulses: ``frame_done`` / ``segment_done`` / ``saturated`` with the
        DP pipeline's ``states`` handshake, ``list_done`` with a trailer's handshake on
        ``candidates`` (:func:`~dptbd.hw.layouts.event_layout`).
    """

    def __init__(self, cfg: DPConfig, *, fifo_depth: int = 8, state_output: bool = False,
                 core_options: Mapping[str, str] | None = None,
                 external_state_store: bool = False):
        cfg.require_paper001_datapath("the segmenter top (dptbd.hw.dp_segmenter_top)")
        self._cfg = cfg
        self._state_output = bool(state_output)
        self._external = bool(external_state_store)
        self._dp = (DPCore if self._external else DPPipeline)(cfg, **dict(core_options or {}))
        # The segmenter takes its settings from registers loaded when the DP accepts a
        # segment's first pixel, except at a resync; it takes them only at a segment's first
        # word after reset or an end_of_segment, never the first of a resync's segment. That
        # is exact while fewer words than a frame are in flight between the two (two such
        # segment starts are a whole segment apart), which the DP's credit count guarantees.
        assert self._dp.output_fifo_depth < cfg.width * cfg.height
        options = self._dp.core_options
        self._segmenter = Segmenter(cfg, fifo_depth=fifo_depth,
                                    histogram_style=options["histogram_style"],
                                    control_style=options["control_style"])
        super().__init__({
            "pixels": In(stream.Signature(pixel_layout(cfg))),
            "candidates": Out(stream.Signature(candidate_layout(cfg))),
            **lut_write_members(cfg),
            **segmenter_setting_members(cfg),
            "events": Out(event_layout(cfg)),
            **({"states": Out(stream.Signature(state_layout(cfg)))} if state_output else {}),
            **({"state_store": Out(StateStoreSignature(cfg))} if self._external else {}),
        })

    @property
    def config(self) -> DPConfig:
        return self._cfg

    @property
    def schedule(self):
        return self._dp.schedule

    @property
    def external_state_store(self) -> bool:
        """The state store is outside (the ``state_store`` member)."""
        return self._external

    @property
    def core_options(self) -> dict:
        """The DP core's implementation options (:attr:`DPCore.core_options`)."""
        return self._dp.core_options

    @property
    def latency(self) -> int:
        """Cycles from a pixel's acceptance to its record on ``candidates`` (no stalls):
        the DP pipeline's L plus the segmenter's 3 (plus 1 with ``state_output``)."""
        return self._dp.latency + Segmenter.RECORD_LATENCY + self._state_output

    @property
    def scan_cycles(self) -> int:
        return self._segmenter.scan_cycles

    def elaborate(self, platform):
        m = Module()
        m.submodules.dp = dp = self._dp
        m.submodules.segmenter = seg = self._segmenter
        wiring.connect(m, wiring.flipped(self.pixels), dp.pixels)
        if self._external:
            wiring.connect(m, dp.state_store, wiring.flipped(self.state_store))
        if self._state_output:
            m.submodules.state_broadcast = fork = StreamBroadcast(state_layout(self._cfg))
            wiring.connect(m, dp.states, fork.input)
            wiring.connect(m, fork.outputs[0], seg.states)
            wiring.connect(m, fork.outputs[1], wiring.flipped(self.states))
        else:
            wiring.connect(m, dp.states, seg.states)
        wiring.connect(m, seg.candidates, wiring.flipped(self.candidates))
        m.d.comb += [
            dp.lut_addr.eq(self.lut_addr),
            dp.lut_data.eq(self.lut_data),
            dp.lut_we.eq(self.lut_we),
            dp.segment_frames.eq(self.segment_frames),
        ]
        # Settings of the last segment the DP input began other than at a resync, handed to
        # the segmenter, which takes them at the same segment's first word.
        cfg = self._cfg
        for name, lo, hi in (("segment_frames", 1, cfg.k_max),
                             ("candidate_count", 0, cfg.record_capacity),
                             ("histogram_shift", 0, cfg.energy_bits - 1)):
            port = getattr(self, name)
            latched = Signal.like(port, name=f"input_{name}")
            with m.If(dp.segment_begin & ~dp.resync):
                m.d.sync += latched.eq(clamped(port, lo, hi))
            m.d.comb += getattr(seg, name).eq(latched)
            if name == "segment_frames" and "segment_frames_one" in seg.signature.members:
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
