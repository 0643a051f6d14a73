"""``RegisterFile`` of the build with the state store in external memory (``--state-store
axi``): STATE_BASE takes aligned addresses with room for the frame, the state errors are
sticky, counted and raise the fault interrupt."""

import pytest

from dptbd.hw.axi_lite import RESP_OKAY, RESP_SLVERR
from dptbd.hw.register_file import RegisterFile, event_port_layout
from dptbd.hw.register_map import EVENTS, constants_namespace, register_map
from helpers.axil_harness import axil_read, axil_write
from helpers.hw_harness import simulate


@pytest.fixture
def store(cfg):
    """A store of bursts of 4 x 8 bytes = 32 and 12 address bits (4 KiB) for an 8 x 6 frame
    of 32-bit slots (192 bytes): STATE_BASE in [0, 3904], multiples of 32."""
    return cfg.axi_store(data_bits=64, burst_beats=4, address_bits=12)


def state_base_cases(regs):
    top = regs.STATE_BASE_STATE_BASE_MAX
    yield from (0, 32, top, 64 + 8, 1, top + 32, 4096, 2**32 - 32, 2**32 - 1, 4064)


def ref_state_base(regs, value, before, burst):
    """(response, value read back, write_refused set) of writing STATE_BASE."""
    if value % burst == 0 and value <= regs.STATE_BASE_STATE_BASE_MAX:
        return RESP_OKAY, value, False
    return RESP_SLVERR, before, True


def rtl_state_base(store, values):
    cfg = store.frame
    dut = RegisterFile(cfg, register_map(cfg, store))
    regs = constants_namespace(cfg, store)
    got = []

    async def bench(ctx):
        for value in values:
            resp = await axil_write(ctx, dut.axil, regs.REG_STATE_BASE, value)
            back, _ = await axil_read(ctx, dut.axil, regs.REG_STATE_BASE)
            error, _ = await axil_read(ctx, dut.axil, regs.REG_ERROR)
            await axil_write(ctx, dut.axil, regs.REG_ERROR, error)        # W1C
            assert ctx.get(dut.state_base) == back
            got.append((resp, back, bool(error & regs.ERROR_WRITE_REFUSED_MASK)))

    simulate(dut, bench)
    return got


def test_state_base_takes_aligned_addresses_with_room_for_the_frame(store):
    regs = constants_namespace(store.frame, store)
    assert (regs.STATE_BASE_STATE_BASE_MIN, regs.STATE_BASE_STATE_BASE_MAX) == (0, 3904)
    assert store.frame_bytes == 192
    want, current = [], store.base_address
    for value in state_base_cases(regs):
        want.append(ref_state_base(regs, value, current, store.burst_bytes))
        current = want[-1][1]
    assert [w[0] for w in want].count(RESP_SLVERR) == 7
    assert rtl_state_base(store, list(state_base_cases(regs))) == want


def test_state_errors_are_sticky_counted_and_raise_the_fault_interrupt(store):
    cfg = store.frame
    dut = RegisterFile(cfg, register_map(cfg, store))
    regs = constants_namespace(cfg, store)
    assert dut.events.shape() == event_port_layout((*EVENTS, "state_read_error",
                                                     "state_write_error"))

    async def bench(ctx):
        await axil_write(ctx, dut.axil, regs.REG_IRQ_ENABLE, regs.IRQ_ENABLE_FAULT_MASK)
        ctx.set(dut.state_base_active, 0x1E0)
        assert (await axil_read(ctx, dut.axil, regs.REG_STATE_BASE_ACTIVE))[0] == 0x1E0
        for event, bit, counter, times in (
                ("state_read_error", "STATE_READ", "STATE_READ_ERRORS", 3),
                ("state_write_error", "STATE_WRITE", "STATE_WRITE_ERRORS", 2)):
            assert not ctx.get(dut.irq)
            ctx.set(dut.events[event], 1)
            for _ in range(times):
                await ctx.tick()
            ctx.set(dut.events[event], 0)
            assert ctx.get(dut.irq)                              # the fault interrupt
            mask = getattr(regs, f"ERROR_{bit}_MASK")
            assert (await axil_read(ctx, dut.axil, regs.REG_ERROR))[0] == mask
            assert (await axil_read(ctx, dut.axil, getattr(regs, f"REG_{counter}")))[0] == times
            await axil_write(ctx, dut.axil, regs.REG_ERROR, mask)
            await axil_write(ctx, dut.axil, regs.REG_IRQ_STATUS, regs.IRQ_STATUS_FAULT_MASK)
            assert (await axil_read(ctx, dut.axil, regs.REG_ERROR))[0] == 0
        await axil_write(ctx, dut.axil, regs.REG_CONTROL, regs.CONTROL_CLEAR_COUNTERS_MASK)
        assert (await axil_read(ctx, dut.axil, regs.REG_STATE_READ_ERRORS))[0] == 0
        assert await axil_write(ctx, dut.axil, regs.REG_STATE_BASE_ACTIVE, 0) == RESP_SLVERR

    simulate(dut, bench)
