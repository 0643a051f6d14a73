"""DPCore with an external state store: a Python model of a one-cycle synchronous SRAM."""

import random

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.dp_core import DPCore
from hw_harness import assert_states_equal, frames_to_stream, reference_states, run_stream


def sram_model(bus, words, seed):
    """Testbench process: read ``read_addr`` at each edge with ``read_en``, write likewise.

    ``read_data`` is garbage except in the cycle after a read, and the memory starts with
    random contents: the core must use neither.
    """
    rng = random.Random(seed)
    width = len(bus.read_data.as_value())
    contents = [rng.randrange(1 << width) for _ in range(words)]
    collisions = []

    async def process(ctx):
        async for _clk, _rst, read_en, read_addr, write_en, write_addr, write_data in ctx.tick().sample(
                bus.read_en, bus.read_addr, bus.write_en, bus.write_addr,
                bus.write_data.as_value()):
            if read_en and write_en and read_addr == write_addr:
                collisions.append(read_addr)
            data = contents[read_addr] if read_en else rng.randrange(1 << width)
            ctx.set(bus.read_data.as_value(), data)
            if write_en:
                contents[write_addr] = write_data

    return process, collisions


@pytest.mark.parametrize("style", ["bram", "logic"])
def test_external_store_matches_golden_model(style):
    cfg = DPConfig(width=6, height=5, segment_frames=3)
    dut = DPCore(cfg, lut_style=style)
    assert dut.lut_style == style
    frames = np.random.default_rng(21).integers(0, 256, size=(7, cfg.height, cfg.width))
    process, collisions = sram_model(dut.state_store, cfg.width * cfg.height, seed=3)
    run = run_stream(dut, cfg, frames_to_stream(frames), valid_probability=0.8,
                     ready_probability=0.7, seed=11, processes=[process])
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    assert collisions == []   # no read and write of one address in one cycle
