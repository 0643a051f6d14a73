"""DPPipelineAxi: the golden model's bits with the state in a random-latency AXI4 memory."""

import numpy as np
import pytest
from amaranth.back import verilog

from dptbd.config import DPConfig
from dptbd.hw.dp_pipeline_axi import DPPipelineAxi
from dptbd.sim.axi4_memory import Axi4Memory
from helpers.hw_harness import (assert_states_equal, assert_verilator_lints_clean,
                                frames_to_stream, reference_states, run_stream)
from helpers.verilator_harness import needs_verilator


def run_axi(cfg, frames, *, store_fields=(), latency=(0, 0), ready=1.0, valid=1.0,
            valid_probability=1.0, ready_probability=1.0, seed=0, stream=None,
            write_latency=None):
    store = cfg.axi_store(**dict(store_fields))
    dut = DPPipelineAxi(store)
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
    ((0, 600), 0.8, 0.7, 2),
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
    """Memory always ready, no latency: the first pixel enters in cycle 4 (the AR register,
    the memory's answer, the beat FIFO's two registers), then one pixel every cycle."""
    cfg = DPConfig(width=16, height=12, segment_frames=3)
    frames = np.random.default_rng(3).integers(0, 256, size=(4, cfg.height, cfg.width))
    run, _ = run_axi(cfg, frames, store_fields=dict(data_bits=64, burst_beats=4))
    assert run.accept_cycles == list(range(4, 4 + 4 * 192))
    assert_states_equal(run.outputs, reference_states(cfg, frames))


@needs_verilator
@pytest.mark.parametrize("kw, store_fields", [
    (dict(width=640, height=512), dict(data_bits=64)),              # 2 states per beat
    (dict(width=16, height=12), dict(data_bits=32, burst_beats=2)),  # 1 state per beat
    (dict(width=1280, height=1024, segment_frames=8), dict(data_bits=128)),
])
def test_verilog_lints_clean(tmp_path, kw, store_fields):
    store = DPConfig(**kw).build_config().axi_store(**store_fields)
    path = tmp_path / "dptbd_dp_axi.v"
    path.write_text(verilog.convert(DPPipelineAxi(store), name="dptbd_dp_axi"))
    assert_verilator_lints_clean(path, "dptbd_dp_axi")
