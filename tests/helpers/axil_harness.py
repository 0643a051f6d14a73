"""AXI4-Lite manager for Amaranth-simulator testbenches (``ctx`` of ``add_testbench``).

Drives an ``axi_lite_signature`` port: :func:`axil_write` presents AW and W (together, AW
first or W first) and waits for B; :func:`axil_read` presents AR and waits for R. Both
return the response code, counting the cycles they took in ``cycles`` when given.
"""

from __future__ import annotations

import types

from amaranth.sim import Simulator


async def axil_write(ctx, axil, addr: int, data: int, strb: int = 0xF, *,
                     order: str = "together", bready_delay: int = 0) -> int:
    """One write; ``order`` is ``"together"``, ``"aw_first"`` or ``"w_first"``; B is
    accepted ``bready_delay`` cycles after ``bvalid`` rises. Returns ``bresp``."""
    aw, w, b = axil.aw, axil.w, axil.b
    ctx.set(aw.awaddr, addr)
    ctx.set(w.wdata, data)
    ctx.set(w.wstrb, strb)
    ctx.set(aw.awvalid, order != "w_first")
    ctx.set(w.wvalid, order != "aw_first")
    aw_done = w_done = False
    while not (aw_done and w_done):
        aw_go = ctx.get(aw.awvalid) and ctx.get(aw.awready)
        w_go = ctx.get(w.wvalid) and ctx.get(w.wready)
        await ctx.tick()
        if aw_go:
            aw_done = True
            ctx.set(aw.awvalid, 0)
        if w_go:
            w_done = True
            ctx.set(w.wvalid, 0)
        ctx.set(aw.awvalid, not aw_done and (order != "w_first" or w_done))
        ctx.set(w.wvalid, not w_done and (order != "aw_first" or aw_done))
    while not ctx.get(b.bvalid):
        await ctx.tick()
    for _ in range(bready_delay):
        assert ctx.get(b.bvalid)
        await ctx.tick()
    ctx.set(b.bready, 1)
    resp = ctx.get(b.bresp)
    await ctx.tick()
    ctx.set(b.bready, 0)
    return resp


async def axil_read(ctx, axil, addr: int) -> tuple[int, int]:
    """One read: ``(rdata, rresp)``."""
    ar, r = axil.ar, axil.r
    ctx.set(ar.araddr, addr)
    ctx.set(ar.arvalid, 1)
    while not ctx.get(ar.arready):
        await ctx.tick()
    await ctx.tick()
    ctx.set(ar.arvalid, 0)
    while not ctx.get(r.rvalid):
        await ctx.tick()
    ctx.set(r.rready, 1)
    data, resp = ctx.get(r.rdata), ctx.get(r.rresp)
    await ctx.tick()
    ctx.set(r.rready, 0)
    return data, resp


def flat_axil(top):
    """The ``axil.aw.awaddr`` … paths this module drives, on the flat ``s_axil_*``
    ports."""
    def channel(*names):
        return types.SimpleNamespace(**{n: getattr(top, f"s_axil_{n}") for n in names})
    return types.SimpleNamespace(
        aw=channel("awaddr", "awprot", "awvalid", "awready"),
        w=channel("wdata", "wstrb", "wvalid", "wready"),
        b=channel("bresp", "bvalid", "bready"),
        ar=channel("araddr", "arprot", "arvalid", "arready"),
        r=channel("rdata", "rresp", "rvalid", "rready"))


def simulate_top(top, bench, *background):
    """Toggle the AXI top's ``aclk`` (10 ns) and run ``background`` testbenches behind
    ``bench``, which ticks the top's own domain."""
    async def clock(ctx):
        while True:
            ctx.set(top.aclk, 0)
            await ctx.delay(5e-9)
            ctx.set(top.aclk, 1)
            await ctx.delay(5e-9)

    sim = Simulator(top)
    sim.add_testbench(clock, background=True)
    for process in background:
        sim.add_testbench(process, background=True)
    sim.add_testbench(bench)
    sim.run()
