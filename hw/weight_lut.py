"""The weight LUT: (M+1) x M weight codes, M lookups per clock, writable at run time.

Candidate m needs code ``c[d(q_m), m]`` where ``d(q_m)`` is the direction of its own
predecessor. Each move reads only its own column of the table, so the table is split into
M column memories (one per move, M+1 entries each, indexed by the predecessor's direction):
M lookups per clock, each entry stored once, no replication.

A direction code above M (B_d bits hold up to ``2**B_d - 1``; the pipeline never writes
such a code, but an external state store may hold one) reads row M, the ``START`` row:
the lookup is ``c[min(d, M), m]`` (``docs/arithmetic.md`` §3, model operator
``lookup_weight_code``). The clamp sits on each column's read address, so no lookup ever
addresses a column memory out of range (which a 4-state simulator answers with X).

Write protocol: a write presented in cycle c (``write_en`` high at the edge ending it) is
registered, then stored at the edge ending cycle c+1. Reads are synchronous and
non-transparent, so a lookup issued in cycle c+2 or later sees it and one issued earlier
does not. The pipeline issues a pixel's lookups in cycle 2 after its acceptance, so every
pixel accepted in cycle c or later uses the new code and every pixel accepted before
cycle c the old one.

Storage (``lut_style``, :data:`LUT_STYLES`): ``"bram"`` leaves the column memories to the
synthesis tool's RAM inference (Yosys ``synth_ice40``: one SB_RAM40_4K per column, since
each column needs its own read port); ``"logic"`` marks them ``ram_style = "logic"``
(flip-flops, no block RAM), reads every row and selects with a multiplexer tree of its own,
and enables a column's write by a registered one-hot move; ``"auto"`` (the default)
is ``"logic"`` when a column has at most :data:`AUTO_LOGIC_MAX_ENTRIES` entries (r = 1:
10 entries) and ``"bram"`` otherwise (r = 2: 26). The style changes the storage only:
behaviour and timing are identical. ``docs/gateware.md`` ("Weight LUT storage")
gives the reasons and the measured cost.
"""

from __future__ import annotations

from amaranth.hdl import Const, Module, Mux, Signal, unsigned
from amaranth.lib import wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig

__all__ = ["LUT_STYLES", "WRITE_DECODES", "AUTO_LOGIC_MAX_ENTRIES", "resolve_lut_style",
           "DirectionTable", "WeightLUT"]

#: Accepted values of the ``lut_style`` keyword.
LUT_STYLES = ("auto", "bram", "logic")

#: Accepted values of the ``write_decode`` keyword (:class:`DirectionTable`).
WRITE_DECODES = ("case", "predecoded")

#: ``"auto"`` stores the table in logic when a column has at most this many entries (M+1).
AUTO_LOGIC_MAX_ENTRIES = 16


def resolve_lut_style(cfg: DPConfig, lut_style: str = "auto") -> str:
    """The storage ``lut_style`` means for ``cfg``: ``"bram"`` or ``"logic"``.

    Parameters
    ----------
    cfg : DPConfig
        Gives M, the number of moves (a column has M+1 entries).
    lut_style : {"auto", "bram", "logic"}
        ``"auto"``: ``"logic"`` if M+1 <= :data:`AUTO_LOGIC_MAX_ENTRIES` (radius 1),
        else ``"bram"`` (radius 2).

    Raises
    ------
    ValueError
        ``lut_style`` is not one of :data:`LUT_STYLES`.
    """
    if not isinstance(lut_style, str) or lut_style not in LUT_STYLES:
        raise ValueError(f"lut_style must be one of {', '.join(map(repr, LUT_STYLES))}, "
                         f"got {lut_style!r}")
    if lut_style == "auto":
        return "logic" if cfg.n_moves + 1 <= AUTO_LOGIC_MAX_ENTRIES else "bram"
    return lut_style


def _above(value, constant: int):
    """``value > constant`` as AND/OR logic on the bits of ``value``, without a subtractor.

    Bit i up from 0: ``value[:i+1] > constant[:i+1]`` is ``value[i] & (value[:i] >
    constant[:i])`` where ``constant`` has a 1 and ``value[i] | (…)`` where it has a 0.
    A B_d-bit comparison then maps to LUTs alone; Yosys turns ``>`` into an ``SB_CARRY``
    chain (measured for the M clamps at r = 2, 128 x 128: 105 SB_LUT4 instead of 234
    SB_LUT4 + 75 SB_CARRY).
    """
    above = Const(0, 1)
    for bit in range(len(value)):
        above = (value[bit] & above) if (constant >> bit) & 1 else (value[bit] | above)
    return above


def _select(items: list, index):
    """``items[index]`` as a binary tree of ``Mux`` on ``index``'s bits, most significant at
    the root; ``len(items)`` is ``2 ** len(index)``."""
    if len(items) == 1:
        return items[0]
    half = len(items) // 2
    bit = index[(half - 1).bit_length()]
    return Mux(bit, _select(items[half:], index), _select(items[:half], index))


class DirectionTable(wiring.Component):
    """M column memories of codes indexed (predecessor direction, move), M lookups per
    clock, with a single table-wide write port: the weight LUT's storage, shared with the
    penalty LUT (:class:`~dptbd.hw.penalty_lut.PenaltyLUT`, ``docs/arithmetic.md`` §8.2).

    Parameters
    ----------
    cfg : DPConfig
        Number of moves M and direction width B_d.
    codes : numpy.ndarray
        ``(M + 1, M)`` initial codes, indexed ``[direction, move]``.
    code_bits : int
        Width of a code.
    max_code : int or None
        A write above it is stored as ``max_code``; ``None`` (or ``2**code_bits - 1``,
        which no write exceeds): every ``code_bits`` value is stored as written, with no
        comparator.
    lut_style : {"auto", "bram", "logic"}
        Storage of the column memories (module docstring, :func:`resolve_lut_style`).
    write_decode : {"case", "predecoded"}
        How the registered write finds its entry: a case per entry giving (row, one-hot
        move) registers (default), or, with ``lut_style="logic"`` (the ECP5 build's,
        ``lut_write="predecoded"``), the address's low and high halves each registered
        one-hot (the high half with ``write_en``), each code's enable the AND of one bit
        of each: one LUT level before and one after the registers instead of the case's
        three. The same codes in every cycle; with ``"bram"`` it is the case.

    Members
    -------
    direction : In(B_d).array(M)
        Cycle t: the predecessor direction of each move; values above M read row M.
    code : Out(code_bits).array(M)
        Cycle t+1: ``codes[min(direction[m], M), m]``.
    write_addr : In(range((M+1)*M))
        Entry ``p * M + m`` to write; addresses >= (M+1)*M are ignored.
    write_data : In(code_bits)
        The new code.
    write_en : In(1)
        Write in this cycle (module docstring: the write protocol).
    """

    def __init__(self, cfg: DPConfig, codes, code_bits: int, max_code: int | None, *,
                 lut_style: str = "auto", write_decode: str = "case"):
        self._style = resolve_lut_style(cfg, lut_style)
        if write_decode not in WRITE_DECODES:
            self._MustUse__silence = True      # refused: never meant to be elaborated
            raise ValueError(f"write_decode must be one of {WRITE_DECODES}, got {write_decode!r}")
        self._predecoded = write_decode == "predecoded" and self._style == "logic"
        self._cfg = cfg
        self._codes = codes
        self._code_bits = code_bits
        self._max_code = max_code
        moves = cfg.n_moves
        super().__init__({
            "direction": In(cfg.direction_bits).array(moves),
            "code": Out(code_bits).array(moves),
            "write_addr": In(range(cfg.lut_entries)),
            "write_data": In(code_bits),
            "write_en": In(1),
        })

    @property
    def lut_style(self) -> str:
        """The resolved storage: ``"bram"`` or ``"logic"``."""
        return self._style

    @property
    def entries(self) -> int:
        """Number of codes in the table, ``(M + 1) * M``."""
        return self._cfg.lut_entries

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        moves = cfg.n_moves
        codes = self._codes

        # Register the write with its address split into (direction row, move column).
        write_row = Signal(range(moves + 1))
        write_move = Signal(range(moves))
        write_code = Signal(self._code_bits)
        write_pending = Signal()
        # No comparator where no write can exceed max_code (F = 0: max_code = 1 = all ones
        # of a 1-bit code): a constant comparison is what Verilator's CMPCONST refuses.
        top = self._max_code
        clamp = top is not None and top < (1 << self._code_bits) - 1
        m.d.sync += [
            write_code.eq(Mux(self.write_data > top, top, self.write_data) if clamp
                          else self.write_data),
            write_pending.eq(0),
        ]
        if self._predecoded:
            self._elaborate_predecoded(m, write_code)
            return m
        with m.If(self.write_en):
            with m.Switch(self.write_addr):
                for address in range(self.entries):
                    with m.Case(address):
                        m.d.sync += [
                            write_row.eq(address // moves),
                            write_move.eq(address % moves),
                            write_pending.eq(1),
                        ]
                with m.Default():  # address beyond the table: ignored
                    m.d.sync += [write_row.eq(0), write_move.eq(0), write_pending.eq(0)]

        if self._style == "logic":
            self._elaborate_registers(m, write_row, write_code)
            return m
        # Without an attribute synth_ice40 maps each column to an SB_RAM40_4K.
        for move in range(moves):
            memory = Memory(shape=unsigned(self._code_bits), depth=moves + 1,
                            init=[int(c) for c in codes[:, move]])
            m.submodules[f"column_{move}"] = memory
            read = memory.read_port(domain="sync")
            write = memory.write_port(domain="sync")
            m.d.comb += [
                read.addr.eq(self._read_row(move)),
                self.code[move].eq(read.data),
                write.addr.eq(write_row),
                write.data.eq(write_code),
                write.en.eq(write_pending & (write_move == move)),
            ]
        return m

    def _read_row(self, move: int):
        """The row move ``move`` reads: its predecessor's direction, ``M`` (``START``) above M."""
        direction = self.direction[move]
        moves = self._cfg.n_moves
        return Mux(_above(direction, moves), moves, direction)

    def _elaborate_registers(self, m: Module, write_row, write_code):
        """``lut_style="logic"``: flip-flops and a read multiplexer tree per column.

        Each column is a memory marked ``ram_style = "logic"`` (flip-flops after synthesis;
        its contents kept through a reset, and in Verilog its write an ``if (enable)`` in the
        clocked block, so an X enable in a 4-state simulator leaves the codes alone), read
        at every address by a constant-address port. The write is enabled by a one-hot move
        registered in the same cycle as the binary pair, so a code's clock enable is the
        column's enable and one row decode (the binary pair's 9-input decode was a critical
        path on ECP5, ``docs/synthesis.md``); the same write protocol and non-transparent
        synchronous reads as the block-RAM style.
        """
        moves = self._cfg.n_moves
        write_moves = Signal(moves)
        m.d.sync += write_moves.eq(0)
        with m.If(self.write_en):
            with m.Switch(self.write_addr):
                for address in range(self.entries):
                    with m.Case(address):
                        m.d.sync += write_moves.eq(1 << (address % moves))
                with m.Default():  # address beyond the table: ignored
                    m.d.sync += write_moves.eq(0)
        for move in range(moves):
            memory = Memory(shape=unsigned(self._code_bits), depth=moves + 1,
                            init=[int(c) for c in self._codes[:, move]],
                            attrs={"ram_style": "logic"})
            m.submodules[f"column_{move}"] = memory
            write = memory.write_port(domain="sync")
            m.d.comb += [write.addr.eq(write_row), write.data.eq(write_code),
                         write.en.eq(write_moves[move])]
            column = []
            for row in range(moves + 1):
                read = memory.read_port(domain="comb")
                m.d.comb += read.addr.eq(row)
                column.append(read.data)
            # Directions above M read row M: the rows are padded with row M up to 2**B_d,
            # so the read is a plain binary multiplexer tree on the direction's bits (no
            # clamp before it; `?:` in Verilog, evaluated from time 0 in a 4-state simulator,
            # where a `case` in an `always @*` stays X until its selector first changes).
            direction = self.direction[move]
            padded = column + [column[-1]] * ((1 << len(direction)) - len(column))
            m.d.sync += self.code[move].eq(_select(padded, direction))


    def _elaborate_predecoded(self, m: Module, write_code):
        """``write_decode="predecoded"``: the codes in flip-flops of their own, entry a
        (row a // M, move a % M) written when the registered one-hot bits of a's low and
        high address halves are both set (an address beyond the table sets no pair: it
        is ignored); read as :meth:`_elaborate_registers`'s. The same write protocol (the
        halves registered in cycle c, the code stored at the edge ending c + 1); a reset
        drops a pending write (the high half, with ``write_en``, has a reset value)."""
        moves = self._cfg.n_moves
        address = self.write_addr
        split = (len(address) + 1) // 2
        low = Signal(1 << split, name="write_low", reset_less=True)
        high = Signal(1 << (len(address) - split), name="write_high")
        for value in range(len(low)):
            m.d.sync += low[value].eq(address[:split] == value)
        for value in range(len(high)):
            m.d.sync += high[value].eq(self.write_en & (address[split:] == value))
        columns = [[] for _ in range(moves)]
        for entry in range(self.entries):
            row, move = divmod(entry, moves)
            code = Signal(self._code_bits, init=int(self._codes[row, move]), reset_less=True,
                          name=f"code_{row}_{move}")
            with m.If(high[entry >> split] & low[entry & ((1 << split) - 1)]):
                m.d.sync += code.eq(write_code)
            columns[move].append(code)
        for move, column in enumerate(columns):
            direction = self.direction[move]
            padded = column + [column[-1]] * ((1 << len(direction)) - len(column))
            m.d.sync += self.code[move].eq(_select(padded, direction))


class WeightLUT(DirectionTable):
    """M column memories of weight codes with a single table-wide write port.

    Parameters
    ----------
    cfg : DPConfig
        Number of moves M, direction width B_d, code width F+1 and the initial codes
        (``cfg.weight_codes``).
    lut_style : {"auto", "bram", "logic"}
        Storage of the column memories (module docstring, :func:`resolve_lut_style`);
        ``ValueError`` for anything else. Behaviour does not depend on it.
    write_decode : {"case", "predecoded"}
        As :class:`DirectionTable`'s; ``ValueError`` for anything else.

    Members
    -------
    direction : In(B_d).array(M)
        Cycle t: the predecessor direction of each move. Values above M (never produced by
        the pipeline from a state it wrote) read row M, the ``START`` row.
    code : Out(F+1).array(M)
        Cycle t+1: ``c[min(direction[m], M), m]``.
    write_addr : In(range((M+1)*M))
        Entry to write, ``cfg.lut_address(p, m)`` = ``p * M + m`` for predecessor direction p
        and move m. Addresses
        >= (M+1)*M are ignored.
    write_data : In(F+1)
        The new code. Codes above ``2**F`` (a weight above 1.0, outside
        ``docs/arithmetic.md`` §3) are stored as ``2**F``.
    write_en : In(1)
        Write in this cycle.
    """

    def __init__(self, cfg: DPConfig, *, lut_style: str = "auto", write_decode: str = "case"):
        super().__init__(cfg, cfg.weight_codes, cfg.weight_bits, 1 << cfg.weight_frac_bits,
                         lut_style=lut_style, write_decode=write_decode)
