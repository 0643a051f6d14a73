"""Saturating accumulator: the new state (E, d) of one pixel.

``docs/arithmetic.md`` §4.5 and §5 (operator ``add_saturating``):

* inside a segment, ``E = min(E_best + x, E_max)`` formed at B_E + 1 bits, never wrapping,
  and d = the winning move;
* in a segment's first frame, ``E = x`` and ``d = START`` (= M); the previous state and
  the max tree's result are ignored.

:class:`ClampedAccumulator` is paper 000's family's (§8.5): ``clamp(A + P, 0, E_max)``.
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal, signed
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig

__all__ = ["Accumulator", "ClampedAccumulator"]


def _members(cfg: DPConfig, best_shape, addend: str, addend_shape) -> dict:
    """The members of both accumulators, in port order: ``best``, ``move``, the ``addend``
    (x or P), ``segment_start``; out ``energy``, ``direction``, ``saturated``."""
    return {
        "best": In(best_shape),
        "move": In(cfg.direction_bits),
        addend: In(addend_shape),
        "segment_start": In(1),
        "energy": Out(cfg.energy_bits),
        "direction": Out(cfg.direction_bits),
        "saturated": Out(1),
    }


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
        super().__init__(_members(cfg, cfg.energy_bits, "pixel", cfg.input_bits))

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        # The sum is formed from the registers directly and a start frame's E = x
        # (B_in <= B_E, so x never saturates) is selected after it: no gate between the
        # max tree's register and the carry chain (ECP5 timing, docs/synthesis.md).
        total = Signal(cfg.energy_bits + 1)
        m.d.comb += total.eq(self.best + self.pixel)
        saturated = total[cfg.energy_bits] & ~self.segment_start
        m.d.sync += [
            # per bit: start frame ? x : sum | carry (E_max is all ones), one LUT4
            self.energy.eq(Mux(self.segment_start, self.pixel,
                               total[:cfg.energy_bits]
                               | total[cfg.energy_bits].replicate(cfg.energy_bits))),
            self.direction.eq(Mux(self.segment_start, cfg.start_code, self.move)),
            self.saturated.eq(saturated),
        ]
        return m


class ClampedAccumulator(wiring.Component):
    """Paper 000's family (``docs/arithmetic.md`` §8.5, operator ``add_clamped``): one
    registered stage, ``E = clamp(A + P, 0, E_max)``.

    The sum is formed signed at ``DPConfig.accumulator_sum_bits`` (B_E + 2) bits and
    clamped at both ends, never wrapping; in a segment's (or the recursion's) first frame
    ``E = clamp(P, 0, E_max)`` and d = ``START`` (§8.6). Built instead of
    :class:`Accumulator` when a §8 field is in use
    (:class:`~dptbd.hw.family_blocks.FamilyBlocks`).

    Parameters
    ----------
    cfg : DPConfig
        B_E, B_P, B_d and M.
    value_shape : amaranth.hdl.Shape
        Shape of A: ``unsigned(B_E)``, or ``signed(B_E + 1)`` with a penalty LUT.

    Members
    -------
    best : In(value_shape)
        A, the (faded) best candidate.
    move : In(B_d)
        Its move index.
    merit : In(signed(B_P))
        The pixel's merit P.
    segment_start : In(1)
        The pixel belongs to a start frame: A and ``move`` are ignored.
    energy, direction : Out(B_E), Out(B_d)
        Next cycle: the new E and d.
    saturated : Out(1)
        Next cycle: the sum exceeded E_max and E was clipped to it (the ``saturated``
        event; a clamp at 0 is not an event).
    """

    def __init__(self, cfg: DPConfig, value_shape):
        self._cfg = cfg
        super().__init__(_members(cfg, value_shape, "merit", signed(cfg.merit_width)))

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        total = Signal(signed(cfg.accumulator_sum_bits))
        m.d.comb += total.eq(Mux(self.segment_start, 0, self.best) + self.merit)
        negative = total < 0
        saturated = total > cfg.e_max
        m.d.sync += [
            self.energy.eq(Mux(negative, 0, Mux(saturated, cfg.e_max, total[:cfg.energy_bits]))),
            self.direction.eq(Mux(self.segment_start, cfg.start_code, self.move)),
            self.saturated.eq(saturated),
        ]
        return m
