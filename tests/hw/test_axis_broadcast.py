"""``StreamBroadcast`` (verilog-axis ``axis_broadcast``): every word reaches every output in
order, under random input gaps × independent random back-pressure per output; ``ref_*`` is
the word list each output must see, ``rtl_*`` runs the component and records the handshakes.
"""

import random

import pytest
from amaranth.sim import Simulator

from dptbd.errors import DptbdError
from dptbd.hw.axis_broadcast import StreamBroadcast


def cases():
    """(words, input gap probability, per-output stall probabilities, seed)."""
    words = list(range(1, 60))
    return [(words, 0.0, (0.0, 0.0), 1), (words, 0.0, (0.6, 0.0), 2),
            (words, 0.4, (0.0, 0.7), 3), (words, 0.3, (0.5, 0.5), 4),
            (words[:20], 0.5, (0.3, 0.8, 0.1), 5)]


def ref_broadcast(words, outputs):
    return [list(words) for _ in range(outputs)]


def rtl_broadcast(words, gap, stalls, seed):
    dut = StreamBroadcast(8, len(stalls))
    rng = random.Random(seed)
    got = [[] for _ in stalls]
    log = {"cycles": 0, "valid_fell_untaken": False}

    async def producer(ctx):
        for word in words:
            while rng.random() < gap:
                await ctx.tick()
            ctx.set(dut.input.payload, word)
            ctx.set(dut.input.valid, 1)
            await ctx.tick().until(dut.input.ready)
            ctx.set(dut.input.valid, 0)

    def consumer(i, stall):
        out = dut.outputs[i]
        local = random.Random(seed * 31 + i)

        async def bench(ctx):
            offered = None
            while len(got[i]) < len(words):
                ready = local.random() >= stall
                ctx.set(out.ready, ready)
                await ctx.delay(1e-9)
                valid, payload = ctx.get(out.valid), ctx.get(out.payload)
                if offered is not None and not valid:
                    log["valid_fell_untaken"] = True          # AXI: tvalid held until taken
                offered = payload if valid and not ready else None
                await ctx.tick()
                if valid and ready:
                    got[i].append(payload)
                log["cycles"] += i == 0
        return bench

    sim = Simulator(dut)
    sim.add_clock(1e-8)
    sim.add_testbench(producer)
    for i, stall in enumerate(stalls):
        sim.add_testbench(consumer(i, stall))
    sim.run()
    return got, log


@pytest.mark.parametrize("words,gap,stalls,seed", cases())
def test_broadcast_delivers_every_word_to_every_output(words, gap, stalls, seed):
    got, log = rtl_broadcast(words, gap, stalls, seed)
    assert got == ref_broadcast(words, len(stalls))
    assert not log["valid_fell_untaken"]


def test_broadcast_full_rate_one_cycle_late():
    got, log = rtl_broadcast(list(range(40)), 0.0, (0.0, 0.0), 9)
    assert got == ref_broadcast(range(40), 2) and log["cycles"] == 41


def test_broadcast_refuses_one_output():
    with pytest.raises(DptbdError, match=r"^count must be an integer in \[2, 16\], got 1$"):
        StreamBroadcast(8, 1)
