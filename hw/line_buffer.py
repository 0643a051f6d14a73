"""Line buffers: a chain of delay lines, each ``depth`` entries long, in one memory.

For a window of 2r+1 rows the pipeline needs the 2r previous rows of the incoming state
stream. All 2r delay lines share one address (a pointer that cycles through 0 … W-1), so
they are stored side by side in one :class:`~amaranth.lib.memory.Memory` of W words of
2r entries each: one read and one write per advance, one block RAM column on an FPGA.
"""

from __future__ import annotations

from amaranth.hdl import Cat, Module, Mux, Shape, Signal, unsigned
from amaranth.lib import wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

__all__ = ["LineBuffer"]


class LineBuffer(wiring.Component):
    """``taps`` cascaded delay lines of ``depth`` entries each.

    Parameters
    ----------
    shape : ShapeLike
        Shape of one entry (e.g. :func:`~dptbd.hw.layouts.state_word_layout`).
    depth : int
        Entries per delay line (the frame width W), >= 2.
    taps : int
        Number of delay lines (2r), >= 1.

    Members
    -------
    advance : In(1)
        Cycle t: a new entry will be presented on ``data_in`` in cycle t+1. Issues the
        memory read.
    data_in : In(shape)
        Cycle t+1: the new entry.
    taps : Out(shape).array(taps)
        Cycle t+1: ``taps[k]`` is the entry given on ``data_in`` ``(k+1) * depth`` advances
        earlier. The memory starts at 0, so the first ``(k+1) * depth`` outputs of tap k
        are 0.

    Between ``advance`` and the cycle after, ``advance`` may not be asserted twice for the
    same entry; one advance per cycle at most, and ``data_in`` is sampled exactly once, in
    the cycle after each advance.
    """

    def __init__(self, shape, depth: int, taps: int):
        if depth < 2:
            raise ValueError(f"depth must be an integer in [2, inf), got {depth}")
        if taps < 1:
            raise ValueError(f"taps must be an integer in [1, inf), got {taps}")
        self._shape = shape
        self._depth = depth
        self._n_taps = taps
        super().__init__({
            "advance": In(1),
            "data_in": In(shape),
            "taps": Out(shape).array(taps),
        })

    @property
    def depth(self) -> int:
        """Entries per delay line."""
        return self._depth

    def elaborate(self, platform):
        m = Module()
        entry_bits = Shape.cast(self._shape).width
        n_taps = self._n_taps
        m.submodules.memory = memory = Memory(
            shape=unsigned(entry_bits * n_taps), depth=self._depth, init=[])
        read = memory.read_port(domain="sync")
        write = memory.write_port(domain="sync")

        pointer = Signal(range(self._depth))
        write_pointer = Signal(range(self._depth))
        write_pending = Signal()
        m.d.comb += [
            read.addr.eq(pointer),
            read.en.eq(self.advance),
        ]
        with m.If(self.advance):
            m.d.sync += pointer.eq(Mux(pointer == self._depth - 1, 0, pointer + 1))
        m.d.sync += [
            write_pointer.eq(pointer),
            write_pending.eq(self.advance),
        ]

        for k in range(n_taps):
            m.d.comb += self.taps[k].eq(read.data[k * entry_bits:(k + 1) * entry_bits])
        # Tap k+1's delay line is fed by tap k's output; tap 0's by data_in.
        shifted = Cat(self.data_in, *[self.taps[k] for k in range(n_taps - 1)])
        m.d.comb += [
            write.addr.eq(write_pointer),
            write.data.eq(shifted),
            write.en.eq(write_pending),
        ]
        return m
