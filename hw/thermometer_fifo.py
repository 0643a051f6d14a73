"""A synchronous FIFO that behaves cycle for cycle as ``amaranth.lib.fifo.SyncFIFOBuffered``,
with every flag a register.

``SyncFIFOBuffered(depth=D)`` is a memory of D - 1 words, read through its registered read
port into an output register (``r_data`` / ``r_rdy``). Its "memory not empty" is
``inner_level != 0`` of a binary level counter, and that decode drives the read port's clock
enable; on ECP5 the counter → decode → enable path was one of the DP core's critical paths.
:class:`ThermometerFIFO` has the same structure and the same cycles (a word written in cycle
t is on ``r`` from cycle t + 2 when the FIFO was empty; ``r.valid`` and ``r.payload`` are
registers; ``w.ready`` is low only when the D - 1 memory words are all in use), but keeps the
memory's level in a :class:`~dptbd.hw.thermometer_counter.ThermometerCounter`: "not empty"
and "full" are registers, so the read enable is one LUT of two registers and ``r.ready``.
The price is D - 1 level registers instead of bitlen(D - 1).

``storage="registers"`` keeps the D - 1 words in flip-flops instead of a memory (the output
register loaded from a multiplexer of them): the same cycles, and on a device whose small
memories are block RAM (iCE40) the word leaves a flip-flop instead of a block-RAM read. A
pair of FIFOs driven by the same ``w.valid`` and ``r.ready`` moves in lockstep, so a payload
can be split between a memory FIFO and a registers twin (``DPCore``'s flags).
``storage="one_hot"`` is ``"registers"`` with one-hot write and read pointers (rings of
D - 1 flip-flops): each word's write enable and read select is one pointer bit, so the read
is an AND-OR of (bit, word) pairs with no decode, and no pointer bit fans out to more than
the word's width (the ECP5 build's flags twin, ``output_queue_style="one_hot"``).

``staged=True`` registers the write first (``w.valid`` and ``w.payload`` into a stage
register, as the memory's word of the next cycle): the same cycles at the ports, but
the writer's logic ends at the stage register instead of running into the memory's write
enable and the level. The staged word is written into the memory at the write pointer in
the next cycle and, when the memory is empty and the output register free, moved into the
output register in that same cycle (read beside the memory: the memory's read is
asynchronous; with ``storage`` other than ``"memory"`` the words are in flip-flops behind
binary pointers). ``low_mark=k`` adds ``low``: the level of ``SyncFIFOBuffered`` (words in
the memory, the stage and the output register) is at most k, from registers.
"""

from __future__ import annotations

from amaranth.hdl import Cat, Const, Module, Mux, Signal, Value
from amaranth.lib import stream, wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

from dptbd.errors import DptbdError, check_int
from dptbd.hw.modular import increment_mod
from dptbd.hw.thermometer_counter import ThermometerCounter

__all__ = ["STORAGES", "ThermometerFIFO"]

#: Where :class:`ThermometerFIFO` keeps its words.
STORAGES = ("memory", "registers", "one_hot")


class ThermometerFIFO(wiring.Component):
    """First in, first out queue of ``depth`` words (see the module doc).

    Parameters
    ----------
    shape : shape-like
        The payload shape (a ``data.Layout`` or a width).
    depth : int
        Words held, in [2, inf): ``depth - 1`` in the memory and one in the output register.
    storage : {"memory", "registers", "one_hot"}
        Where the ``depth - 1`` words are kept: a memory (default) or flip-flops, addressed
        by binary pointers (``"registers"``) or one-hot ones (``"one_hot"``).

    Members
    -------
    w : In(stream.Signature(shape))
        Writes; ``w.ready`` is a register (low when the memory is full).
    r : Out(stream.Signature(shape))
        Reads; ``r.valid`` and ``r.payload`` are registers. ``r.payload`` holds no defined
        value before the first word.
    """

    def __init__(self, shape, depth: int, *, storage: str = "memory", staged: bool = False,
                 low_mark: int | None = None):
        try:
            self._depth = check_int("depth", depth, 2)
            if storage not in STORAGES:
                raise DptbdError(f"storage must be one of {', '.join(map(repr, STORAGES))}, "
                                 f"got {storage!r}")
        except ValueError:
            self._MustUse__silence = True      # refused: never meant to be elaborated
            raise
        self._shape = shape
        self._storage = storage
        self._staged = bool(staged)
        self._low_mark = low_mark
        super().__init__({"w": In(stream.Signature(shape)), "r": Out(stream.Signature(shape)),
                          **({} if low_mark is None else {"low": Out(1)})})

    @property
    def depth(self) -> int:
        """Words held."""
        return self._depth

    def elaborate(self, platform):
        if self._staged:
            return self._elaborate_staged()
        m = Module()
        words = self._depth - 1
        m.submodules.level = level = ThermometerCounter(words)
        not_empty = level.at_least[0]
        full = level.at_least[words - 1]
        do_write = self.w.valid & ~full
        # The memory's head moves into the output register when that is empty or being read.
        do_read = not_empty & (~self.r.valid | self.r.ready)

        if self._storage == "one_hot":
            # rings of one-hot pointers: word i is written when produce[i], read when consume[i]
            produce = Signal(words, init=1)
            consume = Signal(words, init=1)
            with m.If(do_write):
                m.d.sync += produce.eq(produce.rotate_left(1))
            with m.If(do_read):
                m.d.sync += consume.eq(consume.rotate_left(1))
            writes = [produce[i] for i in range(words)]
            reads = [consume[i] for i in range(words)]
        else:
            produce, consume = _binary_pointers(m, words, do_write, do_read)
            writes = [produce == i for i in range(words)]
            reads = [consume == i for i in range(words)]
        m.d.comb += [
            self.w.ready.eq(~full),
            level.up.eq(do_write),
            level.down.eq(do_read),
        ]
        if self._storage == "memory":
            m.submodules.storage = storage = Memory(shape=self._shape, depth=words, init=[])
            write = storage.write_port()
            read = storage.read_port(domain="sync")
            m.d.comb += [
                write.addr.eq(produce),
                write.data.eq(self.w.payload),
                write.en.eq(do_write),
                read.addr.eq(consume),
                read.en.eq(do_read),
                self.r.payload.eq(read.data),
            ]
        else:
            # a write enable per word, and the read an AND-OR of the words, one select per
            # word: an Array or a Switch would become case statements
            # Verilator's lint reports (incompletely covered, or a $pmux's overlapping casez)
            head = Signal(self._shape)
            cells = [Signal(self._shape, name=f"word_{i}") for i in range(words)]
            for i, cell in enumerate(cells):
                with m.If(do_write & writes[i]):
                    m.d.sync += cell.eq(self.w.payload)
            terms = [Mux(reads[i], Value.cast(cell), 0) for i, cell in enumerate(cells)]
            if self._storage == "one_hot":      # a balanced OR of the (bit, word) pairs
                while len(terms) > 1:
                    terms = [terms[j] | terms[j + 1] if j + 1 < len(terms) else terms[j]
                             for j in range(0, len(terms), 2)]
                selected = terms[0]
            else:
                selected = 0
                for term in terms:
                    selected = selected | term
            with m.If(do_read):
                m.d.sync += head.eq(selected)
            m.d.comb += self.r.payload.eq(head)
        self._output_valid(m, do_read)
        if self._low_mark is not None:
            m.d.comb += self.low.eq(_at_most(level.at_least, self._low_mark, [self.r.valid]))
        return m

    def _output_valid(self, m, do_read):
        """``r.valid``: set when a word moves into the output register, cleared when the
        word is read and none follows."""
        with m.If(do_read):
            m.d.sync += self.r.valid.eq(1)
        with m.Elif(self.r.ready):
            m.d.sync += self.r.valid.eq(0)

    def _elaborate_staged(self):
        """``staged=True``: the write through a stage register (see the module doc)."""
        m = Module()
        words = self._depth - 1
        m.submodules.level = level = ThermometerCounter(words)
        staged = Signal()                            # a word in the stage: the memory's
        staged_word = Signal(self._shape)
        # room while the stage and the memory hold at most words - 1 (SyncFIFOBuffered's
        # memory level below its depth)
        full = level.at_least[words - 1] | (staged & (level.at_least[words - 2] if words > 1
                                                      else 1))
        m.d.comb += self.w.ready.eq(~full)
        m.d.sync += [staged.eq(self.w.valid & ~full), staged_word.eq(self.w.payload)]
        not_empty = level.at_least[0]
        # the oldest word (the memory's head, else the staged word) moves into the output
        # register when that is empty or being read; the staged word is always written
        # into the memory, so a word moved from the stage passes through it at once
        do_read = (not_empty | staged) & (~self.r.valid | self.r.ready)
        produce, consume = _binary_pointers(m, words, staged, do_read)
        m.d.comb += [level.up.eq(staged), level.down.eq(do_read)]
        head = Signal(self._shape)
        if self._storage == "memory":
            m.submodules.storage = storage = Memory(shape=self._shape, depth=words, init=[])
            write = storage.write_port()
            read = storage.read_port(domain="comb")
            m.d.comb += [write.addr.eq(produce), write.data.eq(staged_word),
                         write.en.eq(staged), read.addr.eq(consume)]
            oldest = read.data
        else:
            cells = [Signal(self._shape, name=f"word_{i}") for i in range(words)]
            for i, cell in enumerate(cells):
                with m.If(staged & (produce == i)):
                    m.d.sync += cell.eq(staged_word)
            oldest = 0
            for i, cell in enumerate(cells):
                oldest = oldest | Mux(consume == i, Value.cast(cell), 0)
        with m.If(do_read):
            m.d.sync += head.eq(Mux(not_empty, oldest, staged_word))
        m.d.comb += self.r.payload.eq(head)
        self._output_valid(m, do_read)
        if self._low_mark is not None:
            m.d.comb += self.low.eq(_at_most(level.at_least, self._low_mark,
                                             [staged, self.r.valid]))
        return m


def _binary_pointers(m, words: int, do_write, do_read):
    """The write and read pointers of a ring of ``words`` words, each stepped modulo
    ``words`` when its handshake is done; returns ``(produce, consume)``."""
    produce = Signal(range(words))
    consume = Signal(range(words))
    with m.If(do_write):
        m.d.sync += produce.eq(increment_mod(produce, words))
    with m.If(do_read):
        m.d.sync += consume.eq(increment_mod(consume, words))
    return produce, consume


def _at_most(at_least, mark: int, extra) -> Value:
    """A thermometer count (``at_least``) plus the one-bit ``extra`` counts is at most
    ``mark``: for each number e of extra bits set, count <= mark - e."""
    terms = []
    n = len(extra)
    for pattern in range(1 << n):
        bits = [(pattern >> i) & 1 for i in range(n)]
        e = sum(bits)
        match = Cat(*[b if want else ~b for b, want in zip(extra, bits)]).all()
        left = mark - e                              # count <= left
        if left < 0:
            continue
        within = 1 if left >= len(at_least) else ~at_least[left]
        terms.append(match & within)
    return Cat(*terms).any() if terms else Const(0, 1)
