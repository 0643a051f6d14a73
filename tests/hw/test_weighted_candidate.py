"""Weighted candidate C = round(E * c / 2**F) against ``scale_by_weight``.

Glasgow's pattern: ``cases()`` yields the operands, ``ref_weighted_candidate`` is the
golden model's answer, ``rtl_weighted_candidate`` the gateware's, one per operand.
"""

import random

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.weighted_candidate import WeightedCandidate
from dptbd.model.operators import scale_by_weight
from helpers.hw_harness import simulate


def make_config(energy_bits, frac, rounding):
    return DPConfig(input_bits=min(8, energy_bits), energy_bits=energy_bits,
                    weight_frac_bits=frac, rounding=rounding, segment_frames=1)


def cases(cfg, *, outside: bool):
    """(E, c, inside) operands: corners, then random ones; with ``outside`` also
    candidates outside the image (codes up to the field's maximum, above 2**F)."""
    rng = random.Random(cfg.energy_bits * 100 + cfg.weight_frac_bits + outside)
    e_max, unity, code_max = cfg.e_max, 1 << cfg.weight_frac_bits, (1 << cfg.weight_bits) - 1
    if not outside:
        yield from ((e, c, 1) for e, c in [
            (0, 0), (e_max, unity), (e_max, unity - 1 if unity > 1 else 0), (e_max, 0),
            (1, unity // 2), (3, unity // 2), (e_max, unity // 2)])
        for _ in range(150):
            yield rng.randrange(e_max + 1), rng.randrange(unity + 1), 1
        return
    yield from [(e_max, unity, 0), (e_max, code_max, 0), (e_max, unity, 1)]
    for _ in range(150):
        energy, code = rng.randrange(e_max + 1), rng.randrange(code_max + 1)
        inside = rng.randrange(2)
        # an inside candidate never has a code above 2**F (the LUT clamps writes)
        yield energy, min(code, unity) if inside else code, inside


def ref_weighted_candidate(cfg, energy, code, inside) -> int:
    if not inside:
        return 0
    return int(scale_by_weight(np.int64(energy), np.int64(code), cfg.weight_frac_bits,
                               cfg.rounding))


def rtl_weighted_candidate(cfg, operands) -> list[int]:
    """One operand a cycle into the pipeline; C of each, ``latency`` cycles later."""
    dut = WeightedCandidate(cfg)
    got = []

    async def bench(ctx):
        for cycle in range(len(operands) + dut.latency):
            if cycle < len(operands):
                energy, code, inside = operands[cycle]
                ctx.set(dut.energy, energy)
                ctx.set(dut.code, code)
                ctx.set(dut.inside, inside)
            await ctx.tick()
            if cycle + 1 >= dut.latency:
                got.append(ctx.get(dut.weighted))

    simulate(dut, bench)
    return got[:len(operands)]


@pytest.mark.parametrize("energy_bits, frac, rounding", [
    (16, 8, "truncate"), (16, 8, "half_up"), (12, 0, "truncate"), (12, 0, "half_up"),
    (10, 1, "half_up"), (9, 3, "truncate"), (9, 3, "half_up"), (32, 16, "half_up"),
])
def test_matches_scale_by_weight(energy_bits, frac, rounding):
    cfg = make_config(energy_bits, frac, rounding)
    operands = list(cases(cfg, outside=False))
    assert rtl_weighted_candidate(cfg, operands) == \
        [ref_weighted_candidate(cfg, *op) for op in operands]


@pytest.mark.parametrize("energy_bits, frac, rounding", [
    (16, 8, "truncate"), (16, 8, "half_up"), (12, 0, "half_up"), (32, 16, "half_up"),
])
def test_outside_the_image_weighs_zero(energy_bits, frac, rounding):
    """``inside`` = 0 (predecessor outside the image): C = 0 whatever E and the code, also
    a code above 2**F; interleaved cycle by cycle with inside candidates, which still
    match ``scale_by_weight``."""
    cfg = make_config(energy_bits, frac, rounding)
    operands = list(cases(cfg, outside=True))
    assert sum(1 for *_, inside in operands if not inside) > 50
    assert rtl_weighted_candidate(cfg, operands) == \
        [ref_weighted_candidate(cfg, *op) for op in operands]
