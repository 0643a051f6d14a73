"""Saturating accumulator against ``add_saturating``; segment start takes E = x, d = START."""

import random

import pytest
from amaranth.sim import Simulator

from dptbd.config import DPConfig
from dptbd.hw.accumulator import Accumulator
from dptbd.model.operators import add_saturating


@pytest.mark.parametrize("input_bits, energy_bits", [(8, 16), (4, 5), (8, 8)])
def test_matches_add_saturating(input_bits, energy_bits):
    cfg = DPConfig(input_bits=input_bits, energy_bits=energy_bits, segment_frames=1)
    dut = Accumulator(cfg)
    rng = random.Random(energy_bits)
    cases = [(cfg.e_max, cfg.pixel_max, 3, 0), (cfg.e_max - 1, 1, 2, 0), (0, 0, 0, 0),
             (cfg.e_max, cfg.pixel_max, 5, 1)]
    cases += [(rng.choice([rng.randrange(cfg.e_max + 1), cfg.e_max - rng.randrange(1 << input_bits)]),
               rng.randrange(cfg.pixel_max + 1), rng.randrange(cfg.n_moves), rng.random() < 0.2)
              for _ in range(100)]

    async def bench(ctx):
        for best, pixel, move, start in cases:
            ctx.set(dut.best, best)
            ctx.set(dut.pixel, pixel)
            ctx.set(dut.move, move)
            ctx.set(dut.segment_start, start)
            await ctx.tick()
            if start:
                expected = (pixel, cfg.start_code)
            else:
                expected = (int(add_saturating(best, pixel, energy_bits)), move)
            assert (ctx.get(dut.energy), ctx.get(dut.direction)) == expected, \
                f"best={best} x={pixel} start={start}"

    sim = Simulator(dut)
    sim.add_clock(1e-8)
    sim.add_testbench(bench)
    sim.run()
