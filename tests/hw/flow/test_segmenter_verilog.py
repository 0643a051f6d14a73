"""``dptbd.hw.flow.segmenter_verilog``: the segmenter top ``dptbd_seg`` as Verilog with its
manifest, lint-clean under the project's Verilator flags; n = 0 refused."""

import shutil
import subprocess
import warnings

import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.errors import ConfigError
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.flow.segmenter_verilog import SEGMENTER_MODULE_NAME, generate_segmenter_verilog
from dptbd.hw.flow.verilog import VERILATOR_LINT_FLAGS


def seg_config(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def test_verilog_and_manifest(tmp_path):
    cfg = seg_config(width=8, height=6, segment_frames=3, candidate_count=4, histogram_bits=5)
    text, info = generate_segmenter_verilog(cfg, manifest_path=tmp_path / "dptbd_seg.json")
    assert "module dptbd_seg(" in text
    ports = {p["name"]: p for p in info["ports"]}
    width = candidate_layout(cfg).size
    assert ports["candidates__payload"] == {"name": "candidates__payload",
                                            "direction": "output", "width": width}
    assert info["layouts"]["candidate"]["end_of_list"]["offset"] == width - 1
    assert info["latency"] == 17 and info["scan_cycles"] == 36
    assert (tmp_path / "dptbd_seg.json").exists()
    if shutil.which("iverilog"):
        (tmp_path / "dptbd_seg.v").write_text(text)
        subprocess.run(["iverilog", "-g2012", "-o", str(tmp_path / "a.out"),
                        str(tmp_path / "dptbd_seg.v")], check=True, capture_output=True)


@pytest.mark.skipif(shutil.which("verilator") is None, reason="verilator not installed")
@pytest.mark.parametrize("kw", [
    dict(width=8, height=6, segment_frames=3, candidate_count=4, histogram_bits=5),
    dict(width=13, height=9, segment_frames=3, candidate_count=1),     # C = 2, 1-bit count
    dict(width=128, height=128, segment_frames=6),                    # dptbd run's FPGA stage
], ids=["8x6-n4", "13x9-n1", "128x128-default"])
def test_segmenter_verilog_lints_clean(tmp_path, kw):
    """``dptbd_seg`` (what ``dptbd run --rtl`` simulates) under the same Verilator flags as
    ``dptbd_dp`` (``dptbd.hw.flow.verilog.VERILATOR_LINT_FLAGS``, waivers justified there)."""
    text, _ = generate_segmenter_verilog(seg_config(**kw))
    path = tmp_path / "dptbd_seg.v"
    path.write_text(text)
    run = subprocess.run(["verilator", *VERILATOR_LINT_FLAGS, "--top-module", SEGMENTER_MODULE_NAME,
                          str(path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


def test_segmenter_verilog_refuses_zero_points():
    """0.2 % of 13 x 9 rounds to n = 0: refused with the parameter named, not emitted as
    zero-width Verilog."""
    with pytest.raises(ConfigError,
                       match=r"^candidate_count: n = 0 candidate points per segment "
                             r"\(0\.2 % of 13x9 = 117 pixels rounds to 0\) gives a segmenter "
                             r"that emits no points; set candidate_count to 1 … 117$"):
        generate_segmenter_verilog(seg_config(width=13, height=9, segment_frames=3))
