"""AXI4-Stream video adapters: ``AxisToPixels`` and ``CandidatesToAxis``.

``ref_*`` say what each beat must carry (the layouts' own pack/unpack), ``rtl_*`` run the
adapters with random ``tvalid`` gaps and ``tready`` back-pressure.
"""

import random

from amaranth.sim import Simulator

from dptbd.hw.axis_video import AxisToPixels, CandidatesToAxis, byte_padded
from dptbd.hw.candidate_layout import pack_record, pack_trailer
from dptbd.hw.layouts import pack_pixel
from hw_harness import simulate
from seg_harness import make_config


def config():
    return make_config(width=8, height=6, input_bits=10, candidate_count=3)


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


def ref_candidate_beats(words):
    """(tdata, tuser, tlast) per word: tuser[0] on a list's first word, tlast on trailers."""
    out, start = [], 1
    for word, trailer in words:
        out.append((word, start, trailer))
        start = trailer
    return out


def rtl_candidate_beats(cfg, words, seed=1):
    dut = CandidatesToAxis(cfg)
    rng = random.Random(seed)
    got, stalls = [], []

    async def source(ctx):
        for word, _trailer in words:
            ctx.set(dut.candidates.payload.as_value(), word)
            ctx.set(dut.candidates.valid, 1)
            await ctx.tick().until(dut.candidates.ready)
            ctx.set(dut.candidates.valid, 0)
            while rng.random() < 0.3:
                await ctx.tick()

    async def sink(ctx):
        while len(got) < len(words):
            ready = rng.random() < 0.6
            ctx.set(dut.cand.tready, ready)
            stalls.append(ctx.get(dut.stalled))
            assert stalls[-1] == (ctx.get(dut.cand.tvalid) and not ready)
            if ready and ctx.get(dut.cand.tvalid):
                got.append((ctx.get(dut.cand.tdata), ctx.get(dut.cand.tuser),
                            ctx.get(dut.cand.tlast)))
            await ctx.tick()

    simulate(dut, source, sink)
    return got, sum(stalls)


def test_candidates_out_marks_list_start_and_trailer():
    cfg = config()
    trailer = dict(count=2, threshold=3, overflow=0, primed=1, aligned=1, missed=0)
    empty = dict(trailer, count=0)
    words = [(pack_record(cfg, 1, 2, 300, 4), 0), (pack_record(cfg, 5, 7, 9, 9), 0),
             (pack_trailer(cfg, **trailer), 1), (pack_trailer(cfg, **empty), 1),
             (pack_record(cfg, 0, 0, 1, 0), 0), (pack_trailer(cfg, **dict(trailer, count=1)), 1)]
    want = ref_candidate_beats(words)
    assert [w[1] for w in want] == [1, 0, 0, 1, 1, 0]          # the empty list: one beat
    got, stalls = rtl_candidate_beats(cfg, words)
    assert got == want
    assert stalls > 0                                           # back-pressure was exercised
