"""Line buffers: a chain of delay lines, each ``depth`` entries long, in one memory.

For a window of 2r+1 rows the pipeline needs the 2r previous rows of the incoming state
stream. All 2r delay lines share one address (a pointer that cycles through 0 … W-1), so
they are stored side by side in one :class:`~amaranth.lib.memory.Memory` of W words of
2r entries each: one read and one write per advance, one block RAM column on an FPGA.

With ``registered_read=True`` the memory's read data goes through a register before it
reaches the taps, so no logic sits after the block RAM's clock-to-out (5.6 ns on an ECP5
DP16KD without its own output register, which Yosys does not infer). The read is then issued
one cycle ahead, at the address the pointer will hold in the next cycle, so the taps keep
their timing: the registered read costs one register per memory bit and no latency. What it
gains and costs on each family is measured in ``docs/synthesis.md`` ("The line buffer's
read"); it is off by default.

With ``banked_read=True`` (needs ``ram_style="distributed"``, LUT RAM) the memory is built as
banks of :data:`LUT_RAM_BANK_DEPTH` words (one ``TRELLIS_DPR16X4`` column each), read
asynchronously into a register per bank, with the bank select registered beside them: the
bank multiplexer follows the registers instead of sitting between the LUT RAM and the read
register, and the write (data, address, enable) is registered once more so the multiplexer
does not drive the write ports either. Same taps, same cycles; costs one register per bank
and memory bit. Off by default: on ECP5 nextpnr's router did not converge
on every seed with it (``docs/synthesis.md``, "The line buffer's read").

With ``interleaved_read=True`` (needs ``ram_style="distributed"`` and an even ``depth`` >= 4)
the LUT RAM is read ahead, so that neither the read address's fan-out nor a multiplexer sits
between the LUT RAM and a register: the entries at even and odd addresses live in two
halves, each in banks of :data:`LUT_RAM_BANK_DEPTH` words. The entry an advance in cycle t
asks for is at P(t), the pointer, which in cycle t-1 was either P(t) or P(t) - 1: one even
and one odd address. So in every cycle the even half is read at the even one of P and P+1,
the odd half at the odd one, each bank into a register of its own (no enable, no
multiplexer, read address from a 4-bit counter per half); in cycle t the word at P(t) is in
the bank registers whatever cycle t-1 did, and the read register takes it on ``advance``
through an AND-OR multiplexer whose select is a one-hot register (half = P's parity, bank =
P's high bits), its pair terms kept (``keep``) so that Yosys maps two LUT levels rather than
a chain of three. Same taps, same cycles, no write delay; costs one register per bank and
memory bit (224 for the 128 x 28-bit line buffer of the default build). It takes the line
buffer out of the ECP5 critical paths (``docs/synthesis.md``, "The line buffer's read").

With ``ram_style="dp16kd"`` (ECP5 only; ``depth`` >= 3) the memory is ECP5 ``DP16KD`` block
RAMs read through their output register (``REGMODE_B = "OUTREG"``,
:func:`~dptbd.hw.dp16kd.dp16kd_memory`), so the taps come from a register inside the block
RAM (~1 ns clock-to-out) and the read address from a register: the read is issued a cycle
ahead, on ``advance``, at ``ahead`` = P + 1 (mod depth), a register kept beside the pointer,
which is where the pointer will be after the advance. The array's read register thus holds
the word at P(t) in every cycle t (read on the advance that moved the pointer there, and held,
its enable low, through stalls), and the output register, enabled every cycle, shows it in
cycle t+1. Same taps, same cycles as the synchronous read port; the word at P + 1 was last
written at the latest in the cycle before the read when ``depth`` >= 3.
"""

from __future__ import annotations

from amaranth.hdl import Array, Cat, Module, Mux, Shape, Signal, unsigned
from amaranth.lib import wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

from dptbd.hw.dp16kd import dp16kd_memory
from dptbd.hw.modular import increment_mod

__all__ = ["LUT_RAM_BANK_DEPTH", "RAM_STYLES", "LineBuffer"]

#: Words per LUT-RAM bank of ``ram_style="distributed"`` (an ECP5 ``TRELLIS_DPR16X4``).
LUT_RAM_BANK_DEPTH = 16

#: ``LineBuffer(ram_style=…)``: inferred (block RAM), LUT RAM, or ECP5 DP16KDs read through
#: their output register.
RAM_STYLES = (None, "distributed", "dp16kd")


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
    ram_style : {None, "distributed", "dp16kd"}
        Synthesis attribute of the memory: ``None`` (default) leaves it to RAM inference
        (a block RAM), ``"distributed"`` asks Yosys for LUT RAM (ECP5 ``TRELLIS_DPR16X4``,
        no block RAM clock-to-out on the read path; ``docs/synthesis.md``, "Block RAM
        reads"), ``"dp16kd"`` builds ECP5 DP16KDs read a cycle ahead through their output
        register (module docstring; needs ``depth`` >= 3, no other read option). Behaviour
        and timing are the same either way.
    banked_read : bool
        LUT RAM in registered banks (module docstring); needs ``ram_style="distributed"``,
        no ``registered_read`` and ``depth`` >= 3.
    interleaved_read : bool
        LUT RAM read ahead in interleaved halves into bank registers (module docstring);
        needs ``ram_style="distributed"``, an even ``depth`` >= 4 and neither
        ``registered_read`` nor ``banked_read``.
    dp16kd : callable or None
        With ``ram_style="dp16kd"``: ``dp16kd(**ports)`` builds one DP16KD (``cell`` of
        :func:`~dptbd.hw.dp16kd.dp16kd_memory`; ``None``: the ``Instance``). Tests pass a
        behavioural model.

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
                 ram_style: str | None = None, banked_read: bool = False,
                 interleaved_read: bool = False, dp16kd=None):
        if ram_style == "dp16kd" and registered_read:
            raise ValueError("ram_style='dp16kd' reads through the block RAM's output "
                             "register: no registered_read")
        if banked_read and (ram_style != "distributed" or registered_read):
            raise ValueError("banked_read needs ram_style='distributed' and no registered_read")
        if ram_style not in RAM_STYLES:
            raise ValueError(f"ram_style must be one of {RAM_STYLES}, got {ram_style!r}")
        if interleaved_read:
            if ram_style != "distributed" or registered_read or banked_read:
                raise ValueError("interleaved_read needs ram_style='distributed', no "
                                 "registered_read and no banked_read")
            if depth < 4 or depth % 2:
                raise ValueError(f"depth must be an even integer in [4, inf) with "
                                 f"interleaved_read, got {depth}")
        low = 3 if registered_read or banked_read or ram_style == "dp16kd" else 2
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
        self._interleaved_read = bool(interleaved_read)
        self._dp16kd = dp16kd
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
        if self._interleaved_read:
            return self._elaborate_interleaved(m, entry_bits * n_taps)
        if self._ram_style == "dp16kd":
            return self._elaborate_dp16kd(m, entry_bits, n_taps)
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

    def _elaborate_dp16kd(self, m, entry_bits, n_taps):
        pointer, _, write_pointer, write_pending = self._pointers(m)
        # `ahead` = (P + 1) mod depth, stepped with the pointer: the address the array reads
        # on an advance, from a register (no logic between it and the block RAMs' pins).
        ahead = Signal(range(self._depth), init=1)
        with m.If(self.advance):
            m.d.sync += ahead.eq(increment_mod(ahead, self._depth))
        word_bits = entry_bits * n_taps
        shifted = Signal(word_bits)
        words = dp16kd_memory(
            m, "bank", width=word_bits, depth=self._depth, read_addr=ahead,
            read_en=self.advance, out_en=1, write_addr=write_pointer, write_data=shifted,
            write_en=write_pending, cell=self._dp16kd)
        for k in range(n_taps):
            m.d.comb += self.taps[k].eq(words[k * entry_bits:(k + 1) * entry_bits])
        m.d.comb += shifted.eq(Cat(self.data_in, *[self.taps[k] for k in range(n_taps - 1)]))
        return m

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

    def _elaborate_interleaved(self, m, word_bits):
        depth = self._depth
        half = depth // 2
        pointer, _, write_pointer, write_pending = self._pointers(m)
        bank_depth = LUT_RAM_BANK_DEPTH
        n_banks = -(-half // bank_depth)                       # banks per half
        low_width = len(Signal(range(min(bank_depth, half))))  # address bits in a bank
        # The index in the even half of the even one of P and P+1 is ((P+1) mod depth) >> 1:
        # it steps on an advance from an even P and is at its end (half-1) for P in
        # {depth-3, depth-2}; the odd half's, P >> 1, steps from an odd P and is at its end
        # for P in {depth-2, depth-1}. Only the bank-internal bits are kept, one counter per
        # half; they wrap with the index unless half is a multiple of the bank depth (or a
        # power of two below it), where the increment wraps by itself.
        parity = pointer[0]
        at_end = [Signal(name="even_at_end"), Signal(name="odd_at_end")]
        with m.If(self.advance):   # the flags of the pointer's next value, from the pointer
            m.d.sync += [
                at_end[0].eq((pointer == depth - 4) | (pointer == depth - 3)),
                at_end[1].eq((pointer == depth - 3) | (pointer == depth - 2)),
            ]
        wraps_itself = half % bank_depth == 0 or half == 1 << low_width
        read_addrs = []
        for h, step in enumerate((self.advance & ~parity, self.advance & parity)):
            addr = Signal(low_width, name=f"read_addr_{'even' if h == 0 else 'odd'}")
            following = (addr + 1)[:low_width]
            with m.If(step):
                m.d.sync += addr.eq(following if wraps_itself else Mux(at_end[h], 0, following))
            read_addrs.append(addr)

        shifted = Signal(word_bits)
        bank_words = []                                        # index: half + 2 * bank
        for b in range(n_banks):
            for h in range(2):
                memory = Memory(shape=unsigned(word_bits),
                                depth=min(bank_depth, half - b * bank_depth), init=[],
                                attrs={"ram_style": self._ram_style})
                m.submodules[f"bank_{h}_{b}"] = memory
                read = memory.read_port(domain="comb")
                write = memory.write_port(domain="sync")
                m.d.comb += [
                    read.addr.eq(read_addrs[h]),
                    write.addr.eq(write_pointer[1:1 + low_width]),
                    write.data.eq(shifted),
                    write.en.eq(write_pending & (write_pointer[0] == h)
                                & ((write_pointer >> (1 + low_width)) == b)),
                ]
                word = Signal(word_bits, name=f"bank_word_{h}_{b}")
                m.d.sync += word.eq(read.data)
                bank_words.append(word)

        # Cycle t: the bank registers hold the words at P(t) and its neighbour; the entry at
        # P(t) is in half P[0], bank P >> (1 + low_width): bit half + 2 * bank of `onehot`,
        # kept from the pointer's registers, not decoded from its next value. An advance
        # from an even P moves to the odd half of the same bank (one up), from an odd P back
        # to the even half (one down), unless P is the bank's last odd address or depth - 1
        # (one up, wrapping to 0).
        onehot = Signal(len(bank_words), init=1)
        last_odd = Signal()                  # for an odd P, set from the even P before it
        with m.If(self.advance):
            m.d.sync += [
                last_odd.eq((pointer[1:1 + low_width] == (1 << low_width) - 1)
                            | (pointer == depth - 2)),
                onehot.eq(Mux(~parity | last_odd, onehot.rotate_left(1),
                              onehot.rotate_right(1))),
            ]
        # The AND-OR in two LUT levels: terms of two banks each (LUT4), kept, then their OR;
        # without the keep ABC9 maps a chain of three LUT4 off the critical path's slack.
        words = Signal(word_bits)
        for i in range(word_bits):
            pairs = []
            for j in range(0, len(bank_words), 2):
                pair = Signal(name=f"read_pair_{i}_{j // 2}", attrs={"keep": 1})
                m.d.comb += pair.eq(Cat(onehot[k] & bank_words[k][i]
                                        for k in range(j, min(j + 2, len(bank_words)))).any())
                pairs.append(pair)
            with m.If(self.advance):
                m.d.sync += words[i].eq(Cat(pairs).any())
        entry_bits = word_bits // self._n_taps
        for k in range(self._n_taps):
            m.d.comb += self.taps[k].eq(words[k * entry_bits:(k + 1) * entry_bits])
        m.d.comb += shifted.eq(Cat(self.data_in, *self.taps[:self._n_taps - 1]))
        return m

