"""``RegisterFile`` through its AXI4-Lite port against the register map (offsets only from
the generated constants).

Glasgow's pattern: ``cases()`` yields register writes (valid and refused), ``ref_write``
says what the map implies for one (taken? response? value read back?), ``rtl_write`` does
it on the gateware and reads back.
"""

import pytest

from dptbd.hw.axi_lite import RESP_OKAY, RESP_SLVERR
from dptbd.hw.register_file import RegisterFile, event_port_layout
from dptbd.hw.register_map import EVENTS, constants_namespace, register_map
from helpers.axil_harness import axil_read, axil_write
from helpers.hw_harness import simulate
from helpers.seg_harness import make_config


def config():
    return make_config(width=8, height=6, candidate_count=5, histogram_bits=4)


def cases(regs):
    """(register, value) writes: in range, at both ends, just outside, far outside."""
    yield from [("SEGMENT_FRAMES", v) for v in (1, regs.SEGMENT_FRAMES_SEGMENT_FRAMES_MAX,
                                                0, regs.SEGMENT_FRAMES_SEGMENT_FRAMES_MAX + 1,
                                                1 << 20)]
    yield from [("CANDIDATE_COUNT", v) for v in (0, 3, regs.CANDIDATE_COUNT_CANDIDATE_COUNT_MAX,
                                                 regs.CANDIDATE_COUNT_CANDIDATE_COUNT_MAX + 1,
                                                 1 << 31)]
    yield from [("HISTOGRAM_SHIFT", v) for v in (0, regs.HISTOGRAM_SHIFT_HISTOGRAM_SHIFT_MAX,
                                                 regs.HISTOGRAM_SHIFT_HISTOGRAM_SHIFT_MAX + 1)]
    yield from [("VIDEO_INPUT", v) for v in (1, 0, 2, 1, 3)]


#: The port of each setting register (named after its field).
PORTS = {"SEGMENT_FRAMES": "segment_frames", "CANDIDATE_COUNT": "candidate_count",
         "HISTOGRAM_SHIFT": "histogram_shift", "VIDEO_INPUT": "no_sof"}


def ref_write(regs, reg, value, before):
    """(response, value read back, write_refused set) of writing ``value``."""
    lo, hi = (getattr(regs, f"{reg}_{PORTS[reg].upper()}_{end}") for end in ("MIN", "MAX"))
    if lo <= value <= hi:
        return RESP_OKAY, value, False
    return RESP_SLVERR, before, True


def rtl_write(cfg, writes):
    dut = RegisterFile(cfg)
    regs = constants_namespace(cfg)
    got = []

    async def bench(ctx):
        for reg, value in writes:
            addr = getattr(regs, f"REG_{reg}")
            resp = await axil_write(ctx, dut.axil, addr, value)
            back, _ = await axil_read(ctx, dut.axil, addr)
            error, _ = await axil_read(ctx, dut.axil, regs.REG_ERROR)
            refused = bool(error & regs.ERROR_WRITE_REFUSED_MASK)
            await axil_write(ctx, dut.axil, regs.REG_ERROR, error)        # W1C
            port = ctx.get(getattr(dut, PORTS[reg]))
            assert port == back, (reg, port, back)
            got.append((resp, back, refused))

    simulate(dut, bench)
    return got


def test_settings_take_valid_values_and_refuse_others():
    cfg = config()
    regs = constants_namespace(cfg)
    writes = list(cases(regs))
    want, current = [], {"SEGMENT_FRAMES": cfg.segment_frames,
                         "CANDIDATE_COUNT": cfg.n_candidates, "HISTOGRAM_SHIFT": cfg.bin_shift,
                         "VIDEO_INPUT": 0}
    for reg, value in writes:
        want.append(ref_write(regs, reg, value, current[reg]))
        current[reg] = want[-1][1]
    assert sum(w[2] for w in want) == 8
    assert rtl_write(cfg, writes) == want


def test_identification_reads_the_build_and_refuses_writes():
    cfg = config()
    regmap = register_map(cfg)
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg)

    async def bench(ctx):
        for reg in regmap.registers:
            data, resp = await axil_read(ctx, dut.axil, reg.address)
            assert (data, resp) == (getattr(regs, f"{reg.name}_RESET"), RESP_OKAY), reg.name
        assert (await axil_read(ctx, dut.axil, regs.REG_ID))[0] == regs.MAGIC == 0x44505442
        frame, _ = await axil_read(ctx, dut.axil, regs.REG_BUILD_FRAME)
        assert (frame & regs.BUILD_FRAME_HEIGHT_MASK) >> regs.BUILD_FRAME_HEIGHT_SHIFT == 6
        assert await axil_write(ctx, dut.axil, regs.REG_BUILD_FRAME, 0) == RESP_SLVERR
        assert (await axil_read(ctx, dut.axil, regs.REG_BUILD_FRAME))[0] == frame
        assert await axil_write(ctx, dut.axil, regs.REG_FRAMES, 5) == RESP_SLVERR
        # unmapped: between groups and past the LUT window
        for addr in (regs.REG_BUILD_LUT + 4, regs.LUT_BASE + 4 * regs.LUT_ENTRIES, 0xFFC):
            assert await axil_read(ctx, dut.axil, addr) == (0, RESP_SLVERR)
            assert await axil_write(ctx, dut.axil, addr, 1) == RESP_SLVERR
        error, _ = await axil_read(ctx, dut.axil, regs.REG_ERROR)
        assert error == 0                       # only out-of-range values set write_refused

    simulate(dut, bench)


def test_write_strobes_merge_bytes():
    cfg = make_config(width=32, height=32, candidate_count=300)        # C = 600
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg)

    async def bench(ctx):
        addr = regs.REG_CANDIDATE_COUNT
        assert await axil_write(ctx, dut.axil, addr, 0x0203, strb=0b0010) == RESP_OKAY
        assert (await axil_read(ctx, dut.axil, addr))[0] == 0x022C     # byte 1 of 300 -> 2
        assert await axil_write(ctx, dut.axil, addr, 0x0300, strb=0b0010) == RESP_SLVERR
        assert (await axil_read(ctx, dut.axil, addr))[0] == 0x022C     # 0x32C > 600 refused

    simulate(dut, bench)


def test_pulses_lut_window_and_counters():
    cfg = config()
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


def test_sticky_bits_interrupts_and_mask():
    cfg = config()
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


@pytest.mark.parametrize("order", ["together", "aw_first", "w_first"])
def test_axi_lite_one_transaction_at_a_time(order):
    """Any AW/W order, a late bready, and a read queued behind a write: one transaction at
    a time, the write first."""
    cfg = config()
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


def test_events_port_lists_every_event():
    assert [name for name, _ in event_port_layout()] == list(EVENTS)


def test_unaligned_accesses_are_refused():
    """Every address that is not a multiple of 4 (a register, the LUT window, an unmapped
    word): a read answers 0 with SLVERR; a write answers SLVERR, changes nothing and sets
    ERROR.write_refused (cleared by W1C between the writes)."""
    cfg = config()
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
def test_lut_write_needs_every_byte_strobed(strb):
    """A LUT write with wstrb != 1111 is refused (no write to the LUT port, SLVERR,
    ERROR.write_refused set); the same word with every byte strobed is taken."""
    cfg = config()
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


def test_lut_window_reads_answer_slverr():
    cfg = config()
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


def test_status_reads_its_port_and_refuses_writes():
    cfg = config()
    regs = constants_namespace(cfg)
    dut = RegisterFile(cfg)
    got = []

    async def bench(ctx):
        for busy in (1, 0):
            ctx.set(dut.soft_reset_busy, busy)
            got.append(await axil_read(ctx, dut.axil, regs.REG_STATUS))
        got.append(await axil_write(ctx, dut.axil, regs.REG_STATUS, 1))
        got.append((await axil_read(ctx, dut.axil, regs.REG_ERROR))[0])

    simulate(dut, bench)
    assert got == [(regs.STATUS_SOFT_RESET_BUSY_MASK, RESP_OKAY), (0, RESP_OKAY), RESP_SLVERR, 0]


# ---- the build with the state store in external memory (--state-store axi) -------------

def store_config():
    """A store of bursts of 4 x 8 bytes = 32 and 12 address bits (4 KiB) for an 8 x 6 frame
    of 32-bit slots (192 bytes): STATE_BASE in [0, 3904], multiples of 32."""
    return config().axi_store(data_bits=64, burst_beats=4, address_bits=12)


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


def test_state_base_takes_aligned_addresses_with_room_for_the_frame():
    store = store_config()
    regs = constants_namespace(store.frame, store)
    assert (regs.STATE_BASE_STATE_BASE_MIN, regs.STATE_BASE_STATE_BASE_MAX) == (0, 3904)
    assert store.frame_bytes == 192
    want, current = [], store.base_address
    for value in state_base_cases(regs):
        want.append(ref_state_base(regs, value, current, store.burst_bytes))
        current = want[-1][1]
    assert [w[0] for w in want].count(RESP_SLVERR) == 7
    assert rtl_state_base(store, list(state_base_cases(regs))) == want


def test_state_errors_are_sticky_counted_and_raise_the_fault_interrupt():
    store = store_config()
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
