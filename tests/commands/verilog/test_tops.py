"""``dptbd verilog --top axi`` and ``--top seg``: the drop-in core's module, header, manifest
and package, its clock and state output, and the options each top refuses."""

from __future__ import annotations

import json

import pytest

from dptbd.commands import verilog as verilog_command
from helpers.command_args import parser_of
from helpers.refusals import whole

parse = parser_of(verilog_command)


def test_verilog_top_axi_writes_module_header_manifest_and_core(tmp_path, capsys):
    toml = tmp_path / "p.toml"
    toml.write_text("width = 16\nheight = 12\ncandidate_count = 4\n")
    out = tmp_path / "rtl" / "mine.v"
    assert verilog_command.main(parse(["-o", out, "--config", toml, "--top", "axi"])) == 0
    names = sorted(p.name for p in out.parent.iterdir())
    assert names == ["component.xml", "dptbd_regs.h", "mine.core", "mine.json", "mine.sdc",
                     "mine.v", "mine.xdc", "mine_regs.md", "mine_regs.xml", "mine_regs_html"]
    assert (out.parent / "mine_regs_html" / "index.html").is_file()
    assert "module dptbd_axi(" in out.read_text()
    assert "<spirit:name>mine.v</spirit:name>" in (out.parent / "component.xml").read_text()
    manifest = json.loads((out.parent / "mine.json").read_text())
    assert manifest["module"] == "dptbd_axi" and manifest["parameters"]["width"] == 16
    assert manifest["reset"] == {"name": "aresetn", "polarity": "active_low",
                                 "kind": "synchronous"}
    assert "    uint32_t SEGMENT_FRAMES;\n" in (out.parent / "dptbd_regs.h").read_text()
    assert "### SEGMENT_FRAMES register" in (out.parent / "mine_regs.md").read_text()
    assert "<ipxact:name>SEGMENT_FRAMES</ipxact:name>" in (out.parent / "mine_regs.xml").read_text()
    assert "      - mine.v" in (out.parent / "mine.core").read_text()
    assert "      - mine.sdc" in (out.parent / "mine.core").read_text()
    assert (out.parent / "mine.sdc").read_text().endswith(
        "create_clock -name aclk -period 10.000 [get_ports aclk]\n")
    assert "(module dptbd_axi, 16x12, latency" in capsys.readouterr().out


def test_verilog_top_axi_clock_option(tmp_path, capsys):
    out = tmp_path / "a.v"
    assert verilog_command.main(parse(["-o", out, "--top", "axi", "--width", 8, "--height", 6,
                                       "--clock-mhz", 125])) == 0
    assert (tmp_path / "a.xdc").read_text().endswith(
        "create_clock -name aclk -period 8.000 [get_ports aclk]\n")
    assert "aclk 125 MHz)" in capsys.readouterr().out
    with pytest.raises(ValueError, match=r"^--clock-mhz must be a finite real number in "
                                         r"\[1, 1000\], got 0\.0$"):
        verilog_command.main(parse(["-o", out, "--top", "axi", "--width", 8, "--height", 6,
                                    "--clock-mhz", 0, "--force"]))
    with pytest.raises(ValueError, match=r"^--clock-mhz applies to --top axi only \(dptbd_dp "
                                         r"ships no constraints\)$"):
        verilog_command.main(parse(["-o", tmp_path / "d.v", "--width", 8, "--height", 6,
                                    "--clock-mhz", 50]))
    assert not (tmp_path / "d.v").exists()


def test_verilog_top_axi_state_output(tmp_path):
    out = tmp_path / "s.v"
    assert verilog_command.main(parse(["-o", out, "--top", "axi", "--width", 8, "--height", 6,
                                       "--state-output"])) == 0
    assert "  output m_axis_state_tvalid;" in out.read_text()
    with pytest.raises(ValueError, match=r"^--state-output applies to --top axi only "
                                         r"\(dptbd_dp always outputs its states\)$"):
        verilog_command.main(parse(["-o", tmp_path / "d.v", "--width", 8, "--height", 6,
                                    "--state-output"]))


def test_verilog_top_axi_refuses_existing_files_and_dp_only_options(tmp_path):
    out = tmp_path / "dptbd_axi.v"
    (tmp_path / "dptbd_regs.h").write_text("mine")
    (tmp_path / "dptbd_axi.core").write_text("mine")
    names = [tmp_path / n for n in ("dptbd_regs.h", "dptbd_axi.core")]
    with pytest.raises(FileExistsError,
                       match=whole(f"{names[0]} and {names[1]} exist; pass --force to overwrite")):
        verilog_command.main(parse(["-o", out, "--top", "axi", "--width", 8, "--height", 6]))
    assert not out.exists() and (tmp_path / "dptbd_regs.h").read_text() == "mine"
    (tmp_path / "dptbd_axi.json").write_text("mine")
    (tmp_path / "dptbd_axi.xdc").write_text("mine")
    three = ", ".join(str(tmp_path / n)
                      for n in ("dptbd_axi.json", "dptbd_regs.h", "dptbd_axi.xdc"))
    with pytest.raises(FileExistsError,
                       match=whole(f"{three} and {names[1]} exist; pass --force to overwrite")):
        verilog_command.main(parse(["-o", out, "--top", "axi", "--width", 8, "--height", 6]))
    for top in ("axi", "seg"):
        for option in (["--lut-style", "logic"], ["--external-state-store"]):
            with pytest.raises(ValueError, match=whole(
                    f"--external-state-store and --lut-style apply to --top dp only; --top "
                    f"{top} keeps the state store on chip with the automatic LUT style")):
                verilog_command.main(parse(["-o", out, "--top", top, *option, "--force"]))
    toml = tmp_path / "p.toml"
    toml.write_text("width = 8\nheight = 6\ncandidate_count = 2\n")
    assert verilog_command.main(parse(["-o", out, "--top", "axi", "--config", toml,
                                       "--force"])) == 0
    assert (tmp_path / "dptbd_regs.h").read_text().startswith("// Generated by PeakRDL-cheader")


def test_verilog_top_seg_refuses_the_axi_only_options(tmp_path):
    out = tmp_path / "s.v"
    for option, message in (
            (["--clock-mhz", 50], "--clock-mhz applies to --top axi only (dptbd_seg ships no "
                                  "constraints)"),
            (["--allow-saturation"], "--allow-saturation applies to --top axi only"),
            (["--state-output"], "--state-output applies to --top axi only")):
        with pytest.raises(ValueError, match=whole(message)):
            verilog_command.main(parse(["-o", out, "--top", "seg", "--width", 8, "--height", 6,
                                        *option]))
    assert list(tmp_path.iterdir()) == []
