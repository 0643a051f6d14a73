"""Saturating accumulator against ``add_saturating``; segment start takes E = x, d = START;
the ``saturated`` flag against ``saturated_sum``.

Glasgow's pattern: ``cases()`` yields the operands, ``ref_accumulator`` is the golden
model's answer, ``rtl_accumulator`` the gateware's, one per operand.
"""

import random

import pytest

from amaranth.hdl import signed, unsigned

from dptbd.config import DPConfig
from dptbd.hw.accumulator import Accumulator, ClampedAccumulator
from dptbd.model.family.operators import add_clamped
from dptbd.model.operators import add_saturating, saturated_sum
from helpers.hw_harness import simulate


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


def rtl_accumulator(cfg, operands, dut=None, addend="pixel") -> list[tuple[int, int, int]]:
    """(E, d, saturated) of each operand, one cycle after it is presented; ``dut`` defaults
    to ``Accumulator(cfg)``, ``addend`` names its x (or P) input."""
    dut = Accumulator(cfg) if dut is None else dut
    got = []

    async def bench(ctx):
        for best, pixel, move, start in operands:
            ctx.set(dut.best, best)
            ctx.set(getattr(dut, addend), pixel)
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


# ---- paper 000's family: clamp at both ends (docs/arithmetic.md §8.5) ----------------------

def clamped_cases(cfg, value_shape):
    """(A, P, move, start): both clamps, the start frame, then random."""
    rng = random.Random(cfg.energy_bits + 7)
    a_lo = -(1 << (value_shape.width - 1)) if value_shape.signed else 0
    a_hi = (1 << (value_shape.width - 1)) - 1 if value_shape.signed else cfg.e_max
    p_lo, p_hi = -(1 << (cfg.merit_width - 1)), (1 << (cfg.merit_width - 1)) - 1
    yield from [(a_hi, p_hi, 3, 0), (a_lo, p_lo, 2, 0), (0, p_lo, 1, 1), (a_hi, p_hi, 4, 1),
                (0, 0, 0, 0), (cfg.e_max, 1, 1, 0)]
    for _ in range(150):
        yield (rng.randint(a_lo, a_hi), rng.randint(p_lo, p_hi), rng.randrange(cfg.n_moves),
               int(rng.random() < 0.2))


def ref_clamped_accumulator(cfg, best, merit, move, start) -> tuple[int, int, int]:
    """(E, d, saturated) of the family's golden model (``add_clamped``)."""
    total = merit + (0 if start else best)
    energy = int(add_clamped(0 if start else best, merit, cfg.energy_bits))
    return energy, cfg.start_code if start else move, int(total > cfg.e_max)


@pytest.mark.parametrize("energy_bits, merit_bits, is_signed", [
    (10, 11, True), (8, 4, True), (12, 9, False), (6, 7, False)])
def test_clamped_matches_add_clamped(energy_bits, merit_bits, is_signed):
    cfg = DPConfig(input_bits=3, energy_bits=energy_bits, segment_frames=1,
                   merit_codes=[-1, 0, 1, 2, 3, 4, 5, 6], merit_bits=merit_bits)
    shape = signed(cfg.candidate_value_bits) if is_signed else unsigned(energy_bits)
    operands = list(clamped_cases(cfg, shape))
    want = [ref_clamped_accumulator(cfg, *op) for op in operands]
    assert rtl_accumulator(cfg, operands, ClampedAccumulator(cfg, shape), "merit") == want
    energies = [w[0] for w in want]
    assert 0 in energies and cfg.e_max in energies and any(w[2] for w in want)
