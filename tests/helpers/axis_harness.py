"""What the AXI4-Stream video adapters' tests share (``tests/hw/axis_video/``): the small
configuration, a run of an adapter with random gaps and back-pressure, a soft reset's
per-cycle trace, and the AXI4-Stream rules and packets of a per-cycle trace."""

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


def soft_reset_trace(dut, inp, out, flat, at, seed, *, offer, tail):
    """Run ``dut`` (``soft_reset`` in, ``restart`` / ``busy`` / ``stalled`` out) with a
    source on stream ``inp`` that behaves like the core's (a word offered stays offered until
    taken, offered in a cycle with probability ``offer``; on ``restart`` the offered word is
    gone and the rest of its group is dropped: the next word that starts one follows) and a
    random ``tready`` on AXI4-Stream port ``out``; ``flat`` is ``(payload, starts a group)``
    per word, ``soft_reset`` in cycle ``at`` (never if None), the run ``tail`` cycles past it
    at least. Returns the per-cycle trace of ``out`` and ``restart`` / ``busy`` / ``stalled``
    / ``taken`` (the source's word taken)."""
    rng = random.Random(seed)
    trace = []

    async def bench(ctx):
        index, offering, cycle = 0, False, 0
        while index < len(flat) or (at is not None and cycle <= at + tail):
            if not offering and index < len(flat) and rng.random() < offer:
                offering = True
            ctx.set(inp.valid, offering)
            if index < len(flat):
                ctx.set(inp.payload.as_value(), flat[index][0])
            ctx.set(dut.soft_reset, cycle == at)
            ctx.set(out.tready, rng.random() < 0.5)
            row = {name: ctx.get(getattr(out, name)) for name in
                   ("tvalid", "tready", "tdata", "tuser", "tlast")}
            row.update(restart=ctx.get(dut.restart), busy=ctx.get(dut.busy),
                       stalled=ctx.get(dut.stalled), taken=offering and ctx.get(inp.ready))
            trace.append(row)
            if row["taken"]:
                index, offering = index + 1, False
            if row["restart"]:
                offering = False
                while index < len(flat) and not flat[index][1]:
                    index += 1                               # the core drops the group's rest
            await ctx.tick()
            cycle += 1
            assert cycle < 2000

    simulate(dut, bench)
    return trace
