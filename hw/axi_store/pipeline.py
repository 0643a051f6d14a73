"""The DP pipeline with its state store in external memory: :class:`~dptbd.hw.dp_core.DPCore`
(:class:`~dptbd.hw.wide.core.DPCoreWide` at P = 2 or 4 pixels per clock) plus
:class:`~dptbd.hw.axi_store.AxiStateStore` behind an AXI4 manager port.

The same streams, LUT ports and run-time settings as
:class:`~dptbd.hw.dp_pipeline.DPPipeline` (at P > 1
:class:`~dptbd.hw.wide.pipeline.DPPipelineWide`, beats of P pixels), the same bits; the
input is held back
(``pixels.ready`` low) whenever the external memory is behind (``docs/gateware.md``,
"State store in external memory").
"""

from __future__ import annotations

from amaranth.hdl import Module
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import AxiStoreConfig
from dptbd.hw.axi_store.bus import AXI_PREFIX, axi4_signature, store_port_members
from dptbd.hw.axi_store import AxiStateStore
from dptbd.hw.dp_core import (DPCore, family_write_members, family_write_ports,
                               lut_write_members, run_time_k_members)
from dptbd.hw.dp_pipeline import DPPipeline
from dptbd.hw.layouts import pixel_layout, state_layout


def _core_and_layouts(store: AxiStoreConfig, **options):
    """The core of ``store.frame`` (DPCore at P = 1, DPCoreWide at P > 1) and its
    ``pixels`` / ``states`` payload layouts."""
    cfg = store.frame
    if cfg.pixels_per_clock == 1:
        return DPCore(cfg, **options), pixel_layout(cfg), state_layout(cfg)
    from dptbd.hw.wide import DPCoreWide, wide_pixel_layout, wide_state_layout
    return DPCoreWide(cfg, **options), wide_pixel_layout(cfg), wide_state_layout(cfg)

__all__ = ["DPPipelineAxi"]

class DPPipelineAxi(DPPipeline):
    """Streaming DP with the state in external memory (see the module doc); the properties
    (``config``, ``schedule``, ``latency``, ``output_fifo_depth``, ``lut_style``,
    ``core_options``, ``resync``) are :class:`~dptbd.hw.dp_pipeline.DPPipeline`'s.

    Parameters
    ----------
    store : AxiStoreConfig
        The configuration (``store.frame``) and its memory layout.
    lut_style, output_fifo_depth, **core_options
        As for :class:`~dptbd.hw.dp_pipeline.DPPipeline`; ``state_store_style`` is the
        prefetcher's beat FIFO's here (:class:`~dptbd.hw.axi_store.AxiStateStore`'s
        ``style``: ``"dp16kd"``, the ECP5 family's, reads it through the DP16KDs' output
        register into flip-flops, registers the gate and stages the write descriptors).

    Members
    -------
    pixels, states, lut_*, merit_*, penalty_*, segment_frames, segment_begin, events
        As for :class:`~dptbd.hw.dp_pipeline.DPPipeline`; at P = 2 or 4 as for
        :class:`~dptbd.hw.wide.pipeline.DPPipelineWide` (beats of P pixels and states).
    m_axi_state_awid … m_axi_state_rready
        The state store's AXI4 manager port (:func:`~dptbd.hw.axi_store.bus.axi4_signature`, flat
        with the AXI names; :meth:`channel` gives a channel's signals by their names).
    state_base : In(address_bits, init=store.base_address)
        Byte address of pixel 0's state slot (bits below the burst size ignored); change it
        only between frames while the core is idle.
    read_error, write_error : Out(1)
        Pulses: the memory answered a state read beat / a state write burst with
        ``SLVERR`` or ``DECERR``.
    """

    def __init__(self, store: AxiStoreConfig, *, output_fifo_depth: int | None = None,
                 lut_style: str = "auto", **core_options):
        cfg = store.frame
        self._core, pixels, states = _core_and_layouts(
            store, output_fifo_depth=output_fifo_depth, lut_style=lut_style, **core_options)
        self._store_block = AxiStateStore(
            store, write_latency=self._core.schedule.write_latency,
            style=self._core.core_options["state_store_style"])
        self._cfg = cfg
        self._store = store
        wiring.Component.__init__(self, {
            "pixels": In(stream.Signature(pixels)),
            "states": Out(stream.Signature(states)),
            **lut_write_members(cfg),
            **family_write_members(cfg),
            **run_time_k_members(cfg),
            **store_port_members(store),
        })

    @property
    def store(self) -> AxiStoreConfig:
        """The external memory layout."""
        return self._store

    @property
    def core_options(self) -> dict:
        """The core's implementation options (:data:`~dptbd.hw.dp_core.CORE_OPTIONS`)."""
        return self._core.core_options

    def channel(self, name: str):
        """The signals of AXI4 channel ``name`` (``"ar"``, ``"r"``, ``"aw"``, ``"w"``,
        ``"b"``) as attributes named as in the AXI specification (``.araddr``)."""
        members = axi4_signature(self._store).members[name].signature.members
        return type(name, (), {n: getattr(self, f"{AXI_PREFIX}_{n}") for n in members})

    def elaborate(self, platform):
        m = Module()
        m.submodules.core = core = self._core
        m.submodules.state_store = store = self._store_block
        wiring.connect(m, core.state_store, store.bus)
        for path, member in axi4_signature(self._store).members.flatten():
            if member.is_port:
                inner = getattr(getattr(store.axi, path[0]), path[-1])
                outer = getattr(self, f"{AXI_PREFIX}_{path[-1]}")
                m.d.comb += outer.eq(inner) if member.flow == Out else inner.eq(outer)
        wiring.connect(m, core.states, wiring.flipped(self.states))
        m.d.comb += [
            # a pixel enters only when its read word is prefetched and its write has room
            core.pixels.payload.eq(self.pixels.payload),
            core.pixels.valid.eq(self.pixels.valid & store.ready),
            self.pixels.ready.eq(core.pixels.ready & store.ready),
            store.restart.eq(core.resync),
            store.base.eq(self.state_base),
            self.read_error.eq(store.read_error),
            self.write_error.eq(store.write_error),
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
