"""dptbd.sim.benches.dp_axi: the --state-store axi build of dptbd_dp on Icarus (4-state) with
cocotbext-axi's AxiRam, bit-exact with the golden model, X-free, with random pauses."""

import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.flow.verilog import MODULE_NAME, generate_verilog
from dptbd.sim.icarus import TIMESCALE


def run_bench(tmp_path, cfg, frames, store_fields, *, pause=0.0, seed=0):
    from cocotb_tools.runner import get_runner
    store = cfg.axi_store(**store_fields)
    text, _ = generate_verilog(cfg, state_store=store)
    verilog = tmp_path / f"{MODULE_NAME}.v"
    verilog.write_text(text)
    runner = get_runner("icarus")
    runner.build(sources=[verilog], hdl_toplevel=MODULE_NAME, build_dir=tmp_path,
                 timescale=TIMESCALE)
    np.save(tmp_path / "scene.npy", frames)
    job = {"config": cfg.to_mapping(), "store": store_fields, "pause": pause, "seed": seed,
           "summary": str(tmp_path / "summary.json")}
    (tmp_path / "job.json").write_text(json.dumps(job))
    try:
        runner.test(test_module="dptbd.sim.benches.dp_axi", hdl_toplevel=MODULE_NAME,
                    hdl_toplevel_lang="verilog", build_dir=tmp_path, test_dir=tmp_path,
                    extra_env={"DPTBD_SIM_JOB": str(tmp_path / "job.json"),
                               "DPTBD_SIM_SCENE": str(tmp_path / "scene.npy")},
                    timescale=TIMESCALE, log_file=tmp_path / "sim.log")
    except (SystemExit, RuntimeError):
        pass
    summary_path = tmp_path / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    cases = [case for xml in tmp_path.glob("*.xml") for case in ET.parse(xml).getroot().iter("testcase")]
    passed = bool(cases) and all(case.find("failure") is None and case.find("error") is None
                                 for case in cases)
    return passed, summary, (tmp_path / "sim.log").read_text()[-3000:]


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
