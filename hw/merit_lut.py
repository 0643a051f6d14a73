"""The merit LUT: paper 000's per-pixel merit P = merit[x] on the input pixel.

``docs/arithmetic.md`` §8.1 (operator ``lookup_merit_code``): a 2^B_in-entry table of
signed B_P-bit codes (``DPConfig.merit_width``), initialised from ``cfg.merit_codes``,
one synchronous lookup per clock, writable at run time.

Write protocol, the weight LUT's (:mod:`dptbd.hw.weight_lut`): a write presented in cycle
c (``write_en`` high at the edge ending it) is registered, then stored at the edge ending
cycle c+1. Reads are synchronous and non-transparent, so a lookup issued in cycle c+2 or
later sees it and one issued earlier does not. The pipeline issues a pixel's lookup in
cycle 2 after its acceptance (the window stage, like the weight lookups), so every pixel
accepted in cycle c or later uses the new code and every pixel accepted before cycle c
the old one. Addresses are pixel codes: the whole address range is the table.
"""

from __future__ import annotations

from amaranth.hdl import Module, Signal, signed
from amaranth.lib import wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig

__all__ = ["MeritLUT"]


class MeritLUT(wiring.Component):
    """2^B_in signed merit codes, one lookup per clock, one write port.

    Parameters
    ----------
    cfg : DPConfig
        B_in, B_P and the initial codes (``cfg.merit_code_array``).

    Members
    -------
    pixel : In(B_in)
        Cycle t: the pixel code to look up.
    merit : Out(signed(B_P))
        Cycle t+1: ``merit[pixel]``.
    write_addr : In(B_in)
        The pixel code whose merit to write.
    write_data : In(signed(B_P))
        The new merit code.
    write_en : In(1)
        Write in this cycle.
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "pixel": In(cfg.input_bits),
            "merit": Out(signed(cfg.merit_width)),
            "write_addr": In(cfg.input_bits),
            "write_data": In(signed(cfg.merit_width)),
            "write_en": In(1),
        })

    @property
    def entries(self) -> int:
        """Number of codes in the table, ``2**B_in``."""
        return 1 << self._cfg.input_bits

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        write_addr = Signal(cfg.input_bits)
        write_data = Signal(signed(cfg.merit_width))
        write_pending = Signal()
        m.d.sync += [
            write_addr.eq(self.write_addr),
            write_data.eq(self.write_data),
            write_pending.eq(self.write_en),
        ]
        m.submodules.table = table = Memory(
            shape=signed(cfg.merit_width), depth=self.entries,
            init=[int(c) for c in cfg.merit_code_array])
        read = table.read_port(domain="sync")
        write = table.write_port(domain="sync")
        m.d.comb += [
            read.addr.eq(self.pixel),
            self.merit.eq(read.data),
            write.addr.eq(write_addr),
            write.data.eq(write_data),
            write.en.eq(write_pending),
        ]
        return m
