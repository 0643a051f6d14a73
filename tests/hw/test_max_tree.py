"""Max/argmax tree against ``argmax_lowest_index``: ties to the lowest index, invalid never wins."""

import random

import numpy as np
import pytest
from amaranth.sim import Simulator

from dptbd.hw.max_tree import MaxTree, tree_levels
from dptbd.model.operators import INVALID, argmax_lowest_index


@pytest.mark.parametrize("count, value_bits", [(9, 6), (25, 4), (5, 3), (2, 8)])
def test_matches_argmax_lowest_index(count, value_bits):
    dut = MaxTree(count, value_bits)
    rng = random.Random(count)
    top = (1 << value_bits) - 1
    vectors = []
    for n in range(200):
        values = [rng.choice([0, top, rng.randrange(top + 1), rng.randrange(3)])
                  for _ in range(count)]
        if n % 3 == 0:  # many ties
            values = [rng.randrange(2) * top for _ in range(count)]
        valid = [rng.random() < 0.7 for _ in range(count)]
        valid[rng.randrange(count)] = True  # the centre move is always valid
        vectors.append((values, valid))
    vectors.append(([top] * count, [False] * (count - 1) + [True]))   # only the last is valid
    vectors.append(([0] * count, [True] * count))                     # all tie at 0

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

    sim = Simulator(dut)
    sim.add_clock(1e-8)
    sim.add_testbench(bench)
    sim.run()
    for n, (values, valid) in enumerate(vectors):
        candidates = np.where(valid, values, INVALID)
        best, index = argmax_lowest_index(candidates)
        assert got[n] == (1, best, index), f"vector {n}: {values} {valid}"


def test_latency_is_ceil_log2():
    assert [tree_levels(n) for n in (1, 2, 3, 4, 5, 9, 16, 17, 25)] == [0, 1, 2, 2, 3, 4, 4, 5, 5]
