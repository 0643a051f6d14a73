"""Max/argmax tree over the M weighted candidates, lowest index winning ties.

``docs/arithmetic.md`` §4.4 (operator ``argmax_lowest_index``). A binary tree of
compare-and-select nodes over the candidates in index order, registered after every level.
A node keeps its left (lower-index) input unless the right one is valid and either strictly
greater or the left one is invalid; the node compares ``(valid, value)`` as one unsigned
number with ``valid`` on top, which is that rule in one carry chain. Since every left subtree holds only lower indices than
its right sibling, the root is the lowest index attaining the maximum over the valid
candidates. On an odd level the last node passes through a register unchanged.

With ``signed=True`` (paper 000's penalised candidates, ``docs/arithmetic.md`` §8.4) the
values are two's complement: the node inverts each value's sign bit before the same
unsigned comparison (offset binary orders like the signed values), so the rule, the
valid flag on top and the single carry chain are unchanged.
"""

from __future__ import annotations

from amaranth.hdl import Cat, Module, Mux, Signal, signed as signed_shape, unsigned
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

__all__ = ["candidate_layout", "tree_levels", "MaxTree"]


def candidate_layout(value_bits: int, index_bits: int, signed: bool = False) -> data.StructLayout:
    """A candidate in the tree: ``valid``, ``value`` (two's complement if ``signed``) and
    its ``index``."""
    return data.StructLayout({
        "valid": unsigned(1),
        "value": signed_shape(value_bits) if signed else unsigned(value_bits),
        "index": unsigned(index_bits),
    })


def _order_key(value, signed: bool):
    """The bits of ``value`` as an unsigned number that orders like ``value``: the sign bit
    inverted when ``signed`` (offset binary), the bits themselves otherwise."""
    if not signed:
        return value
    return Cat(value[:-1], ~value[-1])


def tree_levels(count: int) -> int:
    """Register levels of a tree over ``count`` candidates: ``ceil(log2(count))``."""
    return (count - 1).bit_length()


class MaxTree(wiring.Component):
    """Pipelined max/argmax of ``count`` candidates.

    Parameters
    ----------
    count : int
        Number of candidates (M), >= 1.
    value_bits : int
        Width of a candidate value (B_E; B_E + 1 when signed).
    signed : bool
        The values are two's complement (``docs/arithmetic.md`` §8.4); default unsigned.

    Members
    -------
    valid : In(count)
        Bit m: candidate m takes part. Invalid candidates never win against a valid one.
    values : In(value_bits).array(count)
        Candidate values (``signed(value_bits)`` when ``signed``).
    best : Out(candidate_layout(value_bits, index_bits, signed))
        :attr:`latency` cycles later: the winner. ``best.valid`` is 0 only if no candidate
        was valid (then ``value`` and ``index`` are those of candidate 0).
    """

    def __init__(self, count: int, value_bits: int, *, signed: bool = False):
        if count < 1:
            raise ValueError(f"count must be an integer in [1, inf), got {count}")
        self._count = count
        self._value_bits = value_bits
        self._signed = bool(signed)
        self._index_bits = max(1, (count - 1).bit_length())
        value_shape = signed_shape(value_bits) if self._signed else unsigned(value_bits)
        super().__init__({
            "valid": In(count),
            "values": In(value_shape).array(count),
            "best": Out(candidate_layout(value_bits, self._index_bits, self._signed)),
        })

    @property
    def latency(self) -> int:
        """Register levels, ``ceil(log2(count))`` (0 for a single candidate)."""
        return tree_levels(self._count)

    def _leaves(self, m: Module) -> list:
        """The ``count`` leaf candidates (``valid``, ``value``, ``index``), in index order."""
        layout = candidate_layout(self._value_bits, self._index_bits, self._signed)
        nodes = []
        for index in range(self._count):
            leaf = Signal(layout, name=f"leaf_{index}")
            m.d.comb += [
                leaf.valid.eq(self.valid[index]),
                leaf.value.eq(self.values[index]),
                leaf.index.eq(index),
            ]
            nodes.append(leaf)
        return nodes

    def _take_right(self, left, right):
        """A node's rule: right.valid & (~left.valid | right.value > left.value), as one
        comparison with ``valid`` as the most significant bit: one carry chain. (When both
        are invalid either may pass; the result stays invalid.)"""
        # right > left as the borrow (sign bit) of left - right: Yosys maps the subtraction
        # to one carry chain whose last stage is the result, where a `>` comparison was
        # mapped with LUT levels after the chain on ECP5 (docs/synthesis.md).
        difference = (Cat(_order_key(left.value, self._signed), left.valid)
                      - Cat(_order_key(right.value, self._signed), right.valid))
        return difference[-1]

    def _pass(self, m: Module, layout, name: str, node):
        """A level's odd last node, passed on through one register per stage."""
        out = Signal(layout, name=f"node_{name}", reset_less=True)
        m.d.sync += out.eq(node)
        return out

    def _node(self, m: Module, layout, name: str, left, right):
        """One compare-and-select node, registered once."""
        out = Signal(layout, name=f"node_{name}", reset_less=True)
        m.d.sync += out.eq(Mux(self._take_right(left, right), right, left))
        return out

    def elaborate(self, platform):
        m = Module()
        layout = candidate_layout(self._value_bits, self._index_bits, self._signed)
        nodes = self._leaves(m)
        level = 0
        while len(nodes) > 1:
            level += 1
            nodes = [self._pass(m, layout, f"l{level}_{pair // 2}", nodes[pair])
                     if pair + 1 == len(nodes) else
                     self._node(m, layout, f"l{level}_{pair // 2}", nodes[pair], nodes[pair + 1])
                     for pair in range(0, len(nodes), 2)]
        m.d.comb += self.best.eq(nodes[0])
        return m
