"""Line buffers: a chain of delay lines, each ``depth`` entries long, in one memory.

For a window of 2r+1 rows the pipeline needs the 2r previous rows of the incoming state
stream. All 2r delay lines share one address (a pointer that cycles through 0 … W-1), so
they are stored side by side in one :class:`~amaranth.lib.memory.Memory` of W words of
2r entries each: one read and one write per advance, one block RAM column on an FPGA.

With ``registered_read=True`` the memory's read data goes through a register before it
reaches the taps, so no logic sits after the block RAM's clock-to-out (5.6 ns on an ECP5
DP16KD without its own output register, which Yosys does not infer). The read is then issued
one cycle ahead, at the address the pointer will hold in the next cycle, so the taps keep
their timing: the registered read costs one register per memory bit and no latency. It buys
ECP5 15 MHz and costs the iCE40 30 logic cells for nothing (``docs/synthesis.md``, "The line
buffer's read register"), so it is off by default.

With ``banked_read=True`` (needs ``ram_style="distributed"``, LUT RAM) the memory is built as
banks of :data:`LUT_RAM_BANK_DEPTH` words (one ``TRELLIS_DPR16X4`` column each), read
asynchronously into a register per bank, with the bank select registered beside them: the
bank multiplexer follows the registers instead of sitting between the LUT RAM and the read
register, and the write (data, address, enable) is registered once more so the multiplexer
does not drive the write ports either. Same taps, same cycles; costs one register per bank
and memory bit. Off by default: on ECP5 it moved the critical path elsewhere (+6 to +11 MHz
on two seeds) but nextpnr's router did not converge on the third seed (``docs/synthesis.md``,
"Towards 200 MHz on ECP5").
"""

from __future__ import annotations

from amaranth.hdl import Array, Cat, Module, Mux, Shape, Signal, unsigned
from amaranth.lib import wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

from dptbd.hw.modular import increment_mod

__all__ = ["LUT_RAM_BANK_DEPTH", "RAM_STYLES", "LineBuffer"]

#: Words per LUT-RAM bank of ``ram_style="distributed"`` (an ECP5 ``TRELLIS_DPR16X4``).
LUT_RAM_BANK_DEPTH = 16

#: ``LineBuffer(ram_style=…)``: inferred (block RAM) or LUT RAM.
RAM_STYLES = (None, "distributed")


class LineBuffer(wiring.Component):
    """``taps`` cascaded delay lines of ``depth`` entries each.

    Parameters
    ----------
    shape : ShapeLike
        Shape of one entry (e.g. :func:`~dptbd.hw.layouts.state_word_layout`).
    depth : int
        Entries per delay line (the frame width W), >= 2; >= 3 with ``registered_read`` (the
        read one cycle ahead must not meet the write of the entry it reads) or with
        ``banked_read`` (the write a cycle late must not meet the read).
    taps : int
        Number of delay lines (2r), >= 1.
    registered_read : bool
        Register the memory's read data (module docstring); needs ``depth`` >= 3.
    ram_style : {None, "distributed"}
        Synthesis attribute of the memory: ``None`` (default) leaves it to RAM inference
        (a block RAM), ``"distributed"`` asks Yosys for LUT RAM (ECP5 ``TRELLIS_DPR16X4``,
        no block RAM clock-to-out on the read path; ``docs/synthesis.md``, "Towards 200 MHz
        on ECP5"). Behaviour and timing are the same either way.
    banked_read : bool
        LUT RAM in registered banks (module docstring); needs ``ram_style="distributed"``,
        no ``registered_read`` and ``depth`` >= 3.

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

    def __init__(self, shape, depth: int, taps: int, *, registered_read: bool = False,
                 ram_style: str | None = None, banked_read: bool = False):
        if banked_read and (ram_style != "distributed" or registered_read):
            raise ValueError("banked_read needs ram_style='distributed' and no registered_read")
        if ram_style not in RAM_STYLES:
            raise ValueError(f"ram_style must be one of {RAM_STYLES}, got {ram_style!r}")
        low = 3 if registered_read or banked_read else 2
        if depth < low:
            raise ValueError(f"depth must be an integer in [{low}, inf), got {depth}")
        if taps < 1:
            raise ValueError(f"taps must be an integer in [1, inf), got {taps}")
        self._shape = shape
        self._depth = depth
        self._n_taps = taps
        self._registered_read = bool(registered_read)
        self._ram_style = ram_style
        self._banked_read = bool(banked_read)
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
        if self._banked_read:
            return self._elaborate_banked(m, entry_bits, n_taps)
        m.submodules.memory = memory = Memory(
            shape=unsigned(entry_bits * n_taps), depth=self._depth, init=[],
            attrs=None if self._ram_style is None else {"ram_style": self._ram_style})
        read = memory.read_port(domain="sync")
        write = memory.write_port(domain="sync")
        pointer, pointer_next, write_pointer, write_pending = self._pointers(m)
        if self._registered_read:
            # Cycle t: pointer P(t), the address an advance in cycle t moves past. The memory
            # reads P(t+1) at the end of cycle t (one cycle ahead, enabled every cycle), the
            # register takes that word at the end of cycle t+1, so in cycle t+1 the taps show
            # the word at P(t) as it stood at the end of cycle t-1. The entry last written
            # there was written in the cycle after the advance `depth` advances earlier, at
            # the latest in cycle t + 1 - depth <= t - 2: the read sees it.
            words = Signal(entry_bits * n_taps)
            m.d.comb += read.addr.eq(pointer_next)
            m.d.sync += words.eq(read.data)
        else:
            # The read of P(t) is issued in cycle t, its word is out in cycle t+1.
            words = read.data
            m.d.comb += [read.addr.eq(pointer), read.en.eq(self.advance)]

        for k in range(n_taps):
            m.d.comb += self.taps[k].eq(words[k * entry_bits:(k + 1) * entry_bits])
        # Tap k+1's delay line is fed by tap k's output; tap 0's by data_in.
        shifted = Cat(self.data_in, *[self.taps[k] for k in range(n_taps - 1)])
        m.d.comb += [
            write.addr.eq(write_pointer),
            write.data.eq(shifted),
            write.en.eq(write_pending),
        ]
        return m

    def _pointers(self, m):
        pointer = Signal(range(self._depth))
        pointer_next = Signal(range(self._depth))
        write_pointer = Signal(range(self._depth))
        write_pending = Signal()
        m.d.comb += pointer_next.eq(
            Mux(self.advance, increment_mod(pointer, self._depth), pointer))
        m.d.sync += [
            pointer.eq(pointer_next),
            write_pointer.eq(pointer),
            write_pending.eq(self.advance),
        ]
        return pointer, pointer_next, write_pointer, write_pending

    def _elaborate_banked(self, m, entry_bits, n_taps):
        # LUT RAM in banks of LUT_RAM_BANK_DEPTH words, each read asynchronously at the
        # pointer's low bits into a register of its own; the bank select (the pointer's high
        # bits) is registered beside them and the bank multiplexer sits after the registers.
        # Same cycle behaviour as the synchronous read port (the bank registers load on
        # `advance` with the words as they stand after the previous cycle's write), but
        # the pointer -> LUT RAM -> register path has no multiplexer on it.
        pointer, _, write_pointer, write_pending = self._pointers(m)
        bank_depth = LUT_RAM_BANK_DEPTH
        n_banks = -(-self._depth // bank_depth)
        low_bits = (bank_depth - 1).bit_length()
        word_bits = entry_bits * n_taps
        bank_words = []
        shifted = Signal(word_bits)
        # The write is registered once more (data, address, enable), so the bank multiplexer
        # does not drive the LUT RAMs' write ports either: written a cycle later, still at
        # least depth - 2 >= 1 cycles before the read of the same address.
        late_data = Signal(word_bits)
        late_pointer = Signal(range(self._depth))
        late_pending = Signal()
        m.d.sync += [late_data.eq(shifted), late_pointer.eq(write_pointer),
                     late_pending.eq(write_pending)]
        for b in range(n_banks):
            memory = Memory(shape=unsigned(word_bits),
                            depth=min(bank_depth, self._depth - b * bank_depth), init=[],
                            attrs={"ram_style": self._ram_style})
            m.submodules[f"bank_{b}"] = memory
            read = memory.read_port(domain="comb")
            write = memory.write_port(domain="sync")
            word = Signal(word_bits, name=f"bank_word_{b}")
            m.d.comb += [
                read.addr.eq(pointer[:low_bits]),
                write.addr.eq(late_pointer[:low_bits]),
                write.data.eq(late_data),
                write.en.eq(late_pending & (late_pointer[low_bits:] == b)),
            ]
            with m.If(self.advance):
                m.d.sync += word.eq(read.data)
            bank_words.append(word)
        bank = Signal(range(n_banks))
        with m.If(self.advance):
            m.d.sync += bank.eq(pointer[low_bits:])
        words = Array(bank_words)[bank]
        for k in range(n_taps):
            m.d.comb += self.taps[k].eq(words[k * entry_bits:(k + 1) * entry_bits])
        m.d.comb += shifted.eq(Cat(self.data_in, *[self.taps[k] for k in range(n_taps - 1)]))
        return m
