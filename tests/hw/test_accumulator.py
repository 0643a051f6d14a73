"""Saturating accumulator against ``add_saturating``; segment start takes E = x, d = START;
the ``saturated`` flag against ``saturated_sum``.

Glasgow's pattern: ``cases()`` yields the operands, ``ref_accumulator`` is the golden
model's answer, ``rtl_accumulator`` the gateware's, one per operand.
"""

import random

import pytest

from dptbd.config import DPConfig
from dptbd.hw.accumulator import Accumulator
from dptbd.model.operators import add_saturating, saturated_sum
from hw_harness import simulate


def cases(cfg):
    """(best, x, move, segment_start): saturation corners, then random ones."""
    rng = random.Random(cfg.energy_bits)
    yield from [(cfg.e_max, cfg.pixel_max, 3, 0), (cfg.e_max - 1, 1, 2, 0), (0, 0, 0, 0),
                (cfg.e_max, cfg.pixel_max, 5, 1)]
    for _ in range(100):
        best = rng.choice([rng.randrange(cfg.e_max + 1),
                           cfg.e_max - rng.randrange(1 << cfg.input_bits)])
        yield (best, rng.randrange(cfg.pixel_max + 1), rng.randrange(cfg.n_moves),
               int(rng.random() < 0.2))


def ref_accumulator(cfg, best, pixel, move, start) -> tuple[int, int, int]:
    """(E, d, saturated) of the golden model."""
    addend = 0 if start else best
    clipped = int(saturated_sum(addend, pixel, cfg.energy_bits))
    if start:
        return pixel, cfg.start_code, clipped
    return int(add_saturating(best, pixel, cfg.energy_bits)), move, clipped


def rtl_accumulator(cfg, operands) -> list[tuple[int, int, int]]:
    """(E, d, saturated) of each operand, one cycle after it is presented."""
    dut = Accumulator(cfg)
    got = []

    async def bench(ctx):
        for best, pixel, move, start in operands:
            ctx.set(dut.best, best)
            ctx.set(dut.pixel, pixel)
            ctx.set(dut.move, move)
            ctx.set(dut.segment_start, start)
            await ctx.tick()
            got.append((ctx.get(dut.energy), ctx.get(dut.direction), ctx.get(dut.saturated)))

    simulate(dut, bench)
    return got


@pytest.mark.parametrize("input_bits, energy_bits", [(8, 16), (4, 5), (8, 8)])
def test_matches_add_saturating(input_bits, energy_bits):
    cfg = DPConfig(input_bits=input_bits, energy_bits=energy_bits, segment_frames=1)
    operands = list(cases(cfg))
    want = [ref_accumulator(cfg, *op) for op in operands]
    assert rtl_accumulator(cfg, operands) == want
    assert any(w[2] for w in want) and not all(w[2] for w in want)
