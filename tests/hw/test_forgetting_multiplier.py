"""Forgetting multiplier A = round_G(V * a) against ``scale_by_forgetting`` (§8.4).

Glasgow's pattern: ``cases()`` yields the operands, ``ref_forgetting`` is the golden model's
answer, ``rtl_forgetting`` the gateware's, one per operand.
"""

import random

import numpy as np
import pytest
from amaranth.hdl import signed, unsigned

from dptbd.config import DPConfig
from dptbd.hw.forgetting_multiplier import ForgettingMultiplier
from dptbd.model.family.operators import scale_by_forgetting
from helpers.hw_harness import simulate


def cases(shape):
    """V operands over the whole range of ``shape``: both ends, -1, 0, 1, then random."""
    lo = -(1 << (shape.width - 1)) if shape.signed else 0
    hi = (1 << (shape.width - 1)) - 1 if shape.signed else (1 << shape.width) - 1
    rng = random.Random(shape.width)
    yield from [v for v in (lo, hi, -3, -1, 0, 1, 3) if lo <= v <= hi]
    for _ in range(150):
        yield rng.randint(lo, hi)


def ref_forgetting(cfg, value) -> int:
    return int(scale_by_forgetting(np.int64(value), cfg.forgetting_code, cfg.forgetting_bits,
                                   cfg.rounding))


def rtl_forgetting(cfg, shape, operands) -> list[int]:
    """One V a cycle into the multiplier; A of each, ``latency`` cycles later."""
    dut = ForgettingMultiplier(cfg, shape)
    got = []

    async def bench(ctx):
        for cycle in range(len(operands) + dut.latency):
            if cycle < len(operands):
                ctx.set(dut.value, operands[cycle])
            await ctx.tick()
            if cycle + 1 >= dut.latency:
                got.append(ctx.get(dut.scaled))

    simulate(dut, bench)
    return got[:len(operands)]


@pytest.mark.parametrize("alpha, bits, rounding, energy_bits, is_signed", [
    (0.85, 8, "truncate", 12, True), (0.85, 8, "half_up", 12, True),
    (0.55, 4, "half_up", 10, True), (0.55, 4, "truncate", 10, False),
    (0.5, 1, "half_up", 8, True),            # a = 1, G = 1: V = -3 -> -1 half up
    (0.5, 1, "truncate", 8, True),           # floor: -3 -> -2
    (2 ** -16, 16, "truncate", 16, True),    # the smallest code, a = 1
    (0.99, 16, "half_up", 32, False),
])
def test_matches_scale_by_forgetting(alpha, bits, rounding, energy_bits, is_signed):
    cfg = DPConfig(energy_bits=energy_bits, forgetting=alpha, forgetting_bits=bits,
                   rounding=rounding, segment_frames=1)
    assert cfg.forgetting_code < 1 << bits
    shape = signed(cfg.candidate_value_bits) if is_signed else unsigned(energy_bits)
    operands = list(cases(shape))
    assert rtl_forgetting(cfg, shape, operands) == [ref_forgetting(cfg, v) for v in operands]


def test_negative_values_round_towards_minus_infinity_when_truncating():
    cfg = DPConfig(forgetting=0.5, forgetting_bits=1, segment_frames=1)
    assert rtl_forgetting(cfg, signed(17), [-3, -1, 3]) == [-2, -1, 1]
