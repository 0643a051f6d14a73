"""``AxisToPixels``: the AXI4-Stream video input, and the byte padding of ``tdata``."""

from amaranth.sim import Simulator

from dptbd.hw.axis_video import AxisToPixels, byte_padded
from dptbd.hw.layouts import pack_pixel
from helpers.axis_harness import config


def test_byte_padded():
    assert [byte_padded(b) for b in (1, 8, 9, 16, 17)] == [8, 8, 16, 16, 24]


def test_video_in_maps_tuser0_and_low_tdata_bits():
    cfg = config()
    dut = AxisToPixels(cfg)
    beats = [(p, s) for p, s in zip([5, 1023, 0, 77], [1, 0, 0, 1])]
    got = []

    async def bench(ctx):
        ctx.set(dut.pixels.ready, 1)
        for pixel, sof in beats:
            ctx.set(dut.video.tdata, pixel | 0xF000)            # bits above B_in ignored
            ctx.set(dut.video.tuser, sof)
            ctx.set(dut.video.tvalid, 1)
            assert ctx.get(dut.video.tready) and ctx.get(dut.accepted)
            got.append(ctx.get(dut.pixels.payload.as_value()))
            await ctx.delay(1e-8)
        ctx.set(dut.pixels.ready, 0)
        assert not ctx.get(dut.video.tready) and not ctx.get(dut.accepted)

    sim = Simulator(dut)                                         # combinational: no clock
    sim.add_testbench(bench)
    sim.run()
    assert got == [pack_pixel(cfg, p, s) for p, s in beats]
