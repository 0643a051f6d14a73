"""DPPipelineAxi: the golden model's bits with the state in a random-latency AXI4 memory."""

import numpy as np
import pytest
from amaranth.back import verilog

from dptbd.config import DPConfig
from dptbd.hw.axi_store.bus import RESP_SLVERR
from dptbd.hw.axi_store.pipeline import DPPipelineAxi
from dptbd.sim.axi4_memory import Axi4Memory
from helpers.dp16kd_model import model_dp16kd_cells
from helpers.hw_harness import (assert_states_equal, assert_verilator_lints_clean,
                                frames_to_stream, reference_states, run_stream)
from helpers.verilator_harness import needs_verilator


def run_axi(cfg, frames, *, store_fields=(), latency=(0, 0), ready=1.0, valid=1.0,
            valid_probability=1.0, ready_probability=1.0, seed=0, stream=None,
            write_latency=None, **core_options):
    store = cfg.axi_store(**dict(store_fields))
    dut = DPPipelineAxi(store, **core_options)
    memory = Axi4Memory(dut, store, seed=seed, latency=latency, ready=ready, valid=valid,
                        write_latency=write_latency)
    stream = frames_to_stream(frames) if stream is None else stream
    slow = max(latency[1], 1) * 4 * len(stream) + 20 * (write_latency or (0, 0))[1] + 5000
    run = run_stream(dut, cfg, stream, valid_probability=valid_probability,
                     ready_probability=ready_probability, seed=seed,
                     processes=[memory.process()], max_cycles=slow)
    return run, memory


@pytest.mark.parametrize("kw, store_fields", [
    (dict(width=16, height=12, segment_frames=3), dict(data_bits=64, burst_beats=4)),
    (dict(width=16, height=12, segment_frames=2, radius=2, rounding="half_up"),
     dict(data_bits=32, burst_beats=2)),
    (dict(width=20, height=10, segment_frames=4, energy_bits=10), dict(data_bits=128,
                                                                      burst_beats=2)),
])
def test_bits_equal_the_golden_model_at_zero_latency(kw, store_fields):
    cfg = DPConfig(**kw)
    frames = np.random.default_rng(3).integers(0, 256, size=(5, cfg.height, cfg.width))
    run, _ = run_axi(cfg, frames, store_fields=store_fields)
    assert_states_equal(run.outputs, reference_states(cfg, frames))


@pytest.mark.parametrize("latency, ready, valid, seed", [
    ((0, 40), 0.6, 0.5, 1),
    pytest.param((0, 600), 0.8, 0.7, 2, marks=pytest.mark.slow),     # the longer run
])
def test_memory_latency_and_stalls_change_no_bit(latency, ready, valid, seed):
    cfg = DPConfig(width=16, height=12, segment_frames=2)
    frames = np.random.default_rng(seed).integers(0, 256, size=(4, cfg.height, cfg.width))
    run, memory = run_axi(cfg, frames, store_fields=dict(data_bits=64, burst_beats=4,
                                                         outstanding=2),
                          latency=latency, ready=ready, valid=valid, valid_probability=0.9,
                          ready_probability=0.8, seed=seed)
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    assert memory.stats["write_beats"] >= 3 * 192 // 2   # the state did go through memory


def test_slow_write_responses_hold_the_reads_back():
    """Reads answered at once, write responses after 150 … 400 cycles, a deep prefetch:
    every read of the next frame waits for the response of the write it depends on."""
    cfg = DPConfig(width=16, height=12, segment_frames=3)
    frames = np.random.default_rng(8).integers(0, 256, size=(4, cfg.height, cfg.width))
    run, _ = run_axi(cfg, frames, store_fields=dict(data_bits=128, burst_beats=4,
                                                    outstanding=16),
                     write_latency=(150, 400), seed=4)
    assert_states_equal(run.outputs, reference_states(cfg, frames))


def test_a_zero_latency_memory_keeps_one_pixel_per_cycle():
    """Memory always ready, no latency: the first pixel enters in cycle 5 (the AR register,
    the memory's answer, the beat FIFO's two registers, the head beat's), then one pixel
    every cycle."""
    cfg = DPConfig(width=16, height=12, segment_frames=3)
    frames = np.random.default_rng(3).integers(0, 256, size=(4, cfg.height, cfg.width))
    run, _ = run_axi(cfg, frames, store_fields=dict(data_bits=64, burst_beats=4))
    assert run.accept_cycles == list(range(5, 5 + 4 * 192))
    assert_states_equal(run.outputs, reference_states(cfg, frames))


def test_the_prefetch_fifo_in_dp16kds_keeps_the_bits_and_the_cycles(monkeypatch):
    """``state_store_style="dp16kd"`` (the ECP5 family's) builds the prefetcher's beat FIFO
    in DP16KDs (modelled): the first pixel enters in cycle 6, a cycle after the Amaranth
    FIFO's (the array's read register, the output register and the flip-flop queue in
    place of the FIFO's read register and the head beat), then one every cycle; under
    latency and stalls the golden model's bits."""
    model_dp16kd_cells(monkeypatch)
    cfg = DPConfig(width=16, height=12, segment_frames=3)
    frames = np.random.default_rng(3).integers(0, 256, size=(4, cfg.height, cfg.width))
    run, _ = run_axi(cfg, frames, store_fields=dict(data_bits=64, burst_beats=4),
                     state_store_style="dp16kd")
    assert run.accept_cycles == list(range(6, 6 + 4 * 192))
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    run, _ = run_axi(cfg, frames, store_fields=dict(data_bits=32, burst_beats=2,
                                                    outstanding=3),
                     latency=(0, 40), ready=0.6, valid=0.7, valid_probability=0.8,
                     ready_probability=0.8, seed=6, state_store_style="dp16kd")
    assert_states_equal(run.outputs, reference_states(cfg, frames))


@needs_verilator
@pytest.mark.parametrize("kw, store_fields", [
    (dict(width=640, height=512), dict(data_bits=64)),              # 2 states per beat
    (dict(width=16, height=12), dict(data_bits=32, burst_beats=2)),  # 1 state per beat
    (dict(width=1280, height=1024, segment_frames=8), dict(data_bits=128)),
    (dict(width=64, height=16, pixels_per_clock=2), dict(data_bits=32, burst_beats=2)),
    (dict(width=640, height=512, pixels_per_clock=4), dict(data_bits=64)),  # 1 word per beat
])
def test_verilog_lints_clean(tmp_path, kw, store_fields):
    store = DPConfig(**kw).build_config().axi_store(**store_fields)
    path = tmp_path / "dptbd_dp_axi.v"
    path.write_text(verilog.convert(DPPipelineAxi(store), name="dptbd_dp_axi"))
    assert_verilator_lints_clean(path, "dptbd_dp_axi")


def test_unexpected_first_resynchronises():
    """A frame cut short, then frames with `first`: a new segment starts at the `first`;
    the prefetcher restarts under a random-latency memory."""
    from helpers.hw_harness import FIELDS
    cfg = DPConfig(width=16, height=12, segment_frames=3)
    frames = np.random.default_rng(12).integers(0, 256, size=(6, cfg.height, cfg.width))
    cut = 100
    stream = frames_to_stream(frames[:1]) + frames_to_stream(frames[1:2])[:cut] \
        + frames_to_stream(frames[2:])
    run, _ = run_axi(cfg, frames, store_fields=dict(data_bits=64, burst_beats=4),
                     latency=(0, 50), ready=0.7, valid=0.7, valid_probability=0.8,
                     ready_probability=0.8, seed=4, stream=stream)
    head = reference_states(cfg, frames[:2])
    truncated = head[1].reshape(-1, len(FIELDS))[:cut].copy()
    truncated[:, 3:] = 0                          # the cut frame never ends
    tail = reference_states(cfg, frames[2:])      # a new segment from frame 2
    expected = np.concatenate([head[0].reshape(-1, len(FIELDS)), truncated,
                               tail.reshape(-1, len(FIELDS))])
    assert len(run.outputs) == len(expected)
    for n, (got, want) in enumerate(zip(run.outputs, expected)):
        assert [got[f] for f in FIELDS] == want.tolist(), f"output {n}"


@pytest.mark.parametrize("name", ["recursive-r1", "likelihood-r2",
                                  "forgetting-truncate-penalty"])
def test_paper_000_family_is_bit_exact(name):
    """§8 variants (merit and penalty LUTs, forgetting, recursive mode) at 16 x 12."""
    from helpers.family_harness import family_reference_states, variant
    fields, n_frames = variant(name)
    cfg = DPConfig(**{**fields, "width": 16, "height": 12})
    frames = np.random.default_rng(6).integers(0, 1 << cfg.input_bits,
                                               size=(n_frames, cfg.height, cfg.width))
    run, _ = run_axi(cfg, frames, store_fields=dict(data_bits=64, burst_beats=2),
                     latency=(0, 40), ready=0.7, valid=0.7, seed=5)
    assert_states_equal(run.outputs, family_reference_states(cfg, frames))


def test_recursive_restarts_only_on_a_resync():
    from helpers.family_harness import family_reference_states, variant
    cfg = DPConfig(**{**variant("recursive-r1")[0], "width": 16, "height": 12})
    pixels = cfg.width * cfg.height
    rng = np.random.default_rng(30)
    before = rng.integers(0, 256, size=(3, cfg.height, cfg.width))
    after = rng.integers(0, 256, size=(3, cfg.height, cfg.width))
    cut = 57
    stream = frames_to_stream(before)[: 2 * pixels + cut] + frames_to_stream(after)
    run, _ = run_axi(cfg, before, store_fields=dict(data_bits=32, burst_beats=4),
                     latency=(0, 30), seed=3, stream=stream)
    first = family_reference_states(cfg, before)
    second = family_reference_states(cfg, after)
    assert_states_equal(run.outputs[: 2 * pixels], first[:2])
    partial = first[2].reshape(-1, first.shape[-1])[:cut]
    assert [list(o.values()) for o in run.outputs[2 * pixels: 2 * pixels + cut]] == \
        partial.tolist()
    assert_states_equal(run.outputs[2 * pixels + cut:], second)


def test_a_transient_memory_error_is_flagged_and_the_next_segment_is_right_again():
    """Pixel 50's slot fails its first read (frame 0's, unused: a start frame) and its
    first write (frame 0's state is not stored): frame 1 may be wrong, the core does not
    hang, both errors are pulsed once, and the next segments are bit-exact."""
    cfg = DPConfig(width=16, height=12, segment_frames=2)
    store = cfg.axi_store(data_bits=64, burst_beats=4)
    frames = np.random.default_rng(7).integers(0, 256, size=(6, cfg.height, cfg.width))
    dut = DPPipelineAxi(store)
    memory = Axi4Memory(dut, store, seed=2, latency=(0, 20),
                        errors={50 * store.slot_bits // 8: RESP_SLVERR}, once=True)
    pulses = {"read": 0, "write": 0}

    def count(ctx, _index):
        pulses["read"] += ctx.get(dut.read_error)
        pulses["write"] += ctx.get(dut.write_error)

    run = run_stream(dut, cfg, frames_to_stream(frames), processes=[memory.process()],
                     on_cycle=count, seed=1)
    expected = reference_states(cfg, frames)
    assert_states_equal(run.outputs[:192], expected[:1])
    assert_states_equal(run.outputs[2 * 192:], expected[2:])
    assert pulses == {"read": 1, "write": 1}
    with pytest.raises(AssertionError):       # the lost write did reach frame 1
        assert_states_equal(run.outputs[192:2 * 192], expected[1:2])


# ---- P = 2 and 4 pixels per clock (DPCoreWide inside, store words of P states) -----------
def run_axi_beats(cfg, frames, *, store_fields=(), latency=(0, 0), ready=1.0, valid=1.0,
                  valid_probability=1.0, ready_probability=1.0, seed=0, beats=None,
                  **core_options):
    from helpers.wide_harness import frames_to_beats, run_beats
    store = cfg.axi_store(**dict(store_fields))
    dut = DPPipelineAxi(store, **core_options)
    memory = Axi4Memory(dut, store, seed=seed, latency=latency, ready=ready, valid=valid)
    beats = frames_to_beats(cfg, frames) if beats is None else beats
    run = run_beats(dut, cfg, beats, valid_probability=valid_probability,
                    ready_probability=ready_probability, seed=seed,
                    processes=[memory.process()],
                    max_cycles=max(latency[1], 1) * 4 * len(beats) + 5000)
    return run, memory


@pytest.mark.parametrize("p, store_fields", [
    (2, dict(data_bits=64, burst_beats=4)),      # 2 words of 2 states per beat
    (2, dict(data_bits=32, burst_beats=2)),      # 1 word per beat
    (4, dict(data_bits=64, burst_beats=4)),      # 1 word of 4 states per beat
    (4, dict(data_bits=128, burst_beats=2)),     # 2 words per beat
])
def test_p_pixels_per_clock_keep_one_beat_per_cycle_at_zero_latency(p, store_fields):
    """A memory always ready without latency: the first beat enters in cycle 5 (as at
    P = 1), then one beat of P pixels every cycle (with bursts of 2 beats of one word, 2
    beats every 3 cycles: a burst issues every third cycle at most), the golden model's
    bits."""
    cfg = DPConfig(width=16, height=12, segment_frames=3, pixels_per_clock=p).build_config()
    frames = np.random.default_rng(p).integers(0, 256, size=(4, cfg.height, cfg.width))
    run, memory = run_axi_beats(cfg, frames, store_fields=store_fields)
    beats = 4 * cfg.frame_beats
    if store_fields["data_bits"] == 32:          # 2-beat bursts, one AR every third cycle
        assert run.accept_cycles[0] == 5 and run.accept_cycles[-1] == 5 + 3 * beats // 2
    else:
        assert run.accept_cycles == list(range(5, 5 + beats))
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    # the state did go through memory (the last frame's bursts may still be on their way)
    assert memory.stats["write_beats"] >= 3 * cfg.axi_store(**store_fields).frame_beats


def test_p_pixels_with_the_prefetch_fifo_in_dp16kds_keep_the_cycles(monkeypatch):
    """P = 4 with the beat FIFO in (modelled) DP16KDs: the first beat in cycle 6 (a cycle
    after the Amaranth FIFO's), one beat every cycle, the golden model's bits."""
    model_dp16kd_cells(monkeypatch)
    cfg = DPConfig(width=16, height=12, segment_frames=3, pixels_per_clock=4).build_config()
    frames = np.random.default_rng(4).integers(0, 256, size=(4, cfg.height, cfg.width))
    run, _ = run_axi_beats(cfg, frames, store_fields=dict(data_bits=64, burst_beats=4),
                           state_store_style="dp16kd")
    assert run.accept_cycles == list(range(6, 6 + 4 * cfg.frame_beats))
    assert_states_equal(run.outputs, reference_states(cfg, frames))


@pytest.mark.parametrize("p, latency, seed", [
    (2, (0, 300), 1), pytest.param(4, (0, 500), 2, marks=pytest.mark.slow), (4, (100, 200), 3)])
def test_p_pixels_latency_and_stalls_change_no_bit(p, latency, seed):
    cfg = DPConfig(width=16, height=12, segment_frames=2, pixels_per_clock=p).build_config()
    frames = np.random.default_rng(seed).integers(0, 256, size=(4, cfg.height, cfg.width))
    run, _ = run_axi_beats(cfg, frames, store_fields=dict(data_bits=64, burst_beats=2,
                                                          outstanding=3),
                           latency=latency, ready=0.6, valid=0.7, valid_probability=0.8,
                           ready_probability=0.8, seed=seed)
    assert_states_equal(run.outputs, reference_states(cfg, frames))


def test_p_pixels_unexpected_first_resynchronises():
    """P = 2: a frame cut short after 30 beats, then frames with `first`: a new segment
    starts there, the prefetcher restarts (words of 2 states) under a random latency."""
    from helpers.hw_harness import FIELDS
    from helpers.wide_harness import frames_to_beats
    cfg = DPConfig(width=16, height=12, segment_frames=3, pixels_per_clock=2).build_config()
    frames = np.random.default_rng(12).integers(0, 256, size=(6, cfg.height, cfg.width))
    cut = 30
    beats = frames_to_beats(cfg, frames[:1]) + frames_to_beats(cfg, frames[1:2])[:cut] \
        + frames_to_beats(cfg, frames[2:])
    run, _ = run_axi_beats(cfg, frames, store_fields=dict(data_bits=64, burst_beats=4),
                           latency=(0, 50), ready=0.7, valid=0.7, valid_probability=0.8,
                           ready_probability=0.8, seed=4, beats=beats)
    head = reference_states(cfg, frames[:2])
    truncated = head[1].reshape(-1, len(FIELDS))[:2 * cut].copy()
    truncated[:, 3:] = 0                          # the cut frame never ends
    tail = reference_states(cfg, frames[2:])      # a new segment from frame 2
    expected = np.concatenate([head[0].reshape(-1, len(FIELDS)), truncated,
                               tail.reshape(-1, len(FIELDS))])
    assert len(run.outputs) == len(expected)
    for n, (got, want) in enumerate(zip(run.outputs, expected)):
        assert [got[f] for f in FIELDS] == want.tolist(), f"output {n}"


@pytest.mark.parametrize("p", [1, 2, 4])
def test_the_ecp5_build_keeps_the_bits_and_the_cycles(monkeypatch, p):
    """Every ECP5 option (``Family.options_for``: the store's ``ready`` a register, its
    burst descriptors staged, the prefetch FIFO and the DP16KD styles modelled) at P = 1, 2
    and 4: at zero latency the first beat enters in cycle 6 (a cycle after the generic
    build's), then one every cycle; under latency and stalls the golden model's bits."""
    from dptbd.hw.flow.family import ECP5
    model_dp16kd_cells(monkeypatch)
    cfg = DPConfig(width=16, height=12, segment_frames=3, pixels_per_clock=p).build_config()
    frames = np.random.default_rng(20 + p).integers(0, 256, size=(4, cfg.height, cfg.width))
    options = ECP5.options_for(cfg)
    run_ = run_axi if p == 1 else run_axi_beats
    run, _ = run_(cfg, frames, store_fields=dict(data_bits=64, burst_beats=4), **options)
    assert run.accept_cycles == list(range(6, 6 + 4 * cfg.frame_beats))
    assert_states_equal(run.outputs, reference_states(cfg, frames))
    run, _ = run_(cfg, frames, store_fields=dict(data_bits=64, burst_beats=2, outstanding=3),
                  latency=(0, 60), ready=0.6, valid=0.7, valid_probability=0.8,
                  ready_probability=0.8, seed=p, **options)
    assert_states_equal(run.outputs, reference_states(cfg, frames))


@pytest.mark.parametrize("p", [1, 2, 4])
def test_the_ecp5_build_after_a_resynchronisation(monkeypatch, p):
    """A frame cut short, then frames with `first`, at zero latency: the ECP5 build (its
    prefetcher's restart loads a cycle after the restart) accepts every beat a cycle after
    the generic build up to the resynchronising one, then at P = 1 two cycles after (the
    loads' cycle), at P = 2 and 4 still one (the refetch decides there); the same bits."""
    from dptbd.hw.flow.family import ECP5
    from helpers.wide_harness import frames_to_beats
    model_dp16kd_cells(monkeypatch)
    cfg = DPConfig(width=16, height=12, segment_frames=3, pixels_per_clock=p).build_config()
    frames = np.random.default_rng(12).integers(0, 256, size=(4, cfg.height, cfg.width))
    if p == 1:
        cut, run_ = 100, run_axi
        kw = dict(stream=frames_to_stream(frames[:1]) + frames_to_stream(frames[1:2])[:cut]
                  + frames_to_stream(frames[2:]))
    else:
        cut, run_ = 30, run_axi_beats
        kw = dict(beats=frames_to_beats(cfg, frames[:1]) + frames_to_beats(cfg, frames[1:2])[:cut]
                  + frames_to_beats(cfg, frames[2:]))
    fields = dict(data_bits=64, burst_beats=4)
    generic, _ = run_(cfg, frames, store_fields=fields, **kw)
    ecp5, _ = run_(cfg, frames, store_fields=fields, **kw, **ECP5.options_for(cfg))
    resync = cfg.frame_beats + cut + 1            # beats up to the resynchronising one
    late = 2 if p == 1 else 1
    assert ecp5.accept_cycles == ([c + 1 for c in generic.accept_cycles[:resync]]
                                  + [c + late for c in generic.accept_cycles[resync:]])
    assert ecp5.outputs == generic.outputs
