"""Vectors, golden-model references and the Amaranth bench of the max/argmax trees, shared by
``test_max_tree.py`` and ``test_pipelined_max.py`` (Glasgow's pattern: ``cases()`` yields
the vectors, ``ref_max_tree`` is the golden model's answer, ``rtl_max_tree`` the gateware's,
one per vector).
"""

import random

import numpy as np

from dptbd.hw.max_tree import MaxTree
from dptbd.model.family.operators import INVALID_SIGNED
from dptbd.model.operators import INVALID, argmax_lowest_index
from helpers.hw_harness import simulate


def cases(count, value_bits):
    """(values, valid) vectors: extremes, many ties, the centre move always valid."""
    rng = random.Random(count)
    top = (1 << value_bits) - 1
    for n in range(200):
        values = [rng.choice([0, top, rng.randrange(top + 1), rng.randrange(3)])
                  for _ in range(count)]
        if n % 3 == 0:  # many ties
            values = [rng.randrange(2) * top for _ in range(count)]
        valid = [rng.random() < 0.7 for _ in range(count)]
        valid[rng.randrange(count)] = True  # the centre move is always valid
        yield values, valid
    yield [top] * count, [False] * (count - 1) + [True]   # only the last is valid
    yield [0] * count, [True] * count                     # all tie at 0


def ref_max_tree(values, valid) -> tuple[int, int, int]:
    """(valid, best, index) of the golden model."""
    best, index = argmax_lowest_index(np.where(valid, values, INVALID))
    return 1, int(best), int(index)


def signed_cases(count, value_bits):
    """Signed (values, valid) vectors (§8.4): both extremes, -1 / 0 ties, all negative."""
    rng = random.Random(count + 100)
    low, high = -(1 << (value_bits - 1)), (1 << (value_bits - 1)) - 1
    for n in range(200):
        values = [rng.choice([low, high, -1, 0, rng.randint(low, high)]) for _ in range(count)]
        if n % 3 == 0:  # ties across the sign boundary
            values = [rng.choice([-1, 0, low]) for _ in range(count)]
        if n % 5 == 0:  # every value negative
            values = [rng.randint(low, -1) for _ in range(count)]
        valid = [rng.random() < 0.7 for _ in range(count)]
        valid[rng.randrange(count)] = True
        yield values, valid
    yield [high] * count, [False] * (count - 1) + [True]   # only the last valid
    yield [low] * count, [True] * count                    # all tie at the minimum


def ref_signed_max_tree(values, valid) -> tuple[int, int, int]:
    """(valid, best, index) of the family's golden model (``INVALID_SIGNED`` never wins)."""
    best, index = argmax_lowest_index(np.where(valid, np.asarray(values, np.int64), INVALID_SIGNED))
    return 1, int(best), int(index)


def rtl_max_tree(count, value_bits, vectors, signed=False, tree=MaxTree) -> list[tuple[int, int, int]]:
    """One vector a cycle into ``tree`` (``MaxTree`` or a class with its ports and
    ``latency``); (valid, value, index) of each, ``latency`` later."""
    dut = tree(count, value_bits, signed=signed)
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
