"""dptbd.sim.benches.axi_store: ``dptbd_axi --state-store axi`` on Icarus (4-state) with
cocotbext-axi's AxiRam on m_axi_state_*, every list the model's, no X on any output."""

import json
import shutil
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from dptbd.hw.axi_top import AXI_MODULE_NAME
from dptbd.hw.flow.axi_package import generate_axi_verilog
from dptbd.sim.icarus import TIMESCALE
from dptbd.sim.scenarios import make_frames
from helpers.verilator_harness import make_config

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")

# 12 x 10, K = 2 (K_max = 4), n = 4, C = 6, 64 bins of width 4: lists with records
SMALL = dict(width=12, height=10, segment_frames=2, max_segment_frames=4, candidate_count=4,
             candidate_capacity=6, histogram_bits=6, histogram_shift=2)


def run_bench(tmp_path, cfg, frames, store_fields, *, pause=0.0, seed=0):
    from cocotb_tools.runner import get_runner
    store = cfg.axi_store(**store_fields)
    text, _ = generate_axi_verilog(cfg, state_store=store)
    verilog = tmp_path / f"{AXI_MODULE_NAME}.v"
    verilog.write_text(text)
    runner = get_runner("icarus")
    runner.build(sources=[verilog], hdl_toplevel=AXI_MODULE_NAME, build_dir=tmp_path,
                 timescale=TIMESCALE)
    np.save(tmp_path / "scene.npy", frames)
    job = {"config": cfg.to_mapping(), "store": store_fields, "pause": pause, "seed": seed,
           "summary": str(tmp_path / "summary.json")}
    (tmp_path / "job.json").write_text(json.dumps(job))
    try:
        runner.test(test_module="dptbd.sim.benches.axi_store", hdl_toplevel=AXI_MODULE_NAME,
                    hdl_toplevel_lang="verilog", build_dir=tmp_path, test_dir=tmp_path,
                    extra_env={"DPTBD_SIM_JOB": str(tmp_path / "job.json"),
                               "DPTBD_SIM_SCENE": str(tmp_path / "scene.npy")},
                    timescale=TIMESCALE, log_file=tmp_path / "sim.log")
    except (SystemExit, RuntimeError):
        pass
    summary_path = tmp_path / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    cases = [case for xml in tmp_path.glob("*.xml")
             for case in ET.parse(xml).getroot().iter("testcase")]
    passed = bool(cases) and all(case.find("failure") is None and case.find("error") is None
                                 for case in cases)
    return passed, summary, (tmp_path / "sim.log").read_text()[-3000:]


@pytest.mark.parametrize("store_fields, pause", [
    (dict(data_bits=64, burst_beats=4), 0.0),
    (dict(data_bits=32, burst_beats=2, outstanding=2), 0.3),
])
def test_axi_ram_bench_lists_exact_and_x_free(tmp_path, store_fields, pause):
    cfg = make_config(**SMALL).build_config()
    frames = make_frames("two-targets", cfg, 6, seed=1)
    passed, summary, log = run_bench(tmp_path, cfg, frames, store_fields, pause=pause, seed=3)
    assert passed, (summary, log)
    assert summary["lists"] == 3 and all(summary["exact"]) and summary["x"] == []
    assert summary["records"] > 0
