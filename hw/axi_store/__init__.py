"""The state store in external memory: the pipeline's one-cycle synchronous store port
served over an AXI4 manager port, and the gate that makes that possible.

:class:`~dptbd.hw.dp_core.DPCore` reads one state word per accepted pixel and expects it
in the next cycle, and writes one state a fixed latency later without waiting. External
memory answers after any latency, so the adaptor serves reads from the
:class:`~dptbd.hw.axi_store.prefetcher.AxiReadPrefetcher`'s FIFO and writes into the
:class:`~dptbd.hw.axi_store.write_behind.AxiWriteBehind`'s, and ``ready`` lets a pixel in only
when the word it reads is prefetched and the write-behind has room for every state still in
the pipeline. Memory latency and back-pressure on any channel therefore only hold the
input back; they never change a bit (``docs/gateware.md``, "State store in external
memory").
"""

from __future__ import annotations

from amaranth.hdl import Module, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import AxiStoreConfig
from dptbd.hw.axi_store.bus import axi4_signature
from dptbd.hw.axi_store.prefetcher import AxiReadPrefetcher, store_word_layout
from dptbd.hw.axi_store.write_behind import AxiWriteBehind
from dptbd.hw.state_store import StateStoreSignature

__all__ = ["store_signature", "AxiStateStore"]


def store_signature(store: AxiStoreConfig):
    """The pipeline's store port for ``store``: :class:`StateStoreSignature` at P = 1,
    :class:`~dptbd.hw.wide.state_store.WideStateStoreSignature` (a word of P states per
    beat) at P > 1."""
    if store.word_states == 1:
        return StateStoreSignature(store.frame)
    from dptbd.hw.wide.state_store import WideStateStoreSignature
    return WideStateStoreSignature(store.frame)


class AxiStateStore(wiring.Component):
    """State store behind an AXI4 manager port (see the module doc).

    Parameters
    ----------
    store : AxiStoreConfig
        Frame, packing, bursts.
    write_latency : int
        Cycles from a pixel's acceptance to its state write
        (:attr:`~dptbd.hw.schedule.PipelineSchedule.write_latency`).
    style : {"memory", "dp16kd"}
        The prefetcher's beat FIFO (:class:`~dptbd.hw.axi_store.prefetcher.AxiReadPrefetcher`'s
        ``style``): an Amaranth FIFO (default) or ECP5 DP16KDs read through their output
        register. ``dp16kd``: its ``dp16kd`` (tests pass a behavioural model).
        ``"dp16kd"`` (the ECP5 build's) also makes ``ready`` one register (the prefetcher's
        ``available`` and the write-behind's ``room`` a cycle ahead: the same values but
        in the cycle after a restart, where it is low) and writes the write-behind's burst
        descriptors from registers
        (:class:`~dptbd.hw.axi_store.write_behind.AxiWriteBehind` ``staged``: each AW a
        cycle later).

    Members
    -------
    bus : In(StateStoreSignature(cfg))
        The pipeline's side. ``read_en`` must only be high while ``ready`` is. At P = 2 or 4
        pixels per clock :class:`~dptbd.hw.wide.state_store.WideStateStoreSignature`: one
        word of P states per beat (:attr:`AxiStoreConfig.word_states`), P consecutive slots
        in memory.
    axi : Out(axi4_signature(store))
        The AXI4 manager port.
    base : In(address_bits, init=store.base_address)
        Byte address of pixel 0's slot; low bits below the burst size are ignored. Change
        it only while the core is idle between frames.
    ready : Out(1)
        A pixel may be accepted in this cycle.
    restart : In(1)
        The pixel accepted in this cycle resynchronised
        (:attr:`~dptbd.hw.dp_core.DPCore.resync`).
    read_error, write_error : Out(1)
        Pulses: a read beat / a write response came back with ``SLVERR`` or ``DECERR``.
    """

    def __init__(self, store: AxiStoreConfig, *, write_latency: int, style: str = "memory",
                 dp16kd=None):
        self._store = store
        self._reader = AxiReadPrefetcher(store, style=style, dp16kd=dp16kd)
        self._style = style
        self._writer = AxiWriteBehind(store, in_flight=write_latency + 1,
                                      staged=style == "dp16kd")
        super().__init__({
            "bus": In(store_signature(store)),
            "axi": Out(axi4_signature(store)),
            "base": In(store.address_bits, init=store.base_address),
            "ready": Out(1),
            "restart": In(1),
            "read_error": Out(1),
            "write_error": Out(1),
        })

    @property
    def store(self) -> AxiStoreConfig:
        """The memory layout this store was built for."""
        return self._store

    def elaborate(self, platform):
        m = Module()
        store = self._store
        m.submodules.reader = reader = self._reader
        m.submodules.writer = writer = self._writer
        wiring.connect(m, reader.ar, wiring.flipped(self.axi.ar))
        wiring.connect(m, reader.r, wiring.flipped(self.axi.r))
        wiring.connect(m, writer.aw, wiring.flipped(self.axi.aw))
        wiring.connect(m, writer.w, wiring.flipped(self.axi.w))
        wiring.connect(m, writer.b, wiring.flipped(self.axi.b))
        aligned = self.base & ~(store.burst_bytes - 1)
        read_data = Signal(store_word_layout(store))
        with m.If(self.bus.read_en):
            m.d.sync += read_data.eq(reader.word)
        m.d.comb += [
            reader.base.eq(aligned),
            writer.base.eq(aligned),
            reader.written.eq(writer.written),
            reader.take.eq(self.bus.read_en),
            reader.restart.eq(self.restart),
            self.bus.read_data.eq(read_data),
            writer.write_en.eq(self.bus.write_en),
            writer.write_addr.eq(self.bus.write_addr),
            writer.write_data.eq(self.bus.write_data),
            self.read_error.eq(reader.error),
            self.write_error.eq(writer.error),
        ]
        if self._style == "dp16kd":
            # a register: the pipeline's input handshake follows no logic of the store's
            ready = Signal()
            m.d.sync += ready.eq(reader.available_next & writer.room_next)
            m.d.comb += self.ready.eq(ready)
        else:
            m.d.comb += self.ready.eq(reader.available & writer.room)
        return m
