"""AXI4-Stream video adapters: ``AxisToPixels``, ``CandidatesToAxis`` and ``StatesToAxis``.

``ref_*`` say what each beat must carry (the layouts' own pack/unpack), ``rtl_*`` run the
adapters with random ``tvalid`` gaps and ``tready`` back-pressure.
"""

import random

from amaranth.sim import Simulator

from dptbd.hw.axis_video import (STATE_TUSER, AxisToPixels, CandidatesToAxis, StatesToAxis,
                                 byte_padded)
from dptbd.hw.candidate_layout import pack_record, pack_trailer
from dptbd.hw.layouts import pack_pixel, pack_state_word, pack_states
from helpers.hw_harness import simulate
from helpers.seg_harness import make_config


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


def rtl_adapter_beats(dut, inp, out, payloads, seed):
    """Feed ``payloads`` to ``inp`` with random gaps, take ``out`` with random back-pressure:
    the (tdata, tuser, tlast) of each transfer and the cycles ``dut.stalled`` was high
    (checked against tvalid and not tready in every cycle)."""
    rng = random.Random(seed)
    got, stalls = [], []

    async def source(ctx):
        for payload in payloads:
            ctx.set(inp.payload.as_value(), payload)
            ctx.set(inp.valid, 1)
            await ctx.tick().until(inp.ready)
            ctx.set(inp.valid, 0)
            while rng.random() < 0.3:
                await ctx.tick()

    async def sink(ctx):
        while len(got) < len(payloads):
            ready = rng.random() < 0.6
            ctx.set(out.tready, ready)
            stalls.append(ctx.get(dut.stalled))
            assert stalls[-1] == (ctx.get(out.tvalid) and not ready)
            if ready and ctx.get(out.tvalid):
                got.append((ctx.get(out.tdata), ctx.get(out.tuser), ctx.get(out.tlast)))
            await ctx.tick()

    simulate(dut, source, sink)
    return got, sum(stalls)


def rtl_candidate_beats(cfg, words, seed=1):
    dut = CandidatesToAxis(cfg)
    return rtl_adapter_beats(dut, dut.candidates, dut.cand, [w for w, _ in words], seed)


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


def state_cases(cfg):
    """Two frames of two lines of three pixels, the second ending a segment (the adapter
    only follows the flags, so the frame need not be the configuration's W x H)."""
    words = []
    for frame in range(2):
        for i in range(6):
            words.append(dict(energy=100 * frame + 7 * i, direction=i % cfg.n_moves,
                              end_of_line=int(i % 3 == 2), end_of_frame=int(i == 5),
                              end_of_segment=int(frame == 1 and i == 5)))
    return words


def ref_state_beats(cfg, words):
    """(tdata, tuser, tlast) per word: (E, d) as a state word; tuser = start of frame,
    end of frame, end of segment; tlast = end of line."""
    out, start = [], 1
    for w in words:
        user = (start << STATE_TUSER["start_of_frame"]
                | w["end_of_frame"] << STATE_TUSER["end_of_frame"]
                | w["end_of_segment"] << STATE_TUSER["end_of_segment"])
        out.append((pack_state_word(cfg, w["energy"], w["direction"]), user, w["end_of_line"]))
        start = w["end_of_frame"]
    return out


def rtl_state_beats(cfg, words, seed=3):
    dut = StatesToAxis(cfg)
    return rtl_adapter_beats(dut, dut.states, dut.state,
                             [int(pack_states(cfg, **w)) for w in words], seed)


def test_states_out_flags_frames_lines_and_segments():
    cfg = config()
    words = state_cases(cfg)
    want = ref_state_beats(cfg, words)
    assert [w[1] & 1 for w in want] == [1, 0, 0, 0, 0, 0] * 2
    got, stalls = rtl_state_beats(cfg, words)
    assert got == want and stalls > 0
