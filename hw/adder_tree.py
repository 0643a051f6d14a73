"""Binary adder trees: registered after every level (the multipliers' sum), or in one cycle."""

from __future__ import annotations

from amaranth.hdl import Cat, Module, Signal

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


def adder_tree(leaves: list, carries: tuple = ()):
    """The sum of ``leaves`` as a balanced tree of adders in one cycle, neighbouring pairs
    first (an odd last node passes through): at 4 leaves two adders deep, not the three in
    series of Python's ``sum``.

    ``carries``, 1-bit values, one per adder at most (``len(leaves) - 1``), are added as
    the adders' carries in, in the order the adders are formed: ``a + b + c`` as
    ``(2a + c) + (2b + c)`` halved, inside the adder's own carry chain (no adder more).
    """
    assert len(carries) < len(leaves)
    nodes, carries = leaves, list(carries)
    while len(nodes) > 1:
        merged = []
        for i in range(0, len(nodes), 2):
            if i + 1 == len(nodes):
                merged.append(nodes[i])
            elif carries:
                c = carries.pop(0)
                merged.append((Cat(c, nodes[i]) + Cat(c, nodes[i + 1]))[1:])
            else:
                merged.append(nodes[i] + nodes[i + 1])
        nodes = merged
    return nodes[0]
