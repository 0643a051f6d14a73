"""The HDL user's package of ``dptbd_axi``: manifest, FuseSoC core (read back by FuseSoC's
own parser), and the Verilog under Verilator's lint with the project's waivers."""

import json
import os
import shutil
import subprocess
import sysconfig

import pytest
from fusesoc.capi2.core import CoreInterface
from fusesoc.capi2.coreparser import Core2Parser

from dptbd.errors import DptbdError
from dptbd.hw.flow import register_outputs
from dptbd.hw.flow.axi_package import (axi_package, clock_constraints, html_folder_name,
                                       package_file_names, write_html_reference)
from dptbd.hw.flow.verilog import VERILATOR_LINT_FLAGS
from dptbd.hw.register_map import register_constants, register_map
from helpers.seg_harness import make_config
from helpers.refusals import whole


@pytest.fixture(scope="module")
def package(tmp_path_factory):
    cfg = make_config(width=12, height=10, candidate_count=3)
    folder = tmp_path_factory.mktemp("axi")
    files = axi_package(cfg, "top")
    for name, text in files.items():
        (folder / name).write_text(text)
    return cfg, folder, files


def test_manifest_lists_axi_ports_and_registers(package):
    cfg, _folder, files = package
    manifest = json.loads(files["top.json"])
    ports = {p["name"]: p for p in manifest["ports"]}
    assert {"aclk", "aresetn", "s_axis_video_tdata", "s_axis_video_tuser", "s_axis_video_tlast",
            "m_axis_cand_tdata", "m_axis_cand_tlast", "s_axil_awaddr", "s_axil_rresp",
            "irq"} <= set(ports)
    assert not any(name.startswith(("clk", "rst", "pixels", "lut_")) for name in ports)
    assert ports["s_axis_video_tdata"] == {"name": "s_axis_video_tdata", "direction": "input",
                                           "width": 8}
    assert ports["s_axil_rdata"]["direction"] == "output" and ports["s_axil_awaddr"]["width"] == 12
    assert ports["m_axis_cand_tdata"]["width"] % 8 == 0
    assert manifest["registers"]["REG_ERROR"] == register_map(cfg)["ERROR"].address
    # start of frame is tuser[0]: the video tdata carries the pixel only
    assert manifest["streams"]["s_axis_video"]["layout"] == {
        "pixel": {"offset": 0, "width": cfg.input_bits}}


def test_package_carries_the_register_references(package, tmp_path):
    """Beside the Verilog: PeakRDL's Markdown and IP-XACT of the build's map (the same texts
    :mod:`dptbd.hw.flow.register_outputs` renders), named in the manifest; the HTML
    reference is a folder written beside them."""
    cfg, _folder, files = package
    assert list(files) == package_file_names("top")
    assert files["top_regs.md"] == register_outputs.markdown(cfg)
    assert files["top_regs.xml"] == register_outputs.ipxact(cfg)
    assert files["dptbd_regs.h"] == register_outputs.c_header(cfg)
    assert json.loads(files["top.json"])["register_references"] == {
        "markdown": "top_regs.md", "ipxact": "top_regs.xml", "html": "top_regs_html/index.html"}
    write_html_reference(tmp_path, cfg, "top")
    assert html_folder_name("top") == "top_regs_html"
    html = tmp_path / "top_regs_html"
    assert (html / "index.html").is_file()
    assert "SEGMENT_FRAMES" in (html / "data" / "ral-data-0.json").read_text()
    assert any("range_max" in page.read_text() for page in (html / "content").glob("*.html"))


def test_fusesoc_parses_the_core(package):
    _cfg, folder, _files = package
    core = CoreInterface(Core2Parser(), folder / "top.core")
    assert str(core.name) == "dptbd:dptbd:top:0.1.0"
    common = [("top.v", "verilogSource"), ("dptbd_regs.h", "cSource")]
    for tool, constraints in (("quartus", ("top.sdc", "SDC")), ("vivado", ("top.xdc", "xdc")),
                              ("nextpnr", ("top.sdc", "SDC"))):
        files = core.get_files({"target": "default", "tool": tool})
        assert [(f["name"], f["file_type"]) for f in files] == [*common, constraints], tool
        assert files[1]["is_include_file"] is True
    assert core.get_toplevel({"target": "lint"}) == "dptbd_axi"


def test_constraints_clock_aclk_at_the_requested_period(package):
    _cfg, _folder, files = package
    for suffix in ("sdc", "xdc"):
        lines = files[f"top.{suffix}"].splitlines()
        assert lines[-1] == "create_clock -name aclk -period 10.000 [get_ports aclk]"
        assert all(line.startswith("#") for line in lines[:-1])
    assert "Vivado" in files["top.xdc"] and "Quartus" in files["top.sdc"]
    manifest = json.loads(files["top.json"])
    assert manifest["constraints"] == {"sdc": "top.sdc", "xdc": "top.xdc", "period_ns": 10.0}
    assert manifest["clock"]["frequency_mhz"] == 100.0
    assert clock_constraints(150, "sdc").splitlines()[-1] == \
        "create_clock -name aclk -period 6.667 [get_ports aclk]"


@pytest.mark.parametrize("mhz", [0.5, 1000.5, float("nan"), "100"])
def test_constraints_refuse_a_clock_out_of_range(mhz):
    with pytest.raises(DptbdError, match=whole(f"clock_mhz must be a finite real number in "
                                               f"[1, 1000], got {mhz!r}")):
        axi_package(make_config(width=8, height=6, candidate_count=2), clock_mhz=mhz)


def _fusesoc() -> str | None:
    """The ``fusesoc`` executable beside the running Python (the ``test`` extra)."""
    return shutil.which("fusesoc", path=sysconfig.get_path("scripts")) or shutil.which("fusesoc")


@pytest.mark.skipif(shutil.which("verilator") is None or _fusesoc() is None,
                    reason="needs Verilator and FuseSoC")
# the default suite lints the two corners (radius 1 binary LUT, radius 2 fractional LUT)
@pytest.mark.parametrize("radius, fractional_lut", [
    (1, False), pytest.param(1, True, marks=pytest.mark.slow),
    pytest.param(2, False, marks=pytest.mark.slow), (2, True)])
def test_fusesoc_lint_target_passes_with_no_warning(tmp_path, radius, fractional_lut):
    """``fusesoc --cores-root DIR run --target lint`` on the core as ``dptbd verilog --top
    axi [--radius 2] [--fractional-lut]`` writes it (``build_config``: the binary LUT builds
    with F = 0): edalize's lint flow runs Verilator ``-Wall`` with the project's waivers,
    with no warning and no deprecation of the core's description."""
    cfg = make_config(radius=radius).build_config(fractional_lut=fractional_lut)
    assert cfg.weight_frac_bits == (8 if fractional_lut else 0)
    folder = tmp_path / "rtl"
    folder.mkdir()
    for name, text in axi_package(cfg, "top").items():
        (folder / name).write_text(text)
    env = {**os.environ, **{f"XDG_{kind}_HOME": str(tmp_path / kind.lower())
                            for kind in ("CONFIG", "CACHE", "DATA")}}
    run = subprocess.run([_fusesoc(), "--monochrome", "--cores-root", str(folder), "run",
                          "--build-root", str(tmp_path / "build"), "--target", "lint",
                          "dptbd:dptbd:top"], cwd=tmp_path, env=env, capture_output=True,
                         text=True)
    log = run.stdout + run.stderr
    assert run.returncode == 0, log
    assert "%Warning" not in log and "deprecated" not in log.lower(), log
    assert "verilator -f dptbd_dptbd_top_0.1.0.vc" in log
    work = tmp_path / "build" / "dptbd_dptbd_top_0.1.0" / "lint"
    options = (work / "dptbd_dptbd_top_0.1.0.vc").read_text().split()
    assert options[:7] == ["--Mdir", ".", "--lint-only", *VERILATOR_LINT_FLAGS[1:]]
    assert options[-3:] == ["src/dptbd_dptbd_top_0.1.0/top.v", "--top-module", "dptbd_axi"]


@pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")
def test_verilog_lints_clean(package):
    _cfg, folder, _files = package
    run = subprocess.run(["verilator", *VERILATOR_LINT_FLAGS, "top.v", "--top-module",
                          "dptbd_axi"], cwd=folder, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


@pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")
@pytest.mark.parametrize("p", [2, 4])
def test_wide_verilog_lints_clean(tmp_path, p):
    """At P = 2 and 4 pixels per clock (``AXITopWide``) under the same lint."""
    cfg = make_config(width=12, height=10, candidate_count=3, pixels_per_clock=p)
    (tmp_path / "top.v").write_text(axi_package(cfg.build_config(), "top")["top.v"])
    run = subprocess.run(["verilator", *VERILATOR_LINT_FLAGS, "top.v", "--top-module",
                          "dptbd_axi"], cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


def test_state_output_adds_m_axis_state_to_ports_and_manifest():
    cfg = make_config(width=8, height=6, candidate_count=2)
    manifest = json.loads(axi_package(cfg, "s", state_output=True)["s.json"])
    ports = {p["name"]: p for p in manifest["ports"]}
    assert ports["m_axis_state_tuser"] == {"name": "m_axis_state_tuser", "direction": "output",
                                           "width": 4}
    assert ports["m_axis_state_tready"]["direction"] == "input"
    assert ports["m_axis_state_tdata"]["width"] == 8 * -(-(cfg.energy_bits
                                                          + cfg.direction_bits) // 8)
    state = manifest["streams"]["m_axis_state"]
    assert (state["tuser[0]"], state["tuser[1]"], state["tuser[2]"], state["tuser[3]"],
            state["tlast"]) == (
        "start of frame", "end of frame", "end of segment",
        "filler word completing a line cut by a soft reset (tdata 0, no other tuser bit)",
        "end of line")
    plain = json.loads(axi_package(cfg, "p")["p.json"])
    assert "m_axis_state" not in plain["streams"]
    assert manifest["latency"] == plain["latency"] + 1          # the broadcast's register


@pytest.mark.skipif(shutil.which("verilator") is None, reason="needs Verilator")
# the default suite: the narrowest bus at P = 1 and the widest at P = 4
@pytest.mark.parametrize("data_bits, p", [
    (32, 1), pytest.param(128, 1, marks=pytest.mark.slow),
    pytest.param(128, 2, marks=pytest.mark.slow), (128, 4)])
def test_state_store_package_lints_clean_and_names_the_port(tmp_path, data_bits, p):
    """``--state-store axi`` (at P = 1, 2 and 4 pixels per clock): the Verilog (with
    ``m_axi_state_*``) under the same lint, the core file parsed by FuseSoC, the manifest's
    ``state_store`` entry and the header's registers."""
    cfg = make_config(width=12, height=10, candidate_count=3,
                      pixels_per_clock=p).build_config()
    store = cfg.axi_store(data_bits=data_bits, burst_beats=2, id_bits=2)
    files = axi_package(cfg, "top", state_store=store)
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    run = subprocess.run(["verilator", *VERILATOR_LINT_FLAGS, "top.v", "--top-module",
                          "dptbd_axi"], cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    manifest = json.loads(files["top.json"])
    assert manifest["state_store"]["data_bits"] == data_bits
    ports = {p["name"]: p["width"] for p in manifest["ports"]}
    assert ports["m_axi_state_rdata"] == data_bits and ports["m_axi_state_bid"] == 2
    assert manifest["registers"] == register_constants(register_map(cfg, store))
    core = CoreInterface(Core2Parser(), tmp_path / "top.core")
    assert core.get_toplevel({"target": "lint"}) == "dptbd_axi"
    assert "m_axi_state_*" in (tmp_path / "top.core").read_text().splitlines()[2]
    assert "#define DPTBD_AXI__CONTROL__STATE_BASE__STATE_BASE_bm 0xffffffff" in \
        files["dptbd_regs.h"]
    assert "uint32_t STATE_BASE;" in files["dptbd_regs.h"]
    assert manifest["top"] == "AXITopStore" and ports["s_axis_video_tdata"] == 8 * p
    assert ("#define DPTBD_PIXELS_PER_CLOCK" in files["dptbd_regs.h"]) == (p > 1)
