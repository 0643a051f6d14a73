"""The P-pixel pipeline (``hw/wide/``) against the golden model, bit for bit.

Whole small scenes stream through ``DPPipelineWide`` (and ``DPCoreWide`` with a memory
model) in the Amaranth simulator with random input gaps and output back-pressure; every
state of every pixel is compared with ``dptbd.model.fixed``, as the P = 1 pipeline's in
``test_dp_pipeline.py``.
"""

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.dp_pipeline import DPPipeline
from dptbd.hw.wide import (DPCoreWide, DPPipelineWide, check_wide, dp_pipeline,
                              lane_column, pack_beat, unpack_beat_states, wide_pixel_layout,
                              wide_state_layout)
from dptbd.hw.layouts import pack
from helpers.hw_harness import (assert_states_equal, event_counter, lut_writes_for,
                                reference_states, refused)
from helpers.refusals import whole
from helpers.wide_harness import frames_to_beats, make_config, random_frames, run_beats


SCENES = {
    "p2-8x5-r1-k3": (dict(width=8, height=5, segment_frames=3, pixels_per_clock=2), 7),
    "p4-12x8-r1-k2": (dict(width=12, height=8, segment_frames=2, pixels_per_clock=4), 5),
    "p2-10x7-r2-k3-half_up": (dict(width=10, height=7, segment_frames=3, radius=2,
                                   rounding="half_up", pixels_per_clock=2), 6),
    "p4-16x6-r2-k2-f3": (dict(width=16, height=6, segment_frames=2, radius=2,
                              weight_frac_bits=3, pixels_per_clock=4), 5),
    "p4-12x6-r1-k4-b4-e6": (dict(width=12, height=6, segment_frames=4, input_bits=4,
                                 energy_bits=6, pixels_per_clock=4), 9),
}


@pytest.mark.parametrize("name", SCENES)
def test_scene_matches_golden_model(name):
    kw, n_frames = SCENES[name]
    cfg = make_config(**kw)
    frames = random_frames(cfg, n_frames, seed=len(name))
    run = run_beats(DPPipelineWide(cfg), cfg, frames_to_beats(cfg, frames),
                    valid_probability=0.7, ready_probability=0.6, seed=5)
    assert_states_equal(run.outputs, reference_states(cfg, frames))


@pytest.mark.parametrize("p, radius, style", [(2, 1, "logic"), (4, 1, "bram"), (2, 2, "bram"),
                                              (4, 2, "logic")])
def test_exact_cycle_count(p, radius, style):
    """Valid and ready always high: one beat (P pixels) per cycle in and out, after L: N
    frames take exactly N*W*H/P + L cycles."""
    cfg = make_config(width=4 * p, height=6, segment_frames=2, radius=radius,
                      pixels_per_clock=p)
    dut = DPPipelineWide(cfg, lut_style=style)
    assert dut.lut_style == style
    latency = dut.latency
    assert latency == {1: 14, 2: 15}[radius]                # the schedule of P = 1
    frames = random_frames(cfg, 3, seed=p + radius)
    run = run_beats(dut, cfg, frames_to_beats(cfg, frames))
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    beats = 3 * cfg.width * cfg.height // p
    assert beats == 3 * cfg.frame_beats == 72
    first_in = run.accept_cycles[0]
    assert first_in == 1                                      # ready rises a cycle after reset
    assert run.accept_cycles == list(range(first_in, first_in + beats))    # no bubbles
    assert run.output_cycles == list(range(first_in + latency, first_in + latency + beats))
    assert run.output_cycles[-1] - first_in + 1 == beats + latency == {1: 86, 2: 87}[radius]


def sram_model(bus, words, seed):
    """A one-cycle synchronous memory of random contents; ``read_data`` is random except in
    the cycle after a read (the core must use neither)."""
    rng = np.random.default_rng(seed)
    width = len(bus.read_data.as_value())
    contents = [int(rng.integers(0, 1 << 62)) % (1 << width) for _ in range(words)]

    async def process(ctx):
        async for _clk, _rst, read_en, read_addr, write_en, write_addr, write_data in \
                ctx.tick().sample(bus.read_en, bus.read_addr, bus.write_en, bus.write_addr,
                                  bus.write_data.as_value()):
            data = (contents[read_addr] if read_en
                    else int(rng.integers(0, 1 << 62)) % (1 << width))
            ctx.set(bus.read_data.as_value(), data)
            if write_en:
                contents[write_addr] = write_data
    return process


def test_external_store_matches_golden_model():
    cfg = make_config(width=12, height=6, segment_frames=3, pixels_per_clock=4)
    dut = DPCoreWide(cfg)
    frames = random_frames(cfg, 5, seed=21)
    beats = frames_to_beats(cfg, frames)
    process = sram_model(dut.state_store, cfg.frame_beats, seed=3)
    run = run_beats(dut, cfg, beats, valid_probability=0.8, ready_probability=0.7, seed=11,
                    processes=[process])
    assert_states_equal(run.outputs, reference_states(cfg, frames))


@pytest.mark.parametrize("p", [2, 4])
def test_lut_written_at_run_time(p):
    """New codes between frames and inside a frame, at a beat boundary: from that beat on."""
    cfg = make_config(width=3 * p, height=6, segment_frames=4, weight_frac_bits=5,
                      pixels_per_clock=p)
    pixels = cfg.width * cfg.height
    rng = np.random.default_rng(p)
    moves = cfg.n_moves
    old = cfg.weight_codes.astype(np.int64)
    between = rng.integers(0, 33, size=(moves + 1, moves))
    inside = between.copy()
    inside[:, : moves // 2] = rng.integers(0, 33, size=(moves + 1, moves // 2))
    switch_between = pixels                 # before frame 1's first beat
    switch_inside = 2 * pixels + 4 * p      # before beat 4 of frame 2
    writes = {switch_between // p: lut_writes_for(cfg, old, between),
              switch_inside // p: lut_writes_for(cfg, between, inside)}
    frames = random_frames(cfg, 4, seed=p + 10)
    run = run_beats(DPPipelineWide(cfg), cfg, frames_to_beats(cfg, frames),
                    valid_probability=0.8, ready_probability=0.7, seed=p, lut_writes=writes)
    expected = reference_states(cfg, frames, [(switch_between, between), (switch_inside, inside)])
    assert_states_equal(run.outputs, expected)
    assert not np.array_equal(expected, reference_states(cfg, frames))


def test_run_time_k_resync_and_events():
    """K changed between segments, a resync inside a frame (at a beat boundary): every state
    and every event count equals the stream model's (per pixel; events per beat)."""
    from dptbd.model.settings import SegmentSettings
    from dptbd.sim.stream_model import expected_stream

    p = 2
    cfg = make_config(width=8, height=5, segment_frames=2, max_segment_frames=4,
                      energy_bits=9, pixels_per_clock=p)
    size = cfg.width * cfg.height
    lengths = [3, 1, 4, 2]
    frames = random_frames(cfg, sum(lengths) + 3, seed=21)
    pixels = frames.reshape(-1)
    first = np.zeros(pixels.size, dtype=bool)
    first[::size] = True
    keep = np.ones(pixels.size, dtype=bool)
    keep[size * 9 + 6: size * 10] = False                    # resync inside frame 9
    pixels, first = pixels[keep], first[keep]
    starts = np.cumsum([0] + lengths)[:-1] * size
    changes = {int(at): SegmentSettings(k, cfg.n_candidates, cfg.bin_shift)
               for at, k in zip(starts, lengths)}
    changes[size * 9 + 6] = SegmentSettings(3, cfg.n_candidates, cfg.bin_shift)
    exp = expected_stream(cfg, pixels, first, settings_changes=changes)
    beats = [(tuple(int(v) for v in pixels[i:i + p]), bool(first[i]))
             for i in range(0, pixels.size, p)]
    rng = np.random.default_rng(3)
    dut = DPPipelineWide(cfg)

    def drive(ctx, beat):
        k = changes[beat * p].segment_frames if beat * p in changes else int(rng.integers(0, 8))
        ctx.set(dut.segment_frames, k)

    counts = {}
    run = run_beats(dut, cfg, beats, valid_probability=0.7, ready_probability=0.6, seed=5,
                    on_cycle=drive, processes=[event_counter(dut.events, counts)])
    assert len(run.outputs) == len(exp.fields)
    for n, (got, want) in enumerate(zip(run.outputs, exp.fields)):
        assert [got[f] for f in ("energy", "direction", "end_of_line", "end_of_frame",
                                 "end_of_segment")] == want.tolist(), f"output {n}"
    saturated_beats = exp.saturated.reshape(-1, p).any(axis=1)
    assert counts == {"frame_done": int(exp.fields[:, 3].sum()),
                      "segment_done": int(exp.fields[:, 4].sum()), "list_done": 0,
                      "saturated": int(saturated_beats.sum())}
    assert counts["segment_done"] == 4 and counts["saturated"] > 0


def test_beat_layouts_put_pixel_zero_low():
    cfg = make_config(width=12, height=6, input_bits=4, energy_bits=6, pixels_per_clock=4)
    assert pack_beat(cfg, (1, 2, 3, 4), True) == 0x4321 | 1 << 16
    assert [name for name, _ in wide_pixel_layout(cfg)] == [
        "pixel_0", "pixel_1", "pixel_2", "pixel_3", "first"]
    layout = wide_state_layout(cfg)
    word = pack(layout, {**{f"energy_{k}": 10 + k for k in range(4)},
                         **{f"direction_{k}": k for k in range(4)},
                         "end_of_line": 1, "end_of_frame": 0, "end_of_segment": 0})
    assert word & 0x3ff == 10 | 0 << 6                      # state 0 in bits 0 … 9
    states = unpack_beat_states(cfg, word)
    assert [s["energy"] for s in states] == [10, 11, 12, 13]
    assert [s["end_of_line"] for s in states] == [0, 0, 0, 1]


def test_lane_columns():
    """Lane k's window column j is column gP + k + r - j: (slot, word), slot 0 = beat g+r."""
    cfg = make_config(width=8, height=5, pixels_per_clock=2)            # r = 1
    assert [lane_column(cfg, 0, j) for j in range(3)] == [(1, 1), (1, 0), (2, 1)]
    assert [lane_column(cfg, 1, j) for j in range(3)] == [(0, 0), (1, 1), (1, 0)]
    cfg = make_config(width=8, height=5, radius=2, pixels_per_clock=2)  # r = 2: beats g+2 … g-1
    assert [lane_column(cfg, 0, j) for j in range(5)] == [(1, 0), (2, 1), (2, 0), (3, 1), (3, 0)]
    assert [lane_column(cfg, 1, j) for j in range(5)] == [(1, 1), (1, 0), (2, 1), (2, 0), (3, 1)]


def test_dp_pipeline_picks_by_p():
    one = dp_pipeline(DPConfig(width=8, height=5))
    two = dp_pipeline(DPConfig(width=8, height=5, pixels_per_clock=2), lut_style="bram")
    assert type(one) is DPPipeline and type(two) is DPPipelineWide
    assert two.lut_style == "bram"
    for dut in (one, two, one._core, two._core):   # built, never elaborated: fine
        dut._MustUse__silence = True


def test_refuses_p_one():
    with refused(ConfigError, match=whole(
            "pixels_per_clock=1 is built by DPCore and DPPipeline, not by the P-pixel pipeline "
            "(pixels_per_clock 2 or 4)")):
        DPPipelineWide(DPConfig(width=8, height=5))


def test_refuses_paper_000_fields():
    cfg = make_config(width=8, height=5, pixels_per_clock=2, forgetting=0.5, recursive=True)
    with refused(ConfigError, match=whole(
            "pixels_per_clock=2 is built for paper 001's DP only; the paper-000 field(s) "
            "['forgetting', 'recursive'] need pixels_per_clock=1")):
        DPCoreWide(cfg)


def test_refuses_frames_too_small_for_the_read_ahead_in_beats():
    cfg = DPConfig(width=12, height=4, pixels_per_clock=4)   # 12 - 4 = 8 beats <= 12
    one = DPPipeline(cfg.replace(pixels_per_clock=1))                       # fine at P = 1
    one._MustUse__silence = one._core._MustUse__silence = True
    with refused(ConfigError, match=whole(
            "width=12 x height=4 is too small for the read-ahead of radius=1 at "
            "pixels_per_clock=4: the gateware needs (width/P)*height - radius*(width/P+1) > "
            "write latency 12 cycles, but it is 8; each state must be written before the next "
            "frame reads it; use a larger frame")):
        DPPipelineWide(cfg)
    assert check_wide(cfg.replace(height=6)).latency == 14   # 18 - 4 = 14 > 12: built


@pytest.mark.parametrize("option, value, message", [
    ("line_buffer_style", "ultra",
     "line_buffer_style must be one of ('bram', 'lutram', 'dp16kd'), got 'ultra'"),
    ("sideband_delay", "fifo", "sideband_delay must be one of ('registers', 'memory'), got 'fifo'"),
    ("state_store_style", "bram",
     "state_store_style must be one of ('memory', 'dp16kd'), got 'bram'"),
    ("histogram_style", "fifo",
     "histogram_style must be one of ('memory', 'dp16kd'), got 'fifo'"),
    ("control_style", "fast",
     "control_style must be one of ('generic', 'registered'), got 'fast'"),
    ("output_queue_style", "shift",
     "output_queue_style must be one of ('binary', 'one_hot'), got 'shift'"),
    ("register_read", "late",
     "register_read must be one of ('one_level', 'two_level'), got 'late'"),
    ("credit_ready", "many",
     "credit_ready must be one of ('one', 'per_load'), got 'many'"),
    ("lut_write", "table",
     "lut_write must be one of ('case', 'predecoded'), got 'table'"),
    ("output_fifo_depth", 2, "output_fifo_depth must be an integer in [3, inf), got 2"),
])
def test_refuses_bad_options(option, value, message):
    cfg = DPConfig(width=8, height=5, pixels_per_clock=2)
    with refused(ValueError, match=whole(message)):
        DPPipelineWide(cfg, **{option: value})


@pytest.mark.parametrize("p", [2, 4])
def test_build_top_puts_the_axi_store_around_dpcorewide(p):
    from dptbd.hw.axi_store.pipeline import DPPipelineAxi
    from dptbd.hw.flow.verilog import build_top
    cfg = DPConfig(width=64, height=16, pixels_per_clock=p).build_config()
    top = build_top(cfg, state_store=cfg.axi_store())
    assert type(top) is DPPipelineAxi and type(top._core) is DPCoreWide
    assert top.latency == DPCoreWide(cfg).latency
    payload = top.signature.members["pixels"].signature.members["payload"]
    assert payload.shape.size == 8 * p + 1                  # a beat of P pixels and first


def test_one_pixel_blocks_refuse_p_above_one():
    """DPCore (and so DPPipeline, the segmenter, the AXI tops) never builds a P = 1 design
    for a P > 1 configuration."""
    cfg = DPConfig(width=8, height=6, pixels_per_clock=2)
    message = ("pixels_per_clock=2: this block takes one pixel per clock; P = 2 and 4 are "
               "built by DPCoreWide and DPPipelineWide (hw/wide/, the dp top of dptbd "
               "verilog)")
    with refused(ConfigError, match=whole(message)):
        DPPipeline(cfg)
    from dptbd.hw.dp_segmenter_top import DPSegmenter
    with refused(ConfigError, match=whole(message)):
        DPSegmenter(cfg)


def test_refuses_overlapping_segments_at_p_above_one():
    cfg = DPConfig(width=8, height=6, segment_frames=4, segment_stride=2, pixels_per_clock=2)
    with refused(ConfigError, match=whole(
            "segment_stride=2 is not supported by the gateware: only non-overlapping segments "
            "(segment_stride == segment_frames == 4) are implemented, with a single state "
            "store")):
        DPPipelineWide(cfg)


@pytest.mark.parametrize("p, radius, external", [(2, 2, False), (4, 1, True)])
def test_verilator_lints_clean_at_128x128(tmp_path, p, radius, external):
    """The generated Verilog at P = 2 and 4, default frame size, with the project's lint flags."""
    import shutil
    from dptbd.hw.flow.verilog import MODULE_NAME, generate_verilog
    from helpers.hw_harness import assert_verilator_lints_clean

    if shutil.which("verilator") is None:
        pytest.skip("needs Verilator")
    cfg = DPConfig(radius=radius, pixels_per_clock=p).build_config()
    text, info = generate_verilog(cfg, external_state_store=external)
    assert info["top"] == ("DPCoreWide" if external else "DPPipelineWide")
    path = tmp_path / "dptbd_dp.v"
    path.write_text(text)
    assert_verilator_lints_clean(path, MODULE_NAME)
