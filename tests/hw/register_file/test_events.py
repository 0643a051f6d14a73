"""``RegisterFile``'s events: pulses, the LUT window and the counters, sticky bits, interrupts
and their mask, and the events port."""


from dptbd.hw.axi_lite import RESP_OKAY, RESP_SLVERR
from dptbd.hw.register_file import RegisterFile, event_port_layout
from dptbd.hw.register_map import EVENTS, constants_namespace
from helpers.axil_harness import axil_read, axil_write
from helpers.hw_harness import simulate


def test_pulses_lut_window_and_counters(cfg):
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg)

    async def bench(ctx):
        seen = []
        ctx.set(dut.events.frame_done, 1)
        for _ in range(3):
            await ctx.tick()
        ctx.set(dut.events.frame_done, 0)
        ctx.set(dut.events.input_stall, 1)
        await ctx.tick()
        ctx.set(dut.events.input_stall, 0)
        assert (await axil_read(ctx, dut.axil, regs.REG_FRAMES))[0] == 3
        assert (await axil_read(ctx, dut.axil, regs.REG_INPUT_STALLS))[0] == 1
        # soft reset: one pulse, the cycle after the write's bus cycle
        await axil_write(ctx, dut.axil, regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK)
        assert (await axil_read(ctx, dut.axil, regs.REG_CONTROL))[0] == 0
        await axil_write(ctx, dut.axil, regs.REG_CONTROL, regs.CONTROL_CLEAR_COUNTERS_MASK)
        assert (await axil_read(ctx, dut.axil, regs.REG_FRAMES))[0] == 0
        # LUT window: entry [p, m] at LUT_BASE + 4 * lut_address(p, m)
        entry = cfg.lut_address(cfg.n_moves, 2)
        assert await axil_write(ctx, dut.axil, regs.LUT_BASE + 4 * entry, 77) == RESP_OKAY
        assert await axil_write(ctx, dut.axil, regs.LUT_BASE, regs.LUT_MAX + 1) == RESP_SLVERR
        assert await axil_read(ctx, dut.axil, regs.LUT_BASE) == (0, RESP_SLVERR)
        error, _ = await axil_read(ctx, dut.axil, regs.REG_ERROR)
        assert error == regs.ERROR_WRITE_REFUSED_MASK
        seen.append("done")

    writes, pulses = [], []

    async def watch(ctx):
        async for _clk, _rst, we, addr, value, soft in ctx.tick().sample(
                dut.lut_we, dut.lut_addr, dut.lut_data, dut.soft_reset):
            if we:
                writes.append((addr, value))
            pulses.append(soft)

    simulate(dut, bench, background=[watch])
    assert writes == [(cfg.lut_address(cfg.n_moves, 2), 77)]
    assert sum(pulses) == 1


def test_sticky_bits_interrupts_and_mask(cfg):
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg)

    async def pulse(ctx, name):
        """``name`` high in one cycle c; its bit is set at the end of c + 1 (the pulses are
        registered), so the bench goes on in c + 2."""
        ctx.set(dut.events[name], 1)
        await ctx.tick()
        ctx.set(dut.events[name], 0)
        await ctx.tick()

    async def bench(ctx):
        ctx.set(dut.events.segment_done, 1)
        await ctx.tick()
        ctx.set(dut.events.segment_done, 0)
        status, _ = await axil_read(ctx, dut.axil, regs.REG_IRQ_STATUS)    # AR in c + 1
        assert status == regs.IRQ_STATUS_SEGMENT_DONE_MASK       # read in c + 2: set
        assert not ctx.get(dut.irq)                              # masked at reset
        await axil_write(ctx, dut.axil, regs.REG_IRQ_ENABLE, regs.IRQ_ENABLE_SEGMENT_DONE_MASK)
        assert ctx.get(dut.irq)                                  # pending and now enabled
        await axil_write(ctx, dut.axil, regs.REG_IRQ_STATUS, regs.IRQ_STATUS_SEGMENT_DONE_MASK)
        assert not ctx.get(dut.irq)
        for name in ("sof_unexpected", "frame_short", "frame_long", "line_length"):
            await pulse(ctx, name)
            assert not ctx.get(dut.irq)                          # fault masked
            mask = getattr(regs, f"ERROR_{name.upper()}_MASK")
            error, _ = await axil_read(ctx, dut.axil, regs.REG_ERROR)
            assert error == mask
            count, _ = await axil_read(ctx, dut.axil, getattr(regs, f"REG_FAULT_{name.upper()}"))
            assert count == 1
            await axil_write(ctx, dut.axil, regs.REG_ERROR, regs.ERROR_RESET | mask)
        status, _ = await axil_read(ctx, dut.axil, regs.REG_IRQ_STATUS)
        assert status == regs.IRQ_STATUS_FAULT_MASK
        await axil_write(ctx, dut.axil, regs.REG_IRQ_ENABLE, regs.IRQ_ENABLE_FAULT_MASK)
        assert ctx.get(dut.irq)
        # a refused write raises the fault interrupt too, after clearing it
        await axil_write(ctx, dut.axil, regs.REG_IRQ_STATUS, regs.IRQ_STATUS_FAULT_MASK)
        assert not ctx.get(dut.irq)
        await axil_write(ctx, dut.axil, regs.REG_HISTOGRAM_SHIFT, 99)
        assert ctx.get(dut.irq)

    simulate(dut, bench)


def test_events_port_lists_every_event():
    assert [name for name, _ in event_port_layout()] == list(EVENTS)
