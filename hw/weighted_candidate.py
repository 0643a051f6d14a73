"""Weighted candidate ``C = round(E * c / 2**F)``: a pipelined shift-and-add multiplier.

``docs/arithmetic.md`` §4.3 (operator ``scale_by_weight``). Small FPGAs such as the iCE40
have no multiplier blocks, so the B_E x (F+1) product is built from F+1 partial products
``c[k] ? E << k : 0`` summed by a binary adder tree registered after every level: each
stage is one carry chain deep. The rounding constant of ``half_up`` (``2**(F-1)``) is one
more leaf of the tree, so rounding costs no extra stage; ``truncate`` leaves it 0.

Because a code never exceeds ``2**F`` (the LUT clamps writes), ``E * c + 2**(F-1)``
fits in B_E + F bits and ``C <= E``.

A candidate whose predecessor is outside the image (``inside`` low) never wins in the max
tree (§4.4) and is never looked up: its code is forced to 0 and ``C`` is exactly 0
(``docs/arithmetic.md`` §4.2). The partial products are ``E << k`` AND a code bit, so
whatever the predecessor's cell holds (the state store's power-up contents, X in a
4-state simulator) does not reach ``weighted``.
"""

from __future__ import annotations

from amaranth.hdl import Const, Module, Mux, Signal, unsigned
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.adder_tree import registered_adder_tree
from dptbd.hw.schedule import PipelineSchedule

__all__ = ["WeightedCandidate"]


class WeightedCandidate(wiring.Component):
    """``weighted = shift_right_rounded(energy * code, F, rounding)``, fully pipelined.

    Parameters
    ----------
    cfg : DPConfig
        B_E, F and the rounding mode.

    Members
    -------
    energy : In(B_E)
        The predecessor's E.
    code : In(F+1)
        Its weight code c, at most ``2**F``.
    inside : In(1)
        The predecessor is inside the image. When 0 the code is taken as 0, so ``weighted``
        is 0 whatever ``energy`` and ``code`` are.
    weighted : Out(B_E)
        C, :attr:`latency` cycles after ``energy``, ``code`` and ``inside``.

    A new operand set is accepted every cycle.
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "energy": In(cfg.energy_bits),
            "code": In(cfg.weight_bits),
            "inside": In(1),
            "weighted": Out(cfg.energy_bits),
        })

    @property
    def latency(self) -> int:
        """Register levels from operands to ``weighted``; see :class:`PipelineSchedule`."""
        return PipelineSchedule.from_config(self._cfg).multiplier_levels

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        frac = cfg.weight_frac_bits
        product_bits = cfg.energy_bits + frac

        code = Signal(cfg.weight_bits)
        m.d.comb += code.eq(Mux(self.inside, self.code, 0))  # outside the image: weight 0
        leaves = [
            (self.energy << k) & code[k].replicate(cfg.energy_bits + k)
            for k in range(cfg.weight_bits)
        ]
        if frac >= 1:
            rounding = (1 << (frac - 1)) if cfg.rounding == "half_up" else 0
            leaves.append(Const(rounding, frac))

        root = registered_adder_tree(m, leaves, self.latency, unsigned(product_bits))
        m.d.comb += self.weighted.eq(root[frac:])
        return m
