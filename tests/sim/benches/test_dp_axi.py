"""dptbd.sim.benches.dp_axi: the --state-store axi build of dptbd_dp on Icarus (4-state) with
cocotbext-axi's AxiRam, bit-exact with the golden model, X-free, with random pauses."""

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.flow.family import ECP5
from dptbd.hw.flow.verilog import MODULE_NAME, generate_verilog

from helpers.cocotb_harness import run_store_bench


def run_bench(tmp_path, cfg, frames, store_fields, *, pause=0.0, seed=0, core_options=None):
    text, _ = generate_verilog(cfg, state_store=cfg.axi_store(**store_fields),
                               core_options=core_options)
    return run_store_bench(tmp_path, cfg, frames, store_fields, verilog=text, module=MODULE_NAME,
                           bench="dptbd.sim.benches.dp_axi", pause=pause, seed=seed)


@pytest.mark.parametrize("store_fields, pause", [
    (dict(data_bits=64, burst_beats=4), 0.0),
    (dict(data_bits=32, burst_beats=2, outstanding=2), 0.4),
])
def test_axi_ram_bench_is_bit_exact_and_x_free(tmp_path, store_fields, pause):
    cfg = DPConfig(width=16, height=12, segment_frames=3).build_config()
    frames = np.random.default_rng(2).integers(0, 256, size=(4, cfg.height, cfg.width))
    passed, summary, log = run_bench(tmp_path, cfg, frames, store_fields, pause=pause, seed=3)
    assert passed and summary["verdict"] == "bit-exact", (summary, log)
    assert summary["outputs"] == 4 * 192 and summary["x_or_error"] == []


@pytest.mark.parametrize("p, store_fields, pause", [
    (2, dict(data_bits=64, burst_beats=4), 0.3),       # 2 words of 2 states per beat
    (4, dict(data_bits=64, burst_beats=2, outstanding=2), 0.0),
])
def test_p_pixels_per_clock_on_axi_ram_are_bit_exact_and_x_free(tmp_path, p, store_fields,
                                                                 pause):
    """P = 2 and 4 on Icarus (4-state): beats offered from the first cycle after reset,
    store words of P states in cocotbext-axi's AxiRam, no X on any handshake output."""
    cfg = DPConfig(width=16, height=12, segment_frames=3, pixels_per_clock=p).build_config()
    frames = np.random.default_rng(p).integers(0, 256, size=(4, cfg.height, cfg.width))
    passed, summary, log = run_bench(tmp_path, cfg, frames, store_fields, pause=pause, seed=p)
    assert passed and summary["verdict"] == "bit-exact", (summary, log)
    assert summary["outputs"] == 4 * cfg.frame_beats and summary["x_or_error"] == []
    assert summary["pixels"] == 4 * 192


@pytest.mark.slow
@pytest.mark.parametrize("p", [1, 2])
def test_the_ecp5_build_on_the_dp16kd_model_is_bit_exact_and_x_free(tmp_path, p):
    """The ECP5 family's build (prefetch FIFO in DP16KDs; the line buffer in DP16KDs too)
    on the 4-state DP16KD model (``sim/dp16kd.v``: X until written or loaded)."""
    cfg = DPConfig(width=16, height=12, segment_frames=3, pixels_per_clock=p).build_config()
    options = {**ECP5.options_for(cfg), "line_buffer_style": "dp16kd"}
    frames = np.random.default_rng(p).integers(0, 256, size=(4, cfg.height, cfg.width))
    passed, summary, log = run_bench(tmp_path, cfg, frames, dict(data_bits=64, burst_beats=4),
                                     pause=0.3, seed=p, core_options=options)
    assert "DP16KD #(" in (tmp_path / f"{MODULE_NAME}.v").read_text()
    assert passed and summary["verdict"] == "bit-exact", (summary, log)
    assert summary["outputs"] == 4 * cfg.frame_beats and summary["x_or_error"] == []
