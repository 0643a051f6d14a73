"""``RegisterFile``'s settings and identification through its AXI4-Lite port against the
register map (offsets only from the generated constants): valid values taken, others refused,
byte strobes merged, the build read back, read-only registers refused.

Glasgow's pattern: ``cases()`` yields register writes (valid and refused), ``ref_write``
says what the map implies for one (taken? response? value read back?), ``rtl_write`` does
it on the gateware and reads back."""


from dptbd.hw.axi_lite import RESP_OKAY, RESP_SLVERR
from dptbd.hw.register_file import RegisterFile
from dptbd.hw.register_map import constants_namespace, register_map
from helpers.axil_harness import axil_read, axil_write
from helpers.hw_harness import simulate
from helpers.seg_harness import make_config


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


def test_settings_take_valid_values_and_refuse_others(cfg):
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


def test_identification_reads_the_build_and_refuses_writes(cfg):
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


def test_status_reads_its_port_and_refuses_writes(cfg):
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
