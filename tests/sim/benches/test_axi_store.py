"""dptbd.sim.benches.axi_store: ``dptbd_axi --state-store axi`` on Icarus (4-state) with
cocotbext-axi's AxiRam on m_axi_state_*, every list the model's, no X on any output."""

import shutil

import pytest

from dptbd.hw.axi_top import AXI_MODULE_NAME
from dptbd.hw.flow.axi_package import generate_axi_verilog
from dptbd.hw.flow.family import ECP5
from dptbd.sim.scenarios import make_frames
from helpers.cocotb_harness import run_store_bench
from helpers.verilator_harness import make_config

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")

# 12 x 10, K = 2 (K_max = 4), n = 4, C = 6, 64 bins of width 4: lists with records
SMALL = dict(width=12, height=10, segment_frames=2, max_segment_frames=4, candidate_count=4,
             candidate_capacity=6, histogram_bits=6, histogram_shift=2)


def run_bench(tmp_path, cfg, frames, store_fields, *, pause=0.0, seed=0, core_options=None):
    text, _ = generate_axi_verilog(cfg, state_store=cfg.axi_store(**store_fields),
                                   core_options=core_options)
    return run_store_bench(tmp_path, cfg, frames, store_fields, verilog=text, module=AXI_MODULE_NAME,
                           bench="dptbd.sim.benches.axi_store", pause=pause, seed=seed)


@pytest.mark.parametrize("store_fields, pause, p", [
    (dict(data_bits=64, burst_beats=4), 0.0, 1),
    (dict(data_bits=32, burst_beats=2, outstanding=2), 0.3, 1),
    (dict(data_bits=64, burst_beats=2, outstanding=2), 0.3, 2),
    (dict(data_bits=64, burst_beats=4), 0.0, 4),
])
def test_axi_ram_bench_lists_exact_and_x_free(tmp_path, store_fields, pause, p):
    """At P = 1, 2 and 4 pixels per clock (beats of P pixels)."""
    cfg = make_config(**SMALL, pixels_per_clock=p).build_config()
    frames = make_frames("two-targets", cfg, 6, seed=1)
    passed, summary, log = run_bench(tmp_path, cfg, frames, store_fields, pause=pause, seed=3)
    assert passed, (summary, log)
    assert summary["lists"] == 3 and all(summary["exact"]) and summary["x"] == []
    assert summary["records"] > 0


@pytest.mark.parametrize("store_fields, pause, p", [
    (dict(data_bits=64, burst_beats=4), 0.3, 1),
    (dict(data_bits=64, burst_beats=2, outstanding=2), 0.3, 2),
])
def test_the_ecp5_build_on_the_dp16kd_model_is_exact_and_x_free(tmp_path, store_fields, pause,
                                                                 p):
    """The ECP5 family's build (``Family.options_for``: the prefetcher's beat FIFO in
    DP16KDs, here with the line buffer in DP16KDs too) on the 4-state DP16KD model
    (``sim/dp16kd.v``: X until written or loaded), at P = 1 and 2."""
    cfg = make_config(**SMALL, pixels_per_clock=p).build_config()
    options = {**ECP5.options_for(cfg), "line_buffer_style": "dp16kd"}
    frames = make_frames("two-targets", cfg, 6, seed=1)
    passed, summary, log = run_bench(tmp_path, cfg, frames, store_fields, pause=pause, seed=5,
                                     core_options=options)
    assert "DP16KD #(" in (tmp_path / f"{AXI_MODULE_NAME}.v").read_text()
    assert passed, (summary, log)
    assert summary["lists"] == 3 and all(summary["exact"]) and summary["x"] == []
    assert summary["records"] > 0
