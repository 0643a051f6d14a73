"""``adder_tree``: the sum of its leaves, neighbouring pairs first, as few adders deep as a
binary tree allows (``BankedHistogram``'s merge of its banks)."""

import random

import pytest
from amaranth.hdl import Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out
from amaranth.sim import Simulator

from dptbd.hw.adder_tree import adder_tree


class _Node:
    """A term that records its value and how many adders lie in series above its leaves."""

    def __init__(self, value, depth=0, text=None):
        self.value, self.depth, self.text = value, depth, text or str(value)

    def __add__(self, other):
        return _Node(self.value + other.value, max(self.depth, other.depth) + 1,
                     f"({self.text} + {other.text})")


@pytest.mark.parametrize("count, depth, text", [
    (1, 0, "1"),
    (2, 1, "(1 + 2)"),
    (3, 2, "((1 + 2) + 3)"),
    (4, 2, "((1 + 2) + (3 + 4))"),
    (5, 3, "(((1 + 2) + (3 + 4)) + 5)"),
])
def test_the_tree_sums_neighbouring_pairs_first(count, depth, text):
    root = adder_tree([_Node(v) for v in range(1, count + 1)])
    assert (root.value, root.depth, root.text) == (count * (count + 1) // 2, depth, text)


@pytest.mark.parametrize("count", [2, 3, 4])
def test_carries_are_added_inside_the_adders(count):
    """Every carry in is added once: the sum of leaves and carries, for leaves and carries
    at random (exhaustive over the carries), as a circuit of 4-bit leaves."""
    adders = count - 1

    class Tree(wiring.Component):
        leaves: In(4).array(count)
        carries: In(adders)
        total: Out(8)

        def elaborate(self, platform):
            m = Module()
            m.d.comb += self.total.eq(adder_tree(list(self.leaves),
                                                 carries=tuple(self.carries)))
            return m

    dut = Tree()
    rng = random.Random(count)
    got, want = [], []

    async def bench(ctx):
        for bits in range(1 << adders):
            for _ in range(8):
                values = [rng.randrange(16) for _ in range(count)]
                for port, value in zip(dut.leaves, values):
                    ctx.set(port, value)
                ctx.set(dut.carries, bits)
                got.append(ctx.get(dut.total))
                want.append(sum(values) + bin(bits).count("1"))

    sim = Simulator(dut)
    sim.add_testbench(bench)
    sim.run()
    assert got == want and len(got) == 8 << adders
