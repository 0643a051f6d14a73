"""On-chip state store: one-cycle synchronous reads, writes visible to the next read."""

import random


from dptbd.config import DPConfig
from dptbd.hw.layouts import pack_state_word
from dptbd.hw.state_store import StateStore
from helpers.hw_harness import simulate


def test_reads_return_written_words_one_cycle_later():
    cfg = DPConfig(width=5, height=4, energy_bits=10)
    dut = StateStore(cfg)
    rng = random.Random(7)
    words = cfg.width * cfg.height
    model = [0] * words
    checks = []

    async def bench(ctx):
        expected = None
        for _ in range(200):
            read_en = rng.random() < 0.7
            read_addr = rng.randrange(words)
            write_en = rng.random() < 0.5
            write_addr = rng.randrange(words)
            if write_en and read_en and write_addr == read_addr:
                write_addr = (write_addr + 1) % words  # the pipeline never does this
            word = pack_state_word(cfg, rng.randrange(1 << 10), rng.randrange(10))
            ctx.set(dut.bus.read_en, read_en)
            ctx.set(dut.bus.read_addr, read_addr)
            ctx.set(dut.bus.write_en, write_en)
            ctx.set(dut.bus.write_addr, write_addr)
            ctx.set(dut.bus.write_data.as_value(), word)
            if expected is not None:
                checks.append((ctx.get(dut.bus.read_data.as_value()), expected))
            expected = model[read_addr] if read_en else None
            await ctx.tick()
            if write_en:
                model[write_addr] = word

    simulate(dut, bench)
    assert len(checks) > 100
    for n, (got, want) in enumerate(checks):
        assert got == want, f"read {n}: got {got:#x}, expected {want:#x}"
