"""``AXITop`` in the Amaranth simulator: flat AXI port names, identification over the flat
AXI4-Lite port, ``aresetn``, input-stall counting, the soft reset's hold-off cycle and its
close of an open list or state line.
(Whole scenes are scored by the cocotb tests, ``tests/sim/benches/test_axi.py``.)"""


import numpy as np
import pytest
from amaranth.hdl import Fragment
from amaranth.lib.wiring import In, Out

from dptbd.hw.axi_lite import RESP_OKAY, RESP_SLVERR
from dptbd.hw.axi_top import AXITop
from dptbd.hw.axis_video import STATE_TUSER
from dptbd.hw.layouts import pack_states
from dptbd.sim.stream_model import expected_stream
from dptbd.hw.register_map import constants_namespace
from helpers.axil_harness import axil_read, axil_write, flat_axil, simulate_top
from helpers.dp16kd_model import model_dp16kd_cells
from helpers.seg_harness import make_config


def config():
    return make_config(width=8, height=6, candidate_count=2)


def test_ports_carry_axi_names():
    top = AXITop(config())
    names = [path[0] for path, _m, _v in top.signature.flatten(top)]
    assert names[:2] == ["aclk", "aresetn"] and names[-1] == "irq"
    assert {"s_axis_video_tuser", "m_axis_cand_tlast", "s_axil_bresp",
            "s_axil_wstrb"} <= set(names)
    assert not [n for n in names if "__" in n]
    Fragment.get(top, None)                        # elaborates: no UnusedElaboratable warning


def test_identification_stalls_and_soft_reset():
    """After ``aresetn`` the core takes no pixel for one cycle; a soft reset adds its own
    pulse cycle and its (registered) restart cycle before that one: with ``tvalid`` held
    high across it, three stall cycles are counted, and the start-of-frame beat is then
    taken without a fault."""
    cfg = config()
    regs = constants_namespace(cfg)
    top = AXITop(cfg)
    axil = flat_axil(top)
    low = []

    async def bench(ctx):
        ctx.set(top.aresetn, 0)
        await ctx.tick("sync")
        ctx.set(top.aresetn, 1)
        assert ctx.get(top.s_axis_video_tready) == 0
        await ctx.tick("sync")
        assert ctx.get(top.s_axis_video_tready) == 1
        assert await axil_read(ctx, axil, regs.REG_ID) == (regs.MAGIC, RESP_OKAY)
        ctx.set(top.s_axis_video_tuser, 1)
        ctx.set(top.s_axis_video_tvalid, 0)
        await axil_write(ctx, axil, regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK)
        ctx.set(top.s_axis_video_tvalid, 1)             # offered from now on
        while not ctx.get(top.s_axis_video_tready):
            low.append(1)
            await ctx.tick("sync")
        await ctx.tick("sync")                           # accepted here
        ctx.set(top.s_axis_video_tvalid, 0)
        stalls, _ = await axil_read(ctx, axil, regs.REG_INPUT_STALLS)
        assert stalls == len(low)
        error, _ = await axil_read(ctx, axil, regs.REG_ERROR)
        assert error == 0

    simulate_top(top, bench)
    # the restart cycle and the core's post-reset cycle; the pulse ended in axil_write
    assert len(low) == 2


def test_soft_reset_pulse_holds_tready_low():
    """The cycle of the soft-reset pulse itself has tready low (tvalid offered throughout
    the write: the pulse cycle, the restart cycle and the core's post-reset cycle are all
    stalls)."""
    cfg = config()
    regs = constants_namespace(cfg)
    top = AXITop(cfg)
    axil = flat_axil(top)

    async def bench(ctx):
        ctx.set(top.aresetn, 0)
        await ctx.tick("sync")
        ctx.set(top.aresetn, 1)
        await ctx.tick("sync")
        await axil_write(ctx, axil, regs.REG_CONTROL, regs.CONTROL_CLEAR_COUNTERS_MASK)
        ctx.set(top.s_axis_video_tuser, 1)
        ctx.set(top.s_axis_video_tvalid, 1)              # accepted at once, then idle beats
        await ctx.tick("sync")
        ctx.set(top.s_axis_video_tuser, 0)
        ctx.set(top.s_axis_video_tvalid, 0)
        await axil_write(ctx, axil, regs.REG_CONTROL, regs.CONTROL_CLEAR_COUNTERS_MASK)
        ctx.set(top.s_axis_video_tuser, 1)               # a new frame start, offered during
        ctx.set(top.s_axis_video_tvalid, 1)              # the soft-reset write
        await axil_write(ctx, axil, regs.REG_CONTROL, regs.CONTROL_SOFT_RESET_MASK)
        while not ctx.get(top.s_axis_video_tready):
            await ctx.tick("sync")
        await ctx.tick("sync")
        ctx.set(top.s_axis_video_tvalid, 0)
        stalls, _ = await axil_read(ctx, axil, regs.REG_INPUT_STALLS)
        assert stalls == 3
        error, _ = await axil_read(ctx, axil, regs.REG_ERROR)
        assert error == regs.ERROR_SOF_UNEXPECTED_MASK     # before the reset: mid-frame

    simulate_top(top, bench)


async def send_beats(ctx, top, beats):
    """Offer ``(pixel, first, last)`` beats back to back until each is taken."""
    for pixel, first, last in beats:
        ctx.set(top.s_axis_video_tdata, pixel)
        ctx.set(top.s_axis_video_tuser, first)
        ctx.set(top.s_axis_video_tlast, last)
        ctx.set(top.s_axis_video_tvalid, 1)
        taken = False
        while not taken:
            taken = ctx.get(top.s_axis_video_tready)
            await ctx.tick("sync")
    ctx.set(top.s_axis_video_tvalid, 0)


def test_source_without_start_of_frame_markers():
    """Frames with tlast but never tuser[0]: each frame start is a frame_long fault
    (ERROR.frame_long set) unless VIDEO_INPUT.no_sof is 1; then no error at all."""
    cfg = config()
    regs = constants_namespace(cfg)
    frame = [(7, 0, int(c == cfg.width - 1)) for _r in range(cfg.height)
             for c in range(cfg.width)]
    got = {}

    for no_sof in (0, 1):
        top = AXITop(cfg)
        axil = flat_axil(top)

        async def bench(ctx, top=top, axil=axil, no_sof=no_sof):
            await ctx.tick("sync")
            ctx.set(top.aresetn, 1)
            ctx.set(top.m_axis_cand_tready, 1)
            if no_sof:
                assert await axil_write(ctx, axil, regs.REG_VIDEO_INPUT, 1) == RESP_OKAY
            await send_beats(ctx, top, frame * 3)
            for _ in range(4):
                await ctx.tick("sync")
            got[no_sof] = [(await axil_read(ctx, axil, getattr(regs, f"REG_{name}")))[0]
                           for name in ("ERROR", "FAULT_FRAME_LONG", "FAULT_LINE_LENGTH")]

        simulate_top(top, bench)
    assert got == {0: [regs.ERROR_FRAME_LONG_MASK, 3, 0], 1: [0, 0, 0]}


def test_soft_reset_waits_for_the_word_offered_and_shows_busy():
    """K = 1: the first (empty, unprimed) list's only word is offered with tready held low;
    a soft reset then keeps it offered, unchanged, holds the input and reads
    STATUS.soft_reset_busy = 1 for as long as tready stays low; once the word is taken
    (a whole list: tlast, no cut trailer follows) the core is reset, the bit reads 0 and
    the input is taken again. STATUS is read-only (a write answers SLVERR)."""
    cfg = make_config(width=8, height=6, segment_frames=1, candidate_count=2)
    regs = constants_namespace(cfg)
    top = AXITop(cfg)
    axil = flat_axil(top)
    frame = [(9, int(i == 0), int(i % cfg.width == cfg.width - 1))
             for i in range(cfg.width * cfg.height)]
    seen = {}

    async def bench(ctx):
        await ctx.tick("sync")
        ctx.set(top.aresetn, 1)
        await send_beats(ctx, top, frame)
        while not ctx.get(top.m_axis_cand_tvalid):
            await ctx.tick("sync")
        word = ctx.get(top.m_axis_cand_tdata)
        assert ctx.get(top.m_axis_cand_tlast) and ctx.get(top.m_axis_cand_tuser)
        assert await axil_read(ctx, axil, regs.REG_STATUS) == (0, RESP_OKAY)
        assert await axil_write(ctx, axil, regs.REG_CONTROL,
                                regs.CONTROL_SOFT_RESET_MASK) == RESP_OKAY
        seen["busy"] = await axil_read(ctx, axil, regs.REG_STATUS)
        seen["write"] = await axil_write(ctx, axil, regs.REG_STATUS, 1)
        for _ in range(20):                                  # tready low: it waits
            assert ctx.get(top.m_axis_cand_tvalid)
            assert ctx.get(top.m_axis_cand_tdata) == word
            assert not ctx.get(top.s_axis_video_tready)
            await ctx.tick("sync")
        ctx.set(top.m_axis_cand_tready, 1)
        await ctx.tick("sync")                               # the word is taken
        ctx.set(top.m_axis_cand_tready, 0)
        idle = []
        for _ in range(4):
            idle.append((ctx.get(top.m_axis_cand_tvalid), ctx.get(top.s_axis_video_tready)))
            await ctx.tick("sync")
        seen["after"] = idle
        seen["idle"] = await axil_read(ctx, axil, regs.REG_STATUS)

    simulate_top(top, bench)
    assert seen["busy"] == (regs.STATUS_SOFT_RESET_BUSY_MASK, RESP_OKAY)
    assert seen["write"] == RESP_SLVERR
    # the list closed in the cycle after the (list-ending) word was taken; the restart
    # (the reset) in the next; the core's post-reset cycle; then input again
    assert seen["after"] == [(0, 0), (0, 0), (0, 0), (0, 1)]
    assert seen["idle"] == (0, RESP_OKAY)


def test_soft_reset_completes_the_open_state_line_and_waits_for_it():
    """--state-output, K = 1: 11 pixels (line 0 and 3 pixels of line 1) leave as state words,
    then m_axis_state_tready is held low and a soft reset issued: no list is open, so only
    m_axis_state is closed: its line is completed by W - 3 = 5 fillers (tdata 0, tuser =
    cut only, tlast on the last), offered unchanged while tready is low, the input held and
    STATUS.soft_reset_busy 1; the core is reset in the cycle after the last filler is taken
    (the input is taken again three cycles later); the next frame's states are the model's from
    reset, pixel (0, 0) with tuser[0], lines of W words."""
    cfg = make_config(width=8, height=6, segment_frames=1, candidate_count=2)
    regs = constants_namespace(cfg)
    top = AXITop(cfg, state_output=True)
    axil = flat_axil(top)
    pixels = [(3 * i + 1) % 200 for i in range(cfg.width * cfg.height)]
    frame = [(p, int(i == 0), int(i % cfg.width == cfg.width - 1))
             for i, p in enumerate(pixels)]
    cut_user = 1 << STATE_TUSER["cut"]
    seen = {"words": [], "fillers": [], "after": []}

    async def send_and_take(ctx, beats, count):
        """Offer ``beats`` back to back and take m_axis_state (tready high) until every
        beat is accepted and ``count`` state words are taken."""
        ctx.set(top.m_axis_state_tready, 1)
        index = 0
        while index < len(beats) or len(seen["words"]) < count:
            if index < len(beats):
                pixel, first, last = beats[index]
                ctx.set(top.s_axis_video_tdata, pixel)
                ctx.set(top.s_axis_video_tuser, first)
                ctx.set(top.s_axis_video_tlast, last)
            ctx.set(top.s_axis_video_tvalid, index < len(beats))
            if index < len(beats) and ctx.get(top.s_axis_video_tready):
                index += 1
            if ctx.get(top.m_axis_state_tvalid):
                seen["words"].append((ctx.get(top.m_axis_state_tdata),
                                      ctx.get(top.m_axis_state_tuser),
                                      ctx.get(top.m_axis_state_tlast)))
            await ctx.tick("sync")
        ctx.set(top.s_axis_video_tvalid, 0)

    async def bench(ctx):
        await ctx.tick("sync")
        ctx.set(top.aresetn, 1)
        ctx.set(top.m_axis_cand_tready, 1)
        ctx.set(top.m_axis_state_tready, 1)
        await send_and_take(ctx, frame[:11], 11)
        assert len(seen["words"]) == 11
        ctx.set(top.m_axis_state_tready, 0)
        assert await axil_write(ctx, axil, regs.REG_CONTROL,
                                regs.CONTROL_SOFT_RESET_MASK) == RESP_OKAY
        seen["busy"] = await axil_read(ctx, axil, regs.REG_STATUS)
        for _ in range(10):                                  # tready low: it waits
            assert (ctx.get(top.m_axis_state_tvalid), ctx.get(top.m_axis_state_tdata),
                    ctx.get(top.m_axis_state_tuser), ctx.get(top.m_axis_state_tlast)) == (
                        1, 0, cut_user, 0)
            assert not ctx.get(top.s_axis_video_tready)
            await ctx.tick("sync")
        ctx.set(top.m_axis_state_tready, 1)
        last = 0
        while not last:
            assert ctx.get(top.m_axis_state_tvalid) and not ctx.get(top.s_axis_video_tready)
            last = ctx.get(top.m_axis_state_tlast)
            seen["fillers"].append((ctx.get(top.m_axis_state_tdata),
                                    ctx.get(top.m_axis_state_tuser), last))
            await ctx.tick("sync")
        for _ in range(3):
            seen["after"].append((ctx.get(top.m_axis_state_tvalid),
                                  ctx.get(top.s_axis_video_tready)))
            await ctx.tick("sync")
        seen["idle"] = await axil_read(ctx, axil, regs.REG_STATUS)
        seen["words"] = []
        await send_and_take(ctx, frame, len(frame))

    simulate_top(top, bench)
    assert seen["busy"] == (regs.STATUS_SOFT_RESET_BUSY_MASK, RESP_OKAY)
    assert seen["fillers"] == [(0, cut_user, 0)] * 4 + [(0, cut_user, 1)]
    # the restart (the reset) in the cycle after the last filler was taken; the core's
    # post-reset cycle; input
    assert seen["after"] == [(0, 0), (0, 0), (0, 1)]
    assert seen["idle"] == (0, RESP_OKAY)
    want = expected_stream(cfg, np.array(pixels), np.array([f for _p, f, _l in frame]))
    got = [int(pack_states(cfg, energy=d & ((1 << cfg.energy_bits) - 1),
                           direction=d >> cfg.energy_bits, end_of_line=last,
                           end_of_frame=(u >> STATE_TUSER["end_of_frame"]) & 1,
                           end_of_segment=(u >> STATE_TUSER["end_of_segment"]) & 1))
           for d, u, last in seen["words"]]
    assert got == [int(w) for w in want.words]
    assert [u & 1 for _d, u, _l in seen["words"]] == [1] + [0] * (len(frame) - 1)
    assert [last for _d, _u, last in seen["words"]] == [f[2] for f in frame]


def test_external_state_store_ports_and_core_options():
    """``external_state_store=True`` brings the DP core's state-store port out as
    ``state_store_*`` (flows as the core sees them), between the AXI bundles and ``irq``;
    ``core_options`` reach the DP core. Off by default."""
    cfg = config()
    options = {"line_buffer_style": "lutram", "sideband_delay": "memory", "max_tree": "split",
               "state_store_style": "dp16kd", "histogram_style": "dp16kd",
               "control_style": "registered", "output_queue_style": "one_hot",
               "register_read": "two_level", "credit_ready": "per_load", "lut_write": "predecoded"}
    top = AXITop(cfg, external_state_store=True, core_options=options)
    ports = {path[0]: member.flow for path, member, _v in top.signature.flatten(top)}
    store = [n for n in ports if n.startswith("state_store_")]
    assert store == ["state_store_read_addr", "state_store_read_en", "state_store_read_data",
                     "state_store_write_addr", "state_store_write_data",
                     "state_store_write_en"]
    assert [ports[n] for n in store] == [Out, Out, In, Out, Out, Out]
    assert list(ports)[-1] == "irq"
    assert top.core.external_state_store and top.core.core_options == options
    plain = AXITop(cfg)
    Fragment.get(plain, None)
    assert not plain.core.external_state_store
    assert not [p for p, _m, _v in plain.signature.flatten(plain) if p[0].startswith("state")]
    Fragment.get(top, None)


def lockstep_trace(top, cfg, seed, cycles, replay=None, reads=True):
    """Every input and output port of ``top`` in every cycle: a random stimulus (pixels in
    frames of W*H taken beats, a stray start of frame now and then, soft resets and other
    writes to CONTROL, reads, back-pressure, ``aresetn`` now and then), or ``replay``, the
    inputs of an earlier trace (the same stimulus on another build); no reads unless
    ``reads``."""
    regs = constants_namespace(cfg)
    rng = np.random.default_rng(seed)
    pixels = cfg.width * cfg.height
    inputs = [p[0] for p, m, _v in top.signature.flatten(top) if m.flow == In and p[0] != "aclk"]
    outputs = [p[0] for p, m, _v in top.signature.flatten(top) if m.flow == Out]
    trace = []

    async def bench(ctx):
        taken = 0
        for cycle in range(cycles):
            if replay is not None:
                draw = replay[cycle][0]
            else:
                draw = {
                    "aresetn": int(cycle > 0 and rng.random() > 0.002),
                    "s_axis_video_tdata": int(rng.integers(256)),
                    "s_axis_video_tuser": int(taken % pixels == 0 or rng.random() < 0.002),
                    "s_axis_video_tlast": int(taken % cfg.width == cfg.width - 1),
                    "s_axis_video_tvalid": int(rng.random() < 0.9),
                    "m_axis_cand_tready": int(rng.random() < 0.7),
                    "m_axis_state_tready": int(rng.random() < 0.9),
                    "s_axil_awaddr": regs.REG_CONTROL,
                    "s_axil_awvalid": int(rng.random() < 0.02),
                    "s_axil_wvalid": int(rng.random() < 0.02),
                    # soft_reset (bit 0) in one write of twenty, clear_counters (bit 1)
                    "s_axil_wdata": int(rng.random() < 0.05) | 2 * int(rng.random() < 0.5),
                    "s_axil_wstrb": 0xF,
                    "s_axil_bready": int(rng.random() < 0.5),
                    "s_axil_araddr": int(rng.choice([regs.REG_STATUS, regs.REG_INPUT_STALLS])),
                    "s_axil_arvalid": int(rng.random() < 0.05) * reads,
                    "s_axil_rready": int(rng.random() < 0.5),
                }
            for name in inputs:
                ctx.set(getattr(top, name), draw.get(name, 0))
            out = {name: ctx.get(getattr(top, name)) for name in outputs}
            trace.append((draw, out))
            taken += draw["s_axis_video_tvalid"] & out["s_axis_video_tready"]
            await ctx.tick("sync")

    simulate_top(top, bench)
    return trace


@pytest.mark.parametrize("options, reads", [
    ({"control_style": "registered"}, True),
    ({"control_style": "registered", "histogram_style": "dp16kd", "register_read": "two_level"},
     False)],
    ids=["registered", "ecp5"])
def test_registered_control_is_the_generic_top_cycle_for_cycle(options, reads, monkeypatch):
    """``control_style="registered"`` (the ECP5 build: the input held from registers of its
    own computed a cycle ahead, the segmenter's registered control) gives every output port
    the generic build's value in every cycle, under soft resets, other writes, reads,
    back-pressure and ``aresetn``, with the state output; with the ECP5 build's
    ``histogram_style="dp16kd"`` (on the behavioural DP16KD) and ``register_read="two_level"``
    too (a read answered a cycle later, ``tests/hw/test_axi_lite.py``) the same without
    reads."""
    model_dp16kd_cells(monkeypatch)
    # 16 bins: a short histogram scan, so that many lists are sent
    cfg = make_config(width=8, height=6, segment_frames=2, candidate_count=3, histogram_bits=4,
                      histogram_shift=2)
    generic = lockstep_trace(AXITop(cfg, state_output=True), cfg, 5, 5000, reads=reads)
    registered = lockstep_trace(
        AXITop(cfg, state_output=True, core_options=options),
        cfg, 5, 5000, replay=generic)
    assert [out for _d, out in registered] == [out for _d, out in generic]

    def count(condition):
        return sum(bool(condition(d, o)) for d, o in generic)
    # not vacuous: pixels taken, lists and states sent, soft resets served
    assert count(lambda d, o: d["s_axis_video_tvalid"] & o["s_axis_video_tready"]) > 4000
    assert count(lambda d, o: o["m_axis_cand_tvalid"] & d["m_axis_cand_tready"]
                 & o["m_axis_cand_tlast"]) > 25
    assert count(lambda d, o: o["m_axis_state_tvalid"] & d["m_axis_state_tready"]) > 3500
    assert count(lambda d, o: d["s_axil_wvalid"] & o["s_axil_wready"]
                 & d["s_axil_wdata"] & 1) > 2
