"""Binary adder trees: registered after every level (the multipliers' sum), or in one cycle."""

from __future__ import annotations

from amaranth.hdl import Module, Signal

__all__ = ["registered_adder_tree", "adder_tree"]


def registered_adder_tree(m: Module, leaves: list, levels: int, shape):
    """Sum ``leaves`` pairwise, one register level at a time, ``levels`` levels deep.

    Level n adds neighbouring pairs (an odd last node passes through) into reset-less
    registers ``sum_l{n}_{i}`` of ``shape``; ``levels`` must reduce the leaves to one
    (``ceil(log2(len(leaves)))`` or more). Returns the root register.
    """
    nodes = leaves
    for level in range(1, levels + 1):
        merged = []
        for index in range(0, len(nodes), 2):
            total = nodes[index] if index + 1 == len(nodes) else nodes[index] + nodes[index + 1]
            register = Signal(shape, name=f"sum_l{level}_{index // 2}", reset_less=True)
            m.d.sync += register.eq(total)
            merged.append(register)
        nodes = merged
    assert len(nodes) == 1
    return nodes[0]


def adder_tree(leaves: list):
    """The sum of ``leaves`` as a balanced tree of adders in one cycle, neighbouring pairs
    first (an odd last node passes through): at 4 leaves two adders deep, not the three in
    series of Python's ``sum``."""
    nodes = leaves
    while len(nodes) > 1:
        nodes = [nodes[i] if i + 1 == len(nodes) else nodes[i] + nodes[i + 1]
                 for i in range(0, len(nodes), 2)]
    return nodes[0]
