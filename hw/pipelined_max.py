"""Max/argmax tree with each level's compare and select in two register stages.

The same function as :class:`~dptbd.hw.max_tree.MaxTree` (``docs/arithmetic.md`` §4.4,
``argmax_lowest_index``: the lowest index attaining the maximum over the valid candidates),
the same tree shape and the same node rule, but every level takes two cycles: the first
registers the comparison ``take_right`` of each pair beside the pair itself, the second
registers the selected candidate. A level is then one carry chain *or* one multiplexer
between registers instead of both, which is the DP core's critical path on ECP5 once the
line buffer's block RAM is gone (``docs/synthesis.md``, "Block RAM reads").
Latency ``2 * ceil(log2(count))``; :class:`~dptbd.hw.dp_core.DPCore` builds it with
``max_tree="split"`` and :class:`~dptbd.hw.schedule.PipelineSchedule` counts it.
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal

from dptbd.hw.max_tree import MaxTree, tree_levels

__all__ = ["SplitMaxTree"]


class SplitMaxTree(MaxTree):
    """Pipelined max/argmax of ``count`` candidates, two register stages per level.

    Parameters and members as :class:`~dptbd.hw.max_tree.MaxTree`; ``best`` comes
    :attr:`latency` = ``2 * ceil(log2(count))`` cycles after the candidates.
    """

    @property
    def latency(self) -> int:
        """Register stages, ``2 * ceil(log2(count))`` (0 for a single candidate)."""
        return 2 * tree_levels(self._count)

    def _pass(self, m: Module, layout, name: str, node):
        held = Signal(layout, name=f"held_{name}", reset_less=True)
        out = Signal(layout, name=f"node_{name}", reset_less=True)
        m.d.sync += [held.eq(node), out.eq(held)]
        return out

    def _node(self, m: Module, layout, name: str, left, right):
        # Stage 1: the comparison of MaxTree's node and both inputs, registered.
        # Stage 2: the select.
        left_q = Signal(layout, name=f"left_{name}", reset_less=True)
        right_q = Signal(layout, name=f"right_{name}", reset_less=True)
        take_right = Signal(name=f"take_right_{name}", reset_less=True)
        out = Signal(layout, name=f"node_{name}", reset_less=True)
        m.d.sync += [
            left_q.eq(left), right_q.eq(right),
            take_right.eq(self._take_right(left, right)),
            out.eq(Mux(take_right, right_q, left_q)),
        ]
        return out
