"""Shared pieces of the cocotb + Icarus tests: configurations without the saturation
warning, cached builds per design, pause specs, and the pass assertion with the log tail."""

from __future__ import annotations

import pathlib
import warnings

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.sim.icarus import build

BUILD_ROOT = pathlib.Path(__file__).resolve().parents[2] / "build" / "sim"
CYCLE = {"kind": "pattern", "pattern": [1, 1, 1, 0]}          # verilog-axis's cycle_pause

_BUILDS: dict = {}


def random_pause(probability: float, seed: int) -> dict:
    """A :func:`dptbd.sim.benches.drivers.pause_generator` spec pausing with ``probability``."""
    return {"kind": "random", "probability": probability, "seed": seed}


def make_config(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def built(cfg: DPConfig, design: str):
    """:func:`dptbd.sim.icarus.build` of ``design`` for ``cfg``, once per test session."""
    if (cfg, design) not in _BUILDS:
        _BUILDS[cfg, design] = build(cfg, BUILD_ROOT, design=design)
    return _BUILDS[cfg, design]


def assert_passed(result) -> None:
    assert result.passed, f"{result.report}\n--- {result.log} (tail) ---\n{result.log_tail()}"


def run_store_bench(tmp_path, cfg: DPConfig, frames, store_fields: dict, *, verilog: str,
                    module: str, bench: str, pause: float = 0.0, seed: int = 0):
    """Build ``verilog`` (the top ``module`` with the AXI4 state store ``store_fields``) on
    Icarus with cocotb's runner and run the cocotb module ``bench`` on ``frames`` with
    cocotbext-axi's ``AxiRam``: whether every cocotb test passed, the bench's summary and the
    log's tail. Vendor cells in ``verilog`` (an ECP5 build's ``DP16KD``) are compiled with
    their 4-state models (:func:`dptbd.sim.cell_models.model_sources`)."""
    import json
    import xml.etree.ElementTree as ET

    import numpy as np
    from cocotb_tools.runner import get_runner

    from dptbd.sim.cell_models import model_sources
    from dptbd.sim.icarus import TIMESCALE

    source = tmp_path / f"{module}.v"
    source.write_text(verilog)
    runner = get_runner("icarus")
    runner.build(sources=[source, *model_sources(verilog)], hdl_toplevel=module,
                 build_dir=tmp_path, timescale=TIMESCALE)
    np.save(tmp_path / "scene.npy", frames)
    job = {"config": cfg.to_mapping(), "store": store_fields, "pause": pause, "seed": seed,
           "summary": str(tmp_path / "summary.json")}
    (tmp_path / "job.json").write_text(json.dumps(job))
    try:
        runner.test(test_module=bench, hdl_toplevel=module, hdl_toplevel_lang="verilog",
                    build_dir=tmp_path, test_dir=tmp_path,
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
