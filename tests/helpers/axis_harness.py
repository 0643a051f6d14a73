"""What the AXI4-Stream video adapters' tests share (``tests/hw/axis_video/``): the small
configuration, a run of an adapter with random gaps and back-pressure, and the AXI4-Stream
rules and packets of a per-cycle trace."""

import random

from helpers.hw_harness import simulate
from helpers.seg_harness import make_config


def config():
    return make_config(width=8, height=6, input_bits=10, candidate_count=3)


def rtl_adapter_beats(dut, inp, out, payloads, seed):
    """Feed ``payloads`` to ``inp`` with random gaps, take ``out`` with random back-pressure:
    the (tdata, tuser, tlast) of each transfer and the cycles ``dut.stalled`` was high
    (checked against tvalid and not tready in every cycle)."""
    rng = random.Random(seed)
    got, stalls = [], []

    async def source(ctx):
        for payload in payloads:
            ctx.set(inp.payload.as_value(), payload)
            ctx.set(inp.valid, 1)
            await ctx.tick().until(inp.ready)
            ctx.set(inp.valid, 0)
            while rng.random() < 0.3:
                await ctx.tick()

    async def sink(ctx):
        while len(got) < len(payloads):
            ready = rng.random() < 0.6
            ctx.set(out.tready, ready)
            stalls.append(ctx.get(dut.stalled))
            assert stalls[-1] == (ctx.get(out.tvalid) and not ready)
            if ready and ctx.get(out.tvalid):
                got.append((ctx.get(out.tdata), ctx.get(out.tuser), ctx.get(out.tlast)))
            await ctx.tick()

    simulate(dut, source, sink)
    return got, sum(stalls)


def check_axis_rules(trace):
    """AXI4-Stream on every cycle: tvalid never drops, and tdata / tuser / tlast never
    change, while a word waits for tready; ``stalled`` is tvalid and not tready."""
    for before, now in zip(trace, trace[1:]):
        if before["tvalid"] and not before["tready"]:
            assert now["tvalid"]
            assert [now[k] for k in ("tdata", "tuser", "tlast")] == \
                [before[k] for k in ("tdata", "tuser", "tlast")]
    for row in trace:
        assert row["stalled"] == (row["tvalid"] and not row["tready"])


def packets(trace):
    """The transfers, cut into packets at tlast: [[(tdata, tuser), …], …]."""
    out, current = [], []
    for row in trace:
        if row["tvalid"] and row["tready"]:
            current.append((row["tdata"], row["tuser"]))
            if row["tlast"]:
                out.append(current)
                current = []
    assert current == []                                    # every packet ends with tlast
    return out
