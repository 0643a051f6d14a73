"""``dptbd_axi`` with its state store in external memory (``dptbd verilog --top axi
--state-store axi``): :class:`~dptbd.hw.axi_top.AXITop` on
:class:`~dptbd.hw.axi_store.segmenter.DPSegmenterAxi`, with the AXI4 manager port
``m_axi_state_*`` and the registers of :func:`~dptbd.hw.register_map.register_map` with the
store (``docs/integration.md``, "State store in external memory").

What the store adds to the AXI top:

- ``STATE_BASE`` (control, rw): the base address the next soft reset hands to the store
  (refused unless a multiple of the burst size with the frame's state below
  ``2**address_bits``); ``STATE_BASE_ACTIVE`` (status) reads the one in use, taken at
  ``aresetn`` (the build's ``base_address``) and in the cycle of every soft reset's
  restart, when no burst is in flight. A write while frames run changes nothing until then.
- ``ERROR.state_read`` / ``ERROR.state_write`` (sticky, W1C, part of the ``fault``
  interrupt as every ERROR bit) and the counters ``STATE_READ_ERRORS`` (error beats) /
  ``STATE_WRITE_ERRORS`` (error bursts): a read or write answered with ``SLVERR`` or
  ``DECERR``. The transfer counts as done: the core never waits on it.
- The soft reset keeps AXI4 legal: its restart (the reset of the core and of the store) is
  held until the port is quiet (:class:`~dptbd.hw.axi_store.quiet.AxiQuiet`: no burst in
  flight, no valid offered), as it is held until the output streams are closed;
  ``STATUS.soft_reset_busy`` stays 1 until then. Only ``aresetn`` abandons bursts.

At P = 2 or 4 pixels per clock the same class is built on
:class:`~dptbd.hw.wide.axi_top.AXITopWide`'s blocks (``s_axis_video`` of P pixels per beat,
the frame monitor counting beats; no ``m_axis_state``) around the wide
:class:`~dptbd.hw.axi_store.segmenter.DPSegmenterAxi`, whose store words hold P states in the
P = 1 byte layout.
"""

from __future__ import annotations

from typing import Mapping

from amaranth.hdl import Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import AxiStoreConfig
from dptbd.hw.axi_store.quiet import QUIET_INPUTS, AxiQuiet
from dptbd.hw.axi_store.bus import axi_port_members
from dptbd.hw.axi_store.segmenter import DPSegmenterAxi
from dptbd.hw.axi_top import AXITop, _bundle_signatures, _flat
from dptbd.hw.register_map import register_map
from dptbd.hw.wide.axi_top import wide_bundle_signatures

__all__ = ["AXITopStore"]


class AXITopStore(AXITop):
    """``dptbd_axi`` with the state in external memory (see the module doc).

    Parameters
    ----------
    store : AxiStoreConfig
        The configuration (``store.frame``) and its memory layout; ``address_bits`` at
        most 32 (:func:`~dptbd.hw.register_map.register_map` refuses more).
    state_output, core_options
        As for :class:`~dptbd.hw.axi_top.AXITop`; ``state_output`` is refused at
        ``pixels_per_clock`` 2 or 4.

    Members
    -------
    aclk … irq
        As for :class:`~dptbd.hw.axi_top.AXITop` (no ``state_store_*``); at P = 2 or 4 as
        for :class:`~dptbd.hw.wide.axi_top.AXITopWide` (``s_axis_video_tdata`` of P lanes).
    m_axi_state_awid … m_axi_state_rready
        The state store's AXI4 manager port (:func:`~dptbd.hw.axi_store.bus.axi4_signature`,
        flat with the AXI names).
    """

    def __init__(self, store: AxiStoreConfig, *, state_output: bool = False,
                 core_options: Mapping[str, str] | None = None):
        cfg = store.frame
        self._cfg = cfg
        self._store = store
        self._state_output = bool(state_output)
        self._external = False
        try:
            self._register_map = register_map(cfg, store)
            self._core = DPSegmenterAxi(store, state_output=self._state_output,
                                        core_options=core_options)
        except ValueError:                     # ConfigError included
            self._MustUse__silence = True      # refused: no "created but never used" warning
            raise
        self._bundles = (wide_bundle_signatures(cfg) if cfg.pixels_per_clock > 1
                         else _bundle_signatures(cfg, self._state_output))
        members = {"aclk": In(1), "aresetn": In(1)}
        for prefix, signature in self._bundles.items():
            members.update(_flat(prefix, signature))
        members.update(axi_port_members(store))
        members["irq"] = Out(1)
        wiring.Component.__init__(self, members)

    @property
    def store(self) -> AxiStoreConfig:
        """The external memory layout."""
        return self._store

    def elaborate(self, platform):
        # the on-chip top's blocks (AXITop's, at every P), then the store's additions
        m = AXITop.elaborate(self, platform)
        store = self._store
        core, regs = m.submodules["core"], m.submodules["regs"]
        cand_out = m.submodules["cand_out"]
        # the restart is registered: the port was quiet in the cycle before it; in its own
        # cycle (the core still runs) no new valid is offered and no handshake is seen
        restart = cand_out.restart
        for name, member in axi_port_members(store).items():
            outer, inner = getattr(self, name), getattr(core, name)
            if member.flow == Out:
                m.d.comb += outer.eq(inner & ~restart if name.endswith("valid") else inner)
            else:
                m.d.comb += inner.eq(outer & ~restart if name.endswith("ready") else outer)
        m.submodules.state_quiet = quiet = AxiQuiet(store.outstanding)
        for name in QUIET_INPUTS:
            m.d.comb += getattr(quiet, name).eq(getattr(self, f"m_axi_state_{name}"))
        # the restart waits for the state port as for m_axis_state (AXITop._state_port)
        closing = ~m.submodules["state_out"].closed if self._state_output else 0
        m.d.comb += cand_out.hold.eq(closing | ~quiet.quiet)
        active = Signal(store.address_bits, init=store.base_address)
        with m.If(cand_out.restart):
            m.d.sync += active.eq(regs.state_base)
        m.d.comb += [
            core.state_base.eq(active),
            regs.state_base_active.eq(active),
            regs.events.state_read_error.eq(core.read_error),
            regs.events.state_write_error.eq(core.write_error),
        ]
        return m
