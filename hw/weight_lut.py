"""The weight LUT: (M+1) x M weight codes, M lookups per clock, writable at run time.

Candidate m needs code ``c[d(q_m), m]`` where ``d(q_m)`` is the direction of its own
predecessor. Each move reads only its own column of the table, so the table is split into
M column memories (one per move, M+1 entries each, indexed by the predecessor's direction):
M lookups per clock, each entry stored once, no replication.

Write protocol: a write presented in cycle c (``write_en`` high at the edge ending it) is
registered, then stored at the edge ending cycle c+1. Reads are synchronous and
non-transparent, so a lookup issued in cycle c+2 or later sees it and one issued earlier
does not. The pipeline issues a pixel's lookups in cycle 2 after its acceptance, so every
pixel accepted in cycle c or later uses the new code and every pixel accepted before
cycle c the old one.
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal, unsigned
from amaranth.lib import wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig

__all__ = ["WeightLUT"]


class WeightLUT(wiring.Component):
    """M column memories of weight codes with a single table-wide write port.

    Parameters
    ----------
    cfg : DPConfig
        Number of moves M, direction width B_d, code width F+1 and the initial codes
        (``cfg.weight_codes``).

    Members
    -------
    direction : In(B_d).array(M)
        Cycle t: the predecessor direction of each move. Values above M (never produced by
        the pipeline from a state it wrote) read an unspecified code.
    code : Out(F+1).array(M)
        Cycle t+1: ``c[direction[m], m]``.
    write_addr : In(range((M+1)*M))
        Entry to write, ``p * M + m`` for predecessor direction p and move m. Addresses
        >= (M+1)*M are ignored.
    write_data : In(F+1)
        The new code. Codes above ``2**F`` (a weight above 1.0, outside
        ``docs/arithmetic.md`` §3) are stored as ``2**F``.
    write_en : In(1)
        Write in this cycle.
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        moves = cfg.n_moves
        super().__init__({
            "direction": In(cfg.direction_bits).array(moves),
            "code": Out(cfg.weight_bits).array(moves),
            "write_addr": In(range((moves + 1) * moves)),
            "write_data": In(cfg.weight_bits),
            "write_en": In(1),
        })

    @property
    def entries(self) -> int:
        """Number of codes in the table, ``(M + 1) * M``."""
        return (self._cfg.n_moves + 1) * self._cfg.n_moves

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        moves = cfg.n_moves
        unity = 1 << cfg.weight_frac_bits
        codes = cfg.weight_codes

        # Register the write with its address split into (direction row, move column).
        write_row = Signal(range(moves + 1))
        write_move = Signal(range(moves))
        write_code = Signal(cfg.weight_bits)
        write_pending = Signal()
        m.d.sync += [
            write_code.eq(Mux(self.write_data > unity, unity, self.write_data)),
            write_pending.eq(0),
        ]
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

        for move in range(moves):
            memory = Memory(shape=unsigned(cfg.weight_bits), depth=moves + 1,
                            init=[int(c) for c in codes[:, move]])
            m.submodules[f"column_{move}"] = memory
            read = memory.read_port(domain="sync")
            write = memory.write_port(domain="sync")
            m.d.comb += [
                read.addr.eq(self.direction[move]),
                self.code[move].eq(read.data),
                write.addr.eq(write_row),
                write.data.eq(write_code),
                write.en.eq(write_pending & (write_move == move)),
            ]
        return m
