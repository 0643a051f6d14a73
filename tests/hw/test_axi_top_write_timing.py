"""Which beat an AXI4-Lite write applies to (``docs/integration.md``, "When a write takes
effect"), on ``AXITop`` in the Amaranth simulator, scored against the golden model.

The rule: a write takes effect in the first cycle its response is offered (``bvalid`` high,
two cycles after the last of its AW / W handshakes). A weight LUT code is used by every beat
accepted in that cycle or later and by none accepted before; a K / n / s setting applies to
the first segment whose first beat is accepted in that cycle or later. Each case offers the
decisive beat once in that cycle and once in the cycle before, and checks both streams
(every ``m_axis_state`` word and every list word) against the model with the write placed
just before that beat and just after it; the two models are asserted to differ, so the
boundary is pinned to the cycle.
"""

import numpy as np
import pytest

from dptbd.hw.axi_top import AXITop
from dptbd.hw.register_map import constants_namespace
from dptbd.hw.layouts import pack_states
from dptbd.sim.axi.stimulus import clean_beats, expected_outputs
from dptbd.sim.candidate_scoreboard import list_words
from helpers.axil_harness import flat_axil, simulate_top
from helpers.seg_harness import make_config

#: Idle cycles after the last beat: the pipeline's latency, the last list and its scan.
DRAIN = 120


def config():
    """6 x 5, K = 2 at reset and K_max = 3 (segments of 60 beats), 16 histogram bins."""
    return make_config(width=6, height=5, segment_frames=2, max_segment_frames=3,
                       candidate_count=2, histogram_bits=4)


def run_rtl(cfg, beats, at: int, address: int, value: int, same_cycle: bool):
    """Stream ``beats`` (``tvalid`` held high, both outputs always ready) with one write of
    ``value`` to ``address`` issued while the input waits after beat ``at - 1``; beat ``at``
    is accepted in the first cycle of ``bvalid`` (``same_cycle``) or in the cycle before.
    Returns the ``m_axis_cand`` words and the ``m_axis_state`` words packed as the model's
    ``states`` words."""
    top = AXITop(cfg, state_output=True)
    axil = flat_axil(top)
    cand, states = [], []

    async def collect(ctx):
        e_mask = (1 << cfg.energy_bits) - 1
        async for _clk, _rst, *v in ctx.tick("sync").sample(
                top.m_axis_cand_tvalid, top.m_axis_cand_tdata, top.m_axis_state_tvalid,
                top.m_axis_state_tdata, top.m_axis_state_tuser, top.m_axis_state_tlast):
            c_valid, c_data, s_valid, s_data, s_user, s_last = v
            if c_valid:
                cand.append(int(c_data))
            if s_valid:
                states.append(int(pack_states(
                    cfg, energy=np.array(s_data & e_mask),
                    direction=np.array(s_data >> cfg.energy_bits),
                    end_of_line=np.array(s_last), end_of_frame=np.array((s_user >> 1) & 1),
                    end_of_segment=np.array((s_user >> 2) & 1))))

    async def offer(ctx, j):
        ctx.set(top.s_axis_video_tdata, int(beats.pixel[j]))
        ctx.set(top.s_axis_video_tuser, int(beats.first[j]))
        ctx.set(top.s_axis_video_tlast, int(beats.last[j]))
        ctx.set(top.s_axis_video_tvalid, 1)

    async def bench(ctx):
        ctx.set(top.aresetn, 0)
        ctx.set(top.m_axis_cand_tready, 1)
        ctx.set(top.m_axis_state_tready, 1)
        await ctx.tick("sync")
        ctx.set(top.aresetn, 1)
        for j in range(len(beats)):
            if j == at:
                ctx.set(top.s_axis_video_tvalid, 0)
                ctx.set(axil.aw.awaddr, address)
                ctx.set(axil.w.wdata, value)
                ctx.set(axil.w.wstrb, 0xF)
                ctx.set(axil.aw.awvalid, 1)
                ctx.set(axil.w.wvalid, 1)
                assert ctx.get(axil.aw.awready) and ctx.get(axil.w.wready)
                await ctx.tick("sync")                       # cycle t: both handshakes
                ctx.set(axil.aw.awvalid, 0)
                ctx.set(axil.w.wvalid, 0)
                assert not ctx.get(axil.b.bvalid)            # cycle t + 1
                if not same_cycle:
                    await offer(ctx, j)
                    assert ctx.get(top.s_axis_video_tready)
                    await ctx.tick("sync")
                    ctx.set(top.s_axis_video_tvalid, 0)
                else:
                    await ctx.tick("sync")
                assert ctx.get(axil.b.bvalid)                # cycle t + 2: the response
                ctx.set(axil.b.bready, 1)
                if same_cycle:
                    await offer(ctx, j)
                    assert ctx.get(top.s_axis_video_tready)
                await ctx.tick("sync")
                ctx.set(axil.b.bready, 0)
                continue
            await offer(ctx, j)
            while not ctx.get(top.s_axis_video_tready):
                await ctx.tick("sync")
            await ctx.tick("sync")
        ctx.set(top.s_axis_video_tvalid, 0)
        await ctx.tick("sync").repeat(DRAIN)

    simulate_top(top, bench, collect)
    return cand, states


def expected(cfg, beats, at: int, step: dict):
    """The model's list words and ``states`` words with ``step`` (writes or LUT codes)
    placed just before beat ``at``."""
    exp = expected_outputs(cfg, beats, [{"stop": at}, {**step, "stop": len(beats)}])
    return [w for words in list_words(cfg, exp.lists) for w in words], \
        [int(w) for w in exp.state_words]


def check(cfg, beats, at, address, value, step):
    want = {same: expected(cfg, beats, at if same else at + 1, step) for same in (True, False)}
    assert want[True] != want[False]                 # the boundary is observable
    for same in (True, False):
        cand, states = run_rtl(cfg, beats, at, address, value, same)
        assert states == want[same][1], f"states, beat accepted with bvalid: {same}"
        assert cand == want[same][0], f"lists, beat accepted with bvalid: {same}"


def test_a_setting_applies_to_the_segment_whose_first_beat_comes_with_its_response():
    """K written 3 (reset 2): the segment starting at beat 60 has 3 frames when its first
    beat is accepted in the write's first bvalid cycle, 2 (and the next one 3) when it is
    accepted the cycle before."""
    cfg = config()
    regs = constants_namespace(cfg)
    frames = np.random.default_rng(5).integers(0, 256, (8, cfg.height, cfg.width))
    beats = clean_beats(frames)
    check(cfg, beats, 60, regs.REG_SEGMENT_FRAMES, 3,
          {"writes": [("SEGMENT_FRAMES", 3)]})


def test_a_lut_code_applies_from_the_beat_accepted_with_its_response():
    """One weight LUT entry [START, m] set to 0 in the middle of a segment's second frame:
    used from the beat accepted in the write's first bvalid cycle, not by the one before
    (m: the first move for which that beat's own state changes)."""
    cfg = config()
    regs = constants_namespace(cfg)
    frames = np.random.default_rng(6).integers(0, 256, (4, cfg.height, cfg.width))
    beats = clean_beats(frames)
    at = cfg.width * cfg.height + 2 * cfg.width + 3            # frame 1, row 2, column 3
    for move in range(cfg.n_moves):
        codes = cfg.weight_codes.copy()
        codes[cfg.start_code, move] = 0
        step = {"lut_codes": codes}
        if expected(cfg, beats, at, step)[1][at] != expected(cfg, beats, at + 1, step)[1][at]:
            break
    else:
        pytest.fail("no single LUT entry changes the decisive beat's state")
    check(cfg, beats, at, regs.LUT_BASE + 4 * cfg.lut_address(cfg.start_code, move), 0, step)
