"""Forgetting multiplier ``A = round_G(V * a)``: the recursive DP's fading, after the max tree.

``docs/arithmetic.md`` §8.4 (operator ``scale_by_forgetting``). The code a =
``DPConfig.forgetting_code`` (1 <= a < 2**G when the block is built) is a constant of the
configuration, so the multiplier is a constant shift-and-add: one leaf ``V << k`` per set
bit k of a (:func:`~dptbd.hw.family_blocks.forgetting_leaves`), plus the rounding constant
``2**(G-1)`` for ``half_up``, summed by a binary adder tree registered after every level
like :class:`~dptbd.hw.weighted_candidate.WeightedCandidate`'s. The sum is signed, so the
final ``>> G`` is an arithmetic shift: ``truncate`` floors (towards minus infinity for a
negative V) and ``half_up`` rounds half up, as the model does. Since a <= 2**G, A lies
between 0 and V: it fits V's shape.
"""

from __future__ import annotations

from amaranth.hdl import Const, Module, Shape, signed
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.adder_tree import registered_adder_tree
from dptbd.hw.family_blocks import forgetting_leaves
from dptbd.hw.schedule import PipelineSchedule

__all__ = ["ForgettingMultiplier"]


class ForgettingMultiplier(wiring.Component):
    """``scaled = shift_right_rounded(value * a, G, rounding)``, fully pipelined.

    Parameters
    ----------
    cfg : DPConfig
        a (``forgetting_code``), G (``forgetting_bits``) and the rounding mode.
    value_shape : amaranth.hdl.Shape
        Shape of V: ``unsigned(B_E)`` or ``signed(B_E + 1)`` (with a penalty LUT).

    Members
    -------
    value : In(value_shape)
        V_best.
    scaled : Out(value_shape)
        A, :attr:`latency` cycles after ``value``.

    A new operand is accepted every cycle.
    """

    def __init__(self, cfg: DPConfig, value_shape):
        self._cfg = cfg
        self._shape = Shape.cast(value_shape)
        super().__init__({"value": In(self._shape), "scaled": Out(self._shape)})

    @property
    def latency(self) -> int:
        """Register levels; :attr:`PipelineSchedule.forgetting_levels` (at least 1)."""
        return max(1, PipelineSchedule.from_config(self._cfg).forgetting_levels)

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        shift = cfg.forgetting_bits
        sum_shape = signed(self._shape.width + shift + 2)
        leaves = [Const(1 << (shift - 1), shift) if k < 0 else self.value << k
                  for k in forgetting_leaves(cfg)]

        root = registered_adder_tree(m, leaves, self.latency, sum_shape)
        m.d.comb += self.scaled.eq(root[shift:])
        return m
