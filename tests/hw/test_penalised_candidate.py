"""Penalised candidate V = C - Qc against ``subtract_penalty`` (§8.3); outside the image
the penalty is 0.

Glasgow's pattern: ``cases()`` yields the operands, ``ref_penalised`` is the golden model's
answer, ``rtl_penalised`` the gateware's, one per operand.
"""

import random

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.penalised_candidate import PenalisedCandidate
from dptbd.model.family.operators import subtract_penalty
from helpers.hw_harness import simulate


def cases(cfg):
    """(C, Qc, inside): the extremes of both, then random."""
    rng = random.Random(cfg.energy_bits)
    q_max = (1 << cfg.penalty_width) - 1
    yield from [(0, q_max, 1), (cfg.e_max, 0, 1), (cfg.e_max, q_max, 1), (0, 0, 1),
                (0, q_max, 0), (cfg.e_max, q_max, 0)]
    for _ in range(100):
        yield rng.randrange(cfg.e_max + 1), rng.randrange(q_max + 1), int(rng.random() < 0.8)


def ref_penalised(weighted, penalty, inside) -> int:
    return int(subtract_penalty(np.int64(weighted), np.int64(penalty if inside else 0)))


def rtl_penalised(cfg, operands) -> list[int]:
    dut = PenalisedCandidate(cfg)
    got = []

    async def bench(ctx):
        for weighted, penalty, inside in operands:
            ctx.set(dut.weighted, weighted)
            ctx.set(dut.penalty, penalty)
            ctx.set(dut.inside, inside)
            await ctx.tick()
            got.append(ctx.get(dut.value))

    simulate(dut, bench)
    return got


@pytest.mark.parametrize("energy_bits, penalty_bits", [(8, 8), (12, 5), (6, 1)])
def test_matches_subtract_penalty(energy_bits, penalty_bits):
    cfg = DPConfig(input_bits=min(8, energy_bits), energy_bits=energy_bits, segment_frames=1,
                   penalty_codes=np.ones((10, 9), int), penalty_bits=penalty_bits)
    operands = list(cases(cfg))
    want = [ref_penalised(*op) for op in operands]
    assert rtl_penalised(cfg, operands) == want
    assert min(want) == -((1 << penalty_bits) - 1) and max(want) == cfg.e_max
