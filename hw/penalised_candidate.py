"""Penalised candidate ``V = C - Qc``: paper 000's additive transition term after the weight.

``docs/arithmetic.md`` §8.3 (operator ``subtract_penalty``): one registered subtractor per
move, between the weight multiplier and the (signed) max tree. V is exact in B_E + 1 bits
signed (``DPConfig.candidate_value_bits``): ``-(2**B_Q - 1) <= V <= E_max``; nothing
saturates.

A candidate whose predecessor is outside the image (``inside`` low) takes penalty 0, so
what the penalty LUT read for the cell's direction (power-up garbage, X in a 4-state
simulator) never reaches the max tree; the tree's valid flag keeps it from winning.
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, signed
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig

__all__ = ["PenalisedCandidate"]


class PenalisedCandidate(wiring.Component):
    """``value = weighted - penalty``, one register stage.

    Parameters
    ----------
    cfg : DPConfig
        B_E, B_Q.

    Members
    -------
    weighted : In(B_E)
        C, the weighted candidate.
    penalty : In(B_Q)
        Qc, its penalty code.
    inside : In(1)
        The predecessor is inside the image; when 0 the penalty is taken as 0.
    value : Out(signed(B_E + 1))
        Next cycle: V = C - Qc.
    """

    #: Register levels from operands to ``value``.
    latency = 1

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "weighted": In(cfg.energy_bits),
            "penalty": In(cfg.penalty_width),
            "inside": In(1),
            "value": Out(signed(cfg.candidate_value_bits)),
        })

    def elaborate(self, platform):
        m = Module()
        m.d.sync += self.value.eq(self.weighted - Mux(self.inside, self.penalty, 0))
        return m
