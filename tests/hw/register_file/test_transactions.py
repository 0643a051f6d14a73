"""``RegisterFile``'s AXI4-Lite transactions: one at a time in any channel order, unaligned
accesses refused, a LUT write only with every byte strobed, LUT window reads answered SLVERR."""

import pytest
from amaranth.hdl import Fragment

from dptbd.hw.axi_lite import RESP_OKAY, RESP_SLVERR
from dptbd.hw.register_file import RegisterFile
from dptbd.hw.register_map import constants_namespace
from helpers.axil_harness import axil_read, axil_write
from helpers.hw_harness import simulate


@pytest.mark.parametrize("order", ["together", "aw_first", "w_first"])
def test_axi_lite_one_transaction_at_a_time(order, cfg):
    """Any AW/W order, a late bready, and a read queued behind a write: one transaction at
    a time, the write first."""
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg)

    async def bench(ctx):
        assert await axil_write(ctx, dut.axil, regs.REG_CANDIDATE_COUNT, 4, order=order,
                                bready_delay=3) == RESP_OKAY
        ctx.set(dut.axil.ar.arvalid, 1)                 # read and write offered together
        ctx.set(dut.axil.ar.araddr, regs.REG_CANDIDATE_COUNT)
        ctx.set(dut.axil.aw.awvalid, 1)
        assert not ctx.get(dut.axil.ar.arready)
        ctx.set(dut.axil.ar.arvalid, 0)
        ctx.set(dut.axil.aw.awvalid, 0)
        assert await axil_write(ctx, dut.axil, regs.REG_CANDIDATE_COUNT, 2, order=order) == 0
        assert await axil_read(ctx, dut.axil, regs.REG_CANDIDATE_COUNT) == (2, RESP_OKAY)

    simulate(dut, bench)


def test_unaligned_accesses_are_refused(cfg):
    """Every address that is not a multiple of 4 (a register, the LUT window, an unmapped
    word): a read answers 0 with SLVERR; a write answers SLVERR, changes nothing and sets
    ERROR.write_refused (cleared by W1C between the writes)."""
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg)
    entry = cfg.lut_address(1, 0)
    got = []

    async def bench(ctx):
        for base in (regs.REG_ID, regs.REG_SEGMENT_FRAMES, regs.REG_CONTROL, regs.REG_IRQ_ENABLE,
                     regs.REG_ERROR, regs.LUT_BASE + 4 * entry, 0x3F0):
            for offset in (1, 2, 3):
                before, _ = await axil_read(ctx, dut.axil, regs.REG_SEGMENT_FRAMES)
                enable, _ = await axil_read(ctx, dut.axil, regs.REG_IRQ_ENABLE)
                read = await axil_read(ctx, dut.axil, base + offset)
                resp = await axil_write(ctx, dut.axil, base + offset, 1)
                error, _ = await axil_read(ctx, dut.axil, regs.REG_ERROR)
                await axil_write(ctx, dut.axil, regs.REG_ERROR, error)
                after, _ = await axil_read(ctx, dut.axil, regs.REG_SEGMENT_FRAMES)
                enable_after, _ = await axil_read(ctx, dut.axil, regs.REG_IRQ_ENABLE)
                got.append((read, resp, error, after == before, enable_after == enable))

    writes, pulses = [], []

    async def watch(ctx):
        async for _clk, _rst, we, soft, clear in ctx.tick().sample(
                dut.lut_we, dut.soft_reset, dut.clear_counters):
            writes.append(we)
            pulses.append(soft | clear)

    simulate(dut, bench, background=[watch])
    assert got == [((0, RESP_SLVERR), RESP_SLVERR, regs.ERROR_WRITE_REFUSED_MASK, True, True)
                   ] * 21
    assert not any(writes) and not any(pulses)


@pytest.mark.parametrize("strb", [0b0001, 0b0011, 0b0111, 0b1110, 0b1000, 0b0000])
def test_lut_write_needs_every_byte_strobed(strb, cfg):
    """A LUT write with wstrb != 1111 is refused (no write to the LUT port, SLVERR,
    ERROR.write_refused set); the same word with every byte strobed is taken."""
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg)
    entry = cfg.lut_address(cfg.n_moves, 1)
    got = []

    async def bench(ctx):
        addr = regs.LUT_BASE + 4 * entry
        got.append(await axil_write(ctx, dut.axil, addr, 3, strb=strb))
        got.append((await axil_read(ctx, dut.axil, regs.REG_ERROR))[0])
        await axil_write(ctx, dut.axil, regs.REG_ERROR, regs.ERROR_WRITE_REFUSED_MASK)
        got.append(await axil_write(ctx, dut.axil, addr, 3))
        got.append((await axil_read(ctx, dut.axil, regs.REG_ERROR))[0])

    writes = []

    async def watch(ctx):
        async for _clk, _rst, we, addr, value in ctx.tick().sample(
                dut.lut_we, dut.lut_addr, dut.lut_data):
            if we:
                writes.append((addr, value))

    simulate(dut, bench, background=[watch])
    assert got == [RESP_SLVERR, regs.ERROR_WRITE_REFUSED_MASK, RESP_OKAY, 0]
    assert writes == [(entry, 3)]


def test_lut_window_reads_answer_slverr(cfg):
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg)
    got = []

    async def bench(ctx):
        for entry in (0, regs.LUT_ENTRIES - 1):
            addr = regs.LUT_BASE + 4 * entry
            assert await axil_write(ctx, dut.axil, addr, 1) == RESP_OKAY
            got.append(await axil_read(ctx, dut.axil, addr))
        got.append((await axil_read(ctx, dut.axil, regs.REG_ERROR))[0])

    simulate(dut, bench)
    assert got == [(0, RESP_SLVERR), (0, RESP_SLVERR), 0]


def test_pulses_ahead_are_the_next_cycles_pulses(cfg):
    """``pulses_ahead=True``: ``soft_reset_ahead`` and ``clear_counters_ahead`` are high in
    exactly the cycles before ``soft_reset`` and ``clear_counters`` (writes to CONTROL with
    either bit, both, none, a partial strobe, and writes elsewhere)."""
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg, pulses_ahead=True)
    plain = RegisterFile(cfg)
    assert "soft_reset_ahead" not in dict(plain.signature.members)
    Fragment.get(plain, None)

    async def bench(ctx):
        for data, strb in ((1, 0xF), (2, 0xF), (3, 0xF), (0, 0xF), (1, 0xE), (3, 0x1)):
            for order in ("together", "aw_first", "w_first"):
                await axil_write(ctx, dut.axil, regs.REG_CONTROL, data, strb, order=order)
        await axil_write(ctx, dut.axil, regs.REG_CANDIDATE_COUNT, 1)

    trace = []

    async def watch(ctx):
        async for _clk, _rst, *values in ctx.tick().sample(
                dut.soft_reset_ahead, dut.clear_counters_ahead, dut.soft_reset,
                dut.clear_counters):
            trace.append(values)

    simulate(dut, bench, background=[watch])
    ahead = [(s, c) for s, c, _p, _q in trace]
    pulses = [(p, q) for _s, _c, p, q in trace]
    assert ahead[:-1] == pulses[1:]
    assert sum(s for s, _c in ahead) == 9 and sum(c for _s, c in ahead) == 9
