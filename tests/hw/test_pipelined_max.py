"""SplitMaxTree against ``argmax_lowest_index`` (the vectors and the reference of
``test_max_tree.py``): the same answers as MaxTree, two cycles per level."""

import pytest

from dptbd.hw.max_tree import tree_levels
from dptbd.hw.pipelined_max import SplitMaxTree
from hw_harness import refused, simulate
from test_max_tree import cases, ref_max_tree


def rtl_split_max_tree(count, value_bits, vectors) -> list[tuple[int, int, int]]:
    """One vector a cycle into the tree; (valid, value, index) of each, ``latency`` later."""
    dut = SplitMaxTree(count, value_bits)
    got = []

    async def bench(ctx):
        for cycle in range(len(vectors) + dut.latency):
            if cycle < len(vectors):
                values, valid = vectors[cycle]
                for index, value in enumerate(values):
                    ctx.set(dut.values[index], value)
                ctx.set(dut.valid, sum(1 << i for i, v in enumerate(valid) if v))
            await ctx.tick()
            if cycle + 1 >= dut.latency:
                best = ctx.get(dut.best)
                got.append((best.valid, best.value, best.index))

    simulate(dut, bench)
    return got[:len(vectors)]


@pytest.mark.parametrize("count, value_bits", [(9, 6), (25, 4), (5, 3), (2, 8)])
def test_matches_argmax_lowest_index(count, value_bits):
    vectors = list(cases(count, value_bits))
    assert rtl_split_max_tree(count, value_bits, vectors) == [ref_max_tree(*v) for v in vectors]


def test_latency_is_two_stages_per_level():
    assert [SplitMaxTree(n, 4).latency for n in (1, 2, 3, 9, 25)] == \
        [2 * tree_levels(n) for n in (1, 2, 3, 9, 25)] == [0, 2, 4, 8, 10]


def test_refuses_no_candidates():
    with refused(ValueError, match=r"^count must be an integer in \[1, inf\), got 0$"):
        SplitMaxTree(0, 4)
