"""``AXITop`` in the Amaranth simulator: flat AXI port names, identification over the flat
AXI4-Lite port, ``aresetn``, input-stall counting and the soft reset's hold-off cycle.
(Whole scenes are scored by the cocotb tests, ``tests/sim/test_tb_axi.py``.)"""

import types

from amaranth.hdl import Fragment
from amaranth.sim import Simulator

from dptbd.hw.axi_lite import RESP_OKAY
from dptbd.hw.axi_top import AXITop
from dptbd.hw.flow.register_export import constants_namespace
from helpers.axil_harness import axil_read, axil_write
from helpers.seg_harness import make_config


def config():
    return make_config(width=8, height=6, candidate_count=2)


def flat_axil(top):
    """The ``axil.aw.awaddr`` … paths ``axil_harness`` drives, on the flat ``s_axil_*``
    ports."""
    def channel(*names):
        return types.SimpleNamespace(**{n: getattr(top, f"s_axil_{n}") for n in names})
    return types.SimpleNamespace(
        aw=channel("awaddr", "awprot", "awvalid", "awready"),
        w=channel("wdata", "wstrb", "wvalid", "wready"),
        b=channel("bresp", "bvalid", "bready"),
        ar=channel("araddr", "arprot", "arvalid", "arready"),
        r=channel("rdata", "rresp", "rvalid", "rready"))


def simulate_top(top, bench):
    """Toggle ``aclk`` (10 ns) in the background; ``bench`` ticks the top's own domain."""
    async def clock(ctx):
        while True:
            ctx.set(top.aclk, 0)
            await ctx.delay(5e-9)
            ctx.set(top.aclk, 1)
            await ctx.delay(5e-9)

    sim = Simulator(top)
    sim.add_testbench(clock, background=True)
    sim.add_testbench(bench)
    sim.run()


def test_ports_carry_axi_names():
    top = AXITop(config())
    names = [path[0] for path, _m, _v in top.signature.flatten(top)]
    assert names[:2] == ["aclk", "aresetn"] and names[-1] == "irq"
    assert {"s_axis_video_tuser", "m_axis_cand_tlast", "s_axil_bresp",
            "s_axil_wstrb"} <= set(names)
    assert not [n for n in names if "__" in n]
    Fragment.get(top, None)                        # elaborates: no UnusedElaboratable warning


def test_identification_stalls_and_soft_reset():
    """After ``aresetn`` the core takes no pixel for one cycle; a soft reset adds its own
    pulse cycle before that one: with ``tvalid`` held high across it, two stall cycles are
    counted, and the start-of-frame beat is then taken without a fault."""
    cfg = config()
    regs = constants_namespace(cfg)
    top = AXITop(cfg)
    axil = flat_axil(top)
    low = []

    async def bench(ctx):
        ctx.set(top.aresetn, 0)
        await ctx.tick("sync")
        ctx.set(top.aresetn, 1)
        assert ctx.get(top.s_axis_video_tready) == 0
        await ctx.tick("sync")
        assert ctx.get(top.s_axis_video_tready) == 1
        assert await axil_read(ctx, axil, regs.REG_ID) == (regs.MAGIC, RESP_OKAY)
        ctx.set(top.s_axis_video_tuser, 1)
        ctx.set(top.s_axis_video_tvalid, 0)
        await axil_write(ctx, axil, regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK)
        ctx.set(top.s_axis_video_tvalid, 1)             # offered from now on
        while not ctx.get(top.s_axis_video_tready):
            low.append(1)
            await ctx.tick("sync")
        await ctx.tick("sync")                           # accepted here
        ctx.set(top.s_axis_video_tvalid, 0)
        stalls, _ = await axil_read(ctx, axil, regs.REG_INPUT_STALLS)
        assert stalls == len(low)
        error, _ = await axil_read(ctx, axil, regs.REG_ERROR)
        assert error == 0

    simulate_top(top, bench)
    assert len(low) == 1         # the core's post-reset cycle; the pulse ended in axil_write


def test_soft_reset_pulse_holds_tready_low():
    """The cycle of the soft-reset pulse itself has tready low (tvalid offered throughout
    the write: the pulse cycle and the core's post-reset cycle are both stalls)."""
    cfg = config()
    regs = constants_namespace(cfg)
    top = AXITop(cfg)
    axil = flat_axil(top)

    async def bench(ctx):
        ctx.set(top.aresetn, 0)
        await ctx.tick("sync")
        ctx.set(top.aresetn, 1)
        await ctx.tick("sync")
        await axil_write(ctx, axil, regs.REG_CONTROL, regs.CONTROL_CLEAR_COUNTERS_MASK)
        ctx.set(top.s_axis_video_tuser, 1)
        ctx.set(top.s_axis_video_tvalid, 1)              # accepted at once, then idle beats
        await ctx.tick("sync")
        ctx.set(top.s_axis_video_tuser, 0)
        ctx.set(top.s_axis_video_tvalid, 0)
        await axil_write(ctx, axil, regs.REG_CONTROL, regs.CONTROL_CLEAR_COUNTERS_MASK)
        ctx.set(top.s_axis_video_tuser, 1)               # a new frame start, offered during
        ctx.set(top.s_axis_video_tvalid, 1)              # the soft-reset write
        await axil_write(ctx, axil, regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK)
        while not ctx.get(top.s_axis_video_tready):
            await ctx.tick("sync")
        await ctx.tick("sync")
        ctx.set(top.s_axis_video_tvalid, 0)
        stalls, _ = await axil_read(ctx, axil, regs.REG_INPUT_STALLS)
        assert stalls == 2
        error, _ = await axil_read(ctx, axil, regs.REG_ERROR)
        assert error == regs.ERROR_SOF_UNEXPECTED_MASK     # before the reset: mid-frame

    simulate_top(top, bench)
