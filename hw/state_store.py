"""The state store: the previous frame's (E, d) of every pixel, W*H words.

The pipeline talks to the store through :class:`StateStoreSignature`, a plain synchronous
single-read, single-write memory interface, so that a design too large for on-chip RAM can
use :class:`~dptbd.hw.dp_core.DPCore` with an external memory instead of
:class:`StateStore` (see ``docs/gateware.md``).
"""

from __future__ import annotations

from amaranth.hdl import Module
from amaranth.lib import wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.layouts import state_word_layout

__all__ = ["StateStoreSignature", "StateStore"]


class StateStoreSignature(wiring.Signature):
    """Interface between the pipeline (the initiator, flows as seen by it) and a state store.

    Members
    -------
    read_addr : Out(range(W*H))
        Raster address ``row * W + col`` to read.
    read_en : Out(1)
        Read ``read_addr`` at this cycle's rising edge.
    read_data : In(state_word_layout)
        The word addressed when ``read_en`` was last high. It must be valid in the cycle right
        after the one with ``read_en`` high (one-cycle synchronous read); the pipeline samples
        it only then.
    write_addr : Out(range(W*H))
        Raster address to write.
    write_data : Out(state_word_layout)
        (E, d) to store.
    write_en : Out(1)
        Write at this cycle's rising edge; the word must be readable by a read issued in the
        next cycle.

    Outside the first frame after a resynchronisation the pipeline never reads and writes
    the same address in the same cycle, so the store's read-during-write behaviour does not
    matter.
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        words = cfg.width * cfg.height
        layout = state_word_layout(cfg)
        super().__init__({
            "read_addr": Out(range(words)),
            "read_en": Out(1),
            "read_data": In(layout),
            "write_addr": Out(range(words)),
            "write_data": Out(layout),
            "write_en": Out(1),
        })

    def __eq__(self, other):
        return type(other) is type(self) and other._cfg == self._cfg

    def __repr__(self):
        return f"StateStoreSignature({self._cfg.width}x{self._cfg.height})"


class StateStore(wiring.Component):
    """On-chip state store: one :class:`~amaranth.lib.memory.Memory` of W*H (E, d) words.

    One synchronous, non-transparent read port and one write port. The contents start at 0
    (E = 0, d = 0); they are only meaningful after a segment's first frame has been written.

    Parameters
    ----------
    cfg : DPConfig
        Frame size and widths.

    Members
    -------
    bus : In(StateStoreSignature(cfg))
        The pipeline's side of the store.
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({"bus": In(StateStoreSignature(cfg))})

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        m.submodules.memory = memory = Memory(
            shape=state_word_layout(cfg), depth=cfg.width * cfg.height, init=[])
        read = memory.read_port(domain="sync")
        write = memory.write_port(domain="sync")
        m.d.comb += [
            read.addr.eq(self.bus.read_addr),
            read.en.eq(self.bus.read_en),
            self.bus.read_data.eq(read.data),
            write.addr.eq(self.bus.write_addr),
            write.data.eq(self.bus.write_data),
            write.en.eq(self.bus.write_en),
        ]
        return m
