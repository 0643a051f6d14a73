"""``AXILiteSubordinate`` (inside ``RegisterFile``), cycle for cycle: a read answered two
cycles after its AR handshake with the registers of the cycle after it, nothing accepted
while a response is being prepared or offered, and addresses taken at their handshakes
only (the bus may change after it)."""

import pytest

from dptbd.hw.axi_lite import RESP_OKAY, RESP_SLVERR
from dptbd.hw.register_file import RegisterFile
from dptbd.hw.register_map import constants_namespace
from helpers.axil_harness import axil_read, axil_write
from helpers.hw_harness import simulate
from helpers.seg_harness import make_config


def config():
    return make_config(width=8, height=6, candidate_count=5, histogram_bits=4)


def readies(ctx, axil):
    return (ctx.get(axil.aw.awready), ctx.get(axil.w.wready), ctx.get(axil.ar.arready))


@pytest.mark.parametrize("late", [False, True], ids=["generic", "read_registered"])
def test_a_read_is_answered_two_cycles_after_its_handshake(late):
    """AR taken in cycle c (with an event pulse in c, whose bit is set at the end of c + 1):
    ``rvalid`` rises in c + 2 with the registers of c + 1 (the bit not yet set); AW, W and AR
    are refused from c + 1 until the cycle after R is taken, here held 3 cycles. A second
    read taken in d with a pulse in d - 1 reads the bit set at the end of d. With
    ``read_registered`` (the ECP5 build's) ``rvalid`` rises in c + 3, with the registers
    of c + 1 as without."""
    cfg = config()
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg, read_registered=late)
    trace = []

    async def bench(ctx):
        axil = dut.axil
        await ctx.tick()
        ctx.set(axil.ar.araddr, regs.REG_IRQ_STATUS)
        ctx.set(axil.ar.arvalid, 1)
        ctx.set(dut.events.segment_done, 1)
        trace.append(("c", readies(ctx, axil), ctx.get(axil.r.rvalid)))
        await ctx.tick()
        ctx.set(dut.events.segment_done, 0)
        # the manager offers all three channels while the read is answered
        ctx.set(axil.ar.araddr, regs.REG_ID)
        ctx.set(axil.aw.awvalid, 1)
        ctx.set(axil.w.wvalid, 1)
        for cycle in ("c+1", "c+2", "c+3", "c+4"):
            trace.append((cycle, readies(ctx, axil), ctx.get(axil.r.rvalid),
                          ctx.get(axil.r.rdata), ctx.get(axil.r.rresp)))
            await ctx.tick()
        ctx.set(axil.r.rready, 1)                       # taken in c + 5
        ctx.set(axil.aw.awvalid, 0)
        ctx.set(axil.w.wvalid, 0)
        ctx.set(axil.ar.arvalid, 0)
        trace.append(("c+5", readies(ctx, axil), ctx.get(axil.r.rvalid)))
        await ctx.tick()
        ctx.set(axil.r.rready, 0)
        trace.append(("c+6", readies(ctx, axil), ctx.get(axil.r.rvalid)))
        # clear the bit, then: pulse in d - 1, AR in d
        assert await axil_write(ctx, axil, regs.REG_IRQ_STATUS,
                                regs.IRQ_STATUS_SEGMENT_DONE_MASK) == RESP_OKAY
        ctx.set(dut.events.segment_done, 1)
        await ctx.tick()
        ctx.set(dut.events.segment_done, 0)
        trace.append(("d", await axil_read(ctx, axil, regs.REG_IRQ_STATUS)))

    simulate(dut, bench)
    done = regs.IRQ_STATUS_SEGMENT_DONE_MASK
    assert trace == [
        ("c", (1, 1, 1), 0),
        ("c+1", (0, 0, 0), 0, 0, RESP_OKAY),
        ("c+2", (0, 0, 0), int(not late), 0, RESP_OKAY),    # the bit as it was in c + 1
        ("c+3", (0, 0, 0), 1, 0, RESP_OKAY),
        ("c+4", (0, 0, 0), 1, 0, RESP_OKAY),
        ("c+5", (0, 0, 0), 1),
        ("c+6", (1, 1, 1), 0),
        ("d", (done, RESP_OKAY)),
    ]


@pytest.mark.parametrize("late", [False, True], ids=["generic", "read_registered"])
def test_a_read_takes_its_address_at_the_handshake(late):
    """After the AR handshake ``araddr`` changes (to another register, then to an unmapped
    address): the answer is the first address's."""
    cfg = config()
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg, read_registered=late)
    got = []

    async def bench(ctx):
        axil = dut.axil
        assert await axil_write(ctx, axil, regs.REG_CANDIDATE_COUNT, 3) == RESP_OKAY
        for first, then in ((regs.REG_CANDIDATE_COUNT, regs.REG_SEGMENT_FRAMES),
                            (regs.REG_CANDIDATE_COUNT, 0x3F0),
                            (0x3F0, regs.REG_CANDIDATE_COUNT)):
            ctx.set(axil.ar.araddr, first)
            ctx.set(axil.ar.arvalid, 1)
            assert ctx.get(axil.ar.arready)
            await ctx.tick()
            ctx.set(axil.ar.arvalid, 0)
            ctx.set(axil.ar.araddr, then)
            while not ctx.get(axil.r.rvalid):
                await ctx.tick()
            ctx.set(axil.r.rready, 1)
            got.append((ctx.get(axil.r.rdata), ctx.get(axil.r.rresp)))
            await ctx.tick()
            ctx.set(axil.r.rready, 0)

    simulate(dut, bench)
    assert got == [(3, RESP_OKAY), (3, RESP_OKAY), (0, RESP_SLVERR)]


def test_a_write_takes_its_address_at_the_handshake():
    """AW taken alone, then ``awaddr`` changes (to another setting) before W: the write goes
    to the first address; the other keeps its value."""
    cfg = config()
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg)
    got = []

    async def bench(ctx):
        axil = dut.axil
        ctx.set(axil.aw.awaddr, regs.REG_CANDIDATE_COUNT)
        ctx.set(axil.aw.awvalid, 1)
        assert ctx.get(axil.aw.awready)
        await ctx.tick()
        ctx.set(axil.aw.awvalid, 0)
        ctx.set(axil.aw.awaddr, regs.REG_HISTOGRAM_SHIFT)
        await ctx.tick()
        ctx.set(axil.w.wdata, 2)
        ctx.set(axil.w.wstrb, 0xF)
        ctx.set(axil.w.wvalid, 1)
        assert ctx.get(axil.w.wready)
        await ctx.tick()
        ctx.set(axil.w.wvalid, 0)
        while not ctx.get(axil.b.bvalid):
            await ctx.tick()
        ctx.set(axil.b.bready, 1)
        got.append(ctx.get(axil.b.bresp))
        await ctx.tick()
        ctx.set(axil.b.bready, 0)
        got.append((await axil_read(ctx, axil, regs.REG_CANDIDATE_COUNT))[0])
        got.append((await axil_read(ctx, axil, regs.REG_HISTOGRAM_SHIFT))[0])

    simulate(dut, bench)
    assert got == [RESP_OKAY, 2, cfg.bin_shift]
