"""Saturating accumulator: the new state (E, d) of one pixel.

``docs/arithmetic.md`` §4.5 and §5 (operator ``add_saturating``):

* inside a segment, ``E = min(E_best + x, E_max)`` formed at B_E + 1 bits, never wrapping,
  and d = the winning move;
* in a segment's first frame, ``E = x`` and ``d = START`` (= M); the previous state and
  the max tree's result are ignored.
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig

__all__ = ["Accumulator"]


class Accumulator(wiring.Component):
    """One registered stage: saturating add of the pixel to the best candidate.

    Parameters
    ----------
    cfg : DPConfig
        B_in, B_E, B_d and M.

    Members
    -------
    best : In(B_E)
        ``E_best``, the winning weighted candidate.
    move : In(B_d)
        Its move index.
    pixel : In(B_in)
        The pixel x.
    segment_start : In(1)
        The pixel belongs to a segment's first frame.
    energy : Out(B_E)
        Next cycle: the new E.
    direction : Out(B_d)
        Next cycle: the new d.
    saturated : Out(1)
        Next cycle: the sum exceeded E_max and E was clipped to it (the ``saturated`` event).
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "best": In(cfg.energy_bits),
            "move": In(cfg.direction_bits),
            "pixel": In(cfg.input_bits),
            "segment_start": In(1),
            "energy": Out(cfg.energy_bits),
            "direction": Out(cfg.direction_bits),
            "saturated": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        addend = Mux(self.segment_start, 0, self.best)
        total = Signal(cfg.energy_bits + 1)
        m.d.comb += total.eq(addend + self.pixel)
        saturated = total[cfg.energy_bits]
        m.d.sync += [
            self.energy.eq(Mux(saturated, cfg.e_max, total[:cfg.energy_bits])),
            self.direction.eq(Mux(self.segment_start, cfg.start_code, self.move)),
            self.saturated.eq(saturated),
        ]
        return m
