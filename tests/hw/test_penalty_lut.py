"""Penalty LUT against ``lookup_penalty_code`` (§8.2): the weight LUT's storage with the
penalty codes, a direction above M reading the START row, every B_Q-bit code written as is.

Glasgow's pattern: ``cases()`` yields one (directions, write) per cycle, ``ref_penalty_lut``
is the golden model's answer under the write rule (seen by lookups issued 2 cycles after
the write), ``rtl_penalty_lut`` the gateware's.
"""

import random

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.penalty_lut import PenaltyLUT
from dptbd.model.family.operators import lookup_penalty_code
from helpers.hw_harness import simulate


def cases(cfg, n=120):
    rng = random.Random(cfg.radius)
    moves, top = cfg.n_moves, (1 << cfg.penalty_width) - 1
    for _ in range(n):
        directions = [rng.randrange(1 << cfg.direction_bits) for _ in range(moves)]
        write = ((rng.randrange(cfg.lut_entries), rng.randrange(top + 1))
                 if rng.random() < 0.4 else None)
        yield directions, write


def ref_penalty_lut(cfg, vectors) -> list[list[int]]:
    table = cfg.penalty_code_array.copy()
    out = []
    for cycle, (directions, _) in enumerate(vectors):
        if cycle >= 2 and vectors[cycle - 2][1] is not None:
            address, code = vectors[cycle - 2][1]
            table[divmod(address, cfg.n_moves)] = code
        out.append([int(lookup_penalty_code(table, np.int64(d), m))
                    for m, d in enumerate(directions)])
    return out


def rtl_penalty_lut(cfg, vectors, style) -> list[list[int]]:
    dut = PenaltyLUT(cfg, lut_style=style)
    got = []

    async def bench(ctx):
        for directions, write in vectors:
            for move, d in enumerate(directions):
                ctx.set(dut.direction[move], d)
            ctx.set(dut.write_en, write is not None)
            if write is not None:
                ctx.set(dut.write_addr, write[0])
                ctx.set(dut.write_data, write[1])
            await ctx.tick()
            got.append([ctx.get(dut.code[m]) for m in range(cfg.n_moves)])

    simulate(dut, bench)
    return got


@pytest.mark.parametrize("radius, style", [(1, "logic"), (2, "bram")])
def test_matches_lookup_penalty_code_with_writes(radius, style):
    moves = (2 * radius + 1) ** 2
    codes = np.random.default_rng(radius).integers(0, 32, size=(moves + 1, moves))
    cfg = DPConfig(radius=radius, segment_frames=1, penalty_codes=codes, penalty_bits=5)
    vectors = list(cases(cfg))
    want = ref_penalty_lut(cfg, vectors)
    assert rtl_penalty_lut(cfg, vectors, style) == want
    assert any(max(row) == 31 for row in want)
