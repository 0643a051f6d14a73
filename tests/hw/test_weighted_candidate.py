"""Weighted candidate C = round(E * c / 2**F) against ``scale_by_weight``."""

import random

import numpy as np
import pytest
from amaranth.sim import Simulator

from dptbd.config import DPConfig
from dptbd.hw.weighted_candidate import WeightedCandidate
from dptbd.model.operators import scale_by_weight


@pytest.mark.parametrize("energy_bits, frac, rounding", [
    (16, 8, "truncate"), (16, 8, "half_up"), (12, 0, "truncate"), (12, 0, "half_up"),
    (10, 1, "half_up"), (9, 3, "truncate"), (9, 3, "half_up"), (32, 16, "half_up"),
])
def test_matches_scale_by_weight(energy_bits, frac, rounding):
    cfg = DPConfig(input_bits=min(8, energy_bits), energy_bits=energy_bits,
                   weight_frac_bits=frac, rounding=rounding, segment_frames=1)
    dut = WeightedCandidate(cfg)
    rng = random.Random(energy_bits * 100 + frac)
    e_max, unity = cfg.e_max, 1 << frac
    corners = [(0, 0), (e_max, unity), (e_max, unity - 1 if frac else 0), (e_max, 0),
               (1, unity // 2), (3, unity // 2), (e_max, unity // 2)]
    operands = corners + [(rng.randrange(e_max + 1), rng.randrange(unity + 1)) for _ in range(150)]
    energies = np.array([e for e, _ in operands], dtype=np.int64)
    codes = np.array([c for _, c in operands], dtype=np.int64)
    expected = scale_by_weight(energies, codes, frac, rounding).tolist()
    got = []

    async def bench(ctx):
        for cycle in range(len(operands) + dut.latency):
            if cycle < len(operands):
                ctx.set(dut.energy, operands[cycle][0])
                ctx.set(dut.code, operands[cycle][1])
                ctx.set(dut.inside, 1)
            await ctx.tick()
            if cycle + 1 >= dut.latency:
                got.append(ctx.get(dut.weighted))

    sim = Simulator(dut)
    sim.add_clock(1e-8)
    sim.add_testbench(bench)
    sim.run()
    got = got[:len(operands)]
    for n, (g, w) in enumerate(zip(got, expected)):
        assert g == w, f"E={operands[n][0]} c={operands[n][1]}: got {g}, expected {w}"


@pytest.mark.parametrize("energy_bits, frac, rounding", [
    (16, 8, "truncate"), (16, 8, "half_up"), (12, 0, "half_up"), (32, 16, "half_up"),
])
def test_outside_the_image_weighs_zero(energy_bits, frac, rounding):
    """``inside`` = 0 (predecessor outside the image): C = 0 whatever E and the code, also
    a code above 2**F; interleaved cycle by cycle with inside candidates, which still
    match ``scale_by_weight``."""
    cfg = DPConfig(input_bits=min(8, energy_bits), energy_bits=energy_bits,
                   weight_frac_bits=frac, rounding=rounding, segment_frames=1)
    dut = WeightedCandidate(cfg)
    rng = random.Random(energy_bits + frac)
    e_max, unity, code_max = cfg.e_max, 1 << frac, (1 << cfg.weight_bits) - 1
    operands = [(e_max, unity, 0), (e_max, code_max, 0), (e_max, unity, 1)] + [
        (rng.randrange(e_max + 1), rng.randrange(code_max + 1), rng.randrange(2))
        for _ in range(150)]
    expected = [int(scale_by_weight(np.int64(e), np.int64(min(c, unity)), frac, rounding))
                if inside else 0 for e, c, inside in operands]
    got = []

    async def bench(ctx):
        for cycle in range(len(operands) + dut.latency):
            if cycle < len(operands):
                energy, code, inside = operands[cycle]
                # an inside candidate never has a code above 2**F (the LUT clamps writes)
                ctx.set(dut.energy, energy)
                ctx.set(dut.code, code if not inside else min(code, unity))
                ctx.set(dut.inside, inside)
            await ctx.tick()
            if cycle + 1 >= dut.latency:
                got.append(ctx.get(dut.weighted))

    sim = Simulator(dut)
    sim.add_clock(1e-8)
    sim.add_testbench(bench)
    sim.run()
    got = got[:len(operands)]
    assert sum(1 for *_, inside in operands if not inside) > 50
    for n, (g, w) in enumerate(zip(got, expected)):
        assert g == w, f"E, c, inside = {operands[n]}: got {g}, expected {w}"
