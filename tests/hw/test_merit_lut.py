"""Merit LUT against ``lookup_merit_code`` (§8.1), with run-time writes.

Glasgow's pattern: ``cases()`` yields one (pixel, write) per cycle, ``ref_merit_lut`` is the
golden model's answer under the write rule (a write presented in cycle c is seen by the
lookups issued in cycle c+2 and later: the pipeline issues a pixel's lookup 2 cycles after
accepting it, so the write applies to the pixels accepted in cycle c or later),
``rtl_merit_lut`` the gateware's.
"""

import random

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.merit_lut import MeritLUT
from dptbd.model.family.operators import lookup_merit_code
from helpers.hw_harness import simulate


def make_config(input_bits, merit_bits, seed):
    rng = np.random.default_rng(seed)
    top = 1 << (merit_bits - 1)
    return DPConfig(input_bits=input_bits, energy_bits=max(merit_bits, input_bits, 4),
                    segment_frames=1, merit_bits=merit_bits,
                    merit_codes=rng.integers(-top, top, size=1 << input_bits))


def cases(cfg, n=300):
    """(pixel, write or None) per cycle; write = (address, code); every code value."""
    rng = random.Random(cfg.input_bits)
    top = 1 << (cfg.merit_width - 1)
    for _ in range(n):
        write = (rng.randrange(1 << cfg.input_bits), rng.randrange(-top, top)) \
            if rng.random() < 0.3 else None
        yield rng.randrange(1 << cfg.input_bits), write


def ref_merit_lut(cfg, vectors) -> list[int]:
    table = cfg.merit_code_array.copy()
    out = []
    for cycle, (pixel, _) in enumerate(vectors):
        if cycle >= 2 and vectors[cycle - 2][1] is not None:
            address, code = vectors[cycle - 2][1]
            table[address] = code
        out.append(int(lookup_merit_code(table, np.int64(pixel))))
    return out


def rtl_merit_lut(cfg, vectors) -> list[int]:
    dut = MeritLUT(cfg)
    got = []

    async def bench(ctx):
        for pixel, write in vectors:
            ctx.set(dut.pixel, pixel)
            ctx.set(dut.write_en, write is not None)
            if write is not None:
                ctx.set(dut.write_addr, write[0])
                ctx.set(dut.write_data, write[1])
            await ctx.tick()
            got.append(ctx.get(dut.merit))

    simulate(dut, bench)
    return got


@pytest.mark.parametrize("input_bits, merit_bits", [(4, 6), (8, 9), (2, 2), (6, 17)])
def test_matches_lookup_merit_code_with_writes(input_bits, merit_bits):
    cfg = make_config(input_bits, merit_bits, seed=input_bits)
    vectors = list(cases(cfg))
    want = ref_merit_lut(cfg, vectors)
    assert rtl_merit_lut(cfg, vectors) == want
    assert want != ref_merit_lut(cfg, [(p, None) for p, _ in vectors])  # the writes mattered
