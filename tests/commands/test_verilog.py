"""``dptbd verilog``: the module and its manifest, overwriting, TOML parameters, LUT style."""

from __future__ import annotations

import argparse
import json
import tomllib
import warnings

import pytest

from dptbd.commands import verilog as verilog_command
from dptbd.config import EnergyWidthWarning
from dptbd.errors import ConfigError
from helpers.refusals import whole


def parse(argv):
    parser = argparse.ArgumentParser()
    verilog_command.add_arguments(parser)
    return parser.parse_args([str(a) for a in argv])


def test_verilog_writes_module_and_manifest(tmp_path, capsys):
    out = tmp_path / "rtl" / "dp.v"
    args = parse(["-o", out, "--width", 13, "--height", 7, "--radius", 2,
                  "--rounding", "half_up", "--fractional-lut"])
    assert verilog_command.main(args) == 0
    text = out.read_text()
    assert "module dptbd_dp(" in text
    manifest = json.loads((tmp_path / "rtl" / "dp.json").read_text())
    assert manifest["parameters"]["width"] == 13 and manifest["parameters"]["radius"] == 2
    assert manifest["parameters"]["rounding"] == "half_up"
    assert manifest["latency"] == 15
    names = {p["name"]: p for p in manifest["ports"]}
    assert {"clk", "rst", "pixels__payload", "states__payload", "lut_we"} <= set(names)
    assert names["pixels__payload"]["width"] == 9                   # B_in + first
    assert "latency 15 cycles" in capsys.readouterr().out


def test_verilog_refuses_to_overwrite_without_force(tmp_path):
    out = tmp_path / "dp.v"
    out.write_text("mine")
    args = parse(["-o", out, "--width", 8, "--height", 6])
    with pytest.raises(FileExistsError,
                       match=whole(f"{out} exists; pass --force to overwrite")):
        verilog_command.main(args)
    assert out.read_text() == "mine" and not (tmp_path / "dp.json").exists()
    (tmp_path / "other.json").write_text("{}")          # an existing manifest counts too
    other = tmp_path / "other.json"
    with pytest.raises(FileExistsError,
                       match=whole(f"{other} exists; pass --force to overwrite")):
        verilog_command.main(parse(["-o", tmp_path / "other.v"]))
    (tmp_path / "other.v").write_text("mine")           # both: one sentence naming both
    both = " and ".join(str(tmp_path / n) for n in ("other.v", "other.json"))
    with pytest.raises(FileExistsError,
                       match=whole(f"{both} exist; pass --force to overwrite")):
        verilog_command.main(parse(["-o", tmp_path / "other.v"]))
    assert verilog_command.main(parse(["-o", out, "--width", 8, "--height", 6,
                                                        "--force"])) == 0
    assert out.read_text().count("module dptbd_dp(") == 1


def test_verilog_reads_toml_and_options_override_it(tmp_path):
    toml = tmp_path / "p.toml"
    toml.write_text('width = 10\nheight = 8\nsegment_frames = 3\nrounding = "half_up"\n'
                    'weight_frac_bits = 4\n')
    out = tmp_path / "dp.v"
    assert verilog_command.main(parse(["-o", out, "--config", toml,
                                                        "--height", 9])) == 0
    params = json.loads(out.with_suffix(".json").read_text())["parameters"]
    assert (params["width"], params["height"], params["segment_frames"]) == (10, 9, 3)
    assert (params["rounding"], params["weight_frac_bits"]) == ("half_up", 0)   # binary LUT
    assert params["energy_bits"] == 10                      # 3 full-scale 8-bit pixels
    assert verilog_command.main(parse(["-o", out, "--config", toml, "--height", 9,
                                       "--fractional-lut", "--force"])) == 0
    params = json.loads(out.with_suffix(".json").read_text())["parameters"]
    assert (params["weight_frac_bits"], params["energy_bits"]) == (4, 10)


def test_verilog_builds_the_narrowed_default_and_says_so(tmp_path, capsys):
    out = tmp_path / "dp.v"
    assert verilog_command.main(parse(["-o", out, "--width", 16, "--height", 16])) == 0
    params = json.loads(out.with_suffix(".json").read_text())["parameters"]
    assert (params["energy_bits"], params["weight_frac_bits"]) == (10, 0)
    assert capsys.readouterr().out.startswith(
        "building B_E=10, F=0 (asked B_E=16, F=8): the same bits for this LUT and K_max=4; "
        "--fractional-lut keeps F\n")


def test_axi_build_refuses_a_saturating_energy_width_unless_allowed(tmp_path):
    out = tmp_path / "axi.v"
    argv = ["-o", out, "--top", "axi", "--width", 16, "--height", 16, "--energy-bits", 9]
    with pytest.raises(ConfigError, match=(
            r"^max_segment_frames: K_max=4 full-scale 8-bit pixels sum to 1020 > E_max=511 of "
            r"energy_bits=9, so E saturates; use energy_bits >= 10 or K_max <= 2, or allow "
            r"saturation explicitly$")):
        verilog_command.main(parse(argv))
    assert not out.exists()
    assert verilog_command.main(parse(argv + ["--allow-saturation"])) == 0
    assert out.exists()
    with pytest.raises(ValueError, match=r"^--allow-saturation applies to --top axi only$"):
        verilog_command.main(parse(["-o", tmp_path / "dp.v", "--allow-saturation"]))


def test_verilog_refuses_unknown_toml_keys_and_bad_values(tmp_path):
    toml = tmp_path / "p.toml"
    toml.write_text("width = 10\nhieght = 8\n")
    allowed = ("['candidate_capacity', 'candidate_count', 'energy_bits', 'forgetting', "
               "'forgetting_bits', 'height', 'histogram_bits', 'histogram_shift', 'input_bits', "
               "'max_segment_frames', 'merit_bits', 'merit_codes', 'penalty_bits', "
               "'penalty_codes', 'pixels_per_clock', 'radius', 'recursive', 'rounding', "
               "'segment_frames', "
               "'segment_stride', 'weight_frac_bits', "
               "'weights', 'width']")
    with pytest.raises(ConfigError, match=whole(f"unknown parameter(s) ['hieght']; "
                                                f"allowed: {allowed} (from {toml})")):
        verilog_command.main(parse(["-o", tmp_path / "a.v", "--config", toml]))
    toml.write_text("width = [1, 2\n")
    with pytest.raises(tomllib.TOMLDecodeError) as parser:   # its words are the parser's own
        tomllib.loads(toml.read_text())
    with pytest.raises(ConfigError, match=whole(f"{toml} is not valid TOML: {parser.value}")):
        verilog_command.main(parse(["-o", tmp_path / "a.v", "--config", toml]))
    with pytest.raises(ConfigError, match=r"^radius must be an integer in \[1, 2\], got 3$"):
        verilog_command.main(parse(["-o", tmp_path / "a.v", "--radius", 3]))
    assert not list(tmp_path.glob("*.v"))


@pytest.mark.parametrize("argv, radius, style", [
    ([], 1, "logic"), (["--lut-style", "auto", "--radius", 2], 2, "bram"),
    (["--lut-style", "bram"], 1, "bram"), (["--lut-style", "logic", "--radius", 2], 2, "logic"),
])
def test_verilog_lut_style(tmp_path, capsys, argv, radius, style):
    """--lut-style: the attribute on the LUT's column memories, the manifest, the summary."""
    out = tmp_path / "dp.v"
    assert verilog_command.main(parse(["-o", out, "--width", 9,
                                                        "--height", 8, *argv])) == 0
    text = out.read_text()
    moves = (2 * radius + 1) ** 2
    assert text.count('(* ram_style = "logic" *)') == (moves if style == "logic" else 0)
    assert json.loads(out.with_suffix(".json").read_text())["lut_style"] == style
    assert f"weight LUT in {style}" in capsys.readouterr().out


def test_verilog_refuses_an_unknown_lut_style(tmp_path, capsys):
    with pytest.raises(SystemExit):
        parse(["-o", tmp_path / "a.v", "--lut-style", "registers"])
    assert "invalid choice: 'registers'" in capsys.readouterr().err


@pytest.mark.parametrize("top", [[], ["--top", "axi", "--allow-saturation"]])
def test_narrow_energy_width_warns_once_and_builds(tmp_path, capsys, top):
    """The warning is printed once, for the asked configuration; the built one (F = 0, the
    same B_E) warns nothing more, neither printed nor as a Python warning."""
    out = tmp_path / "dp.v"
    args = parse(["-o", out, "--width", 8, "--height", 6, "--input-bits", 6,
                  "--energy-bits", 7, *top])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert verilog_command.main(args) == 0
    assert not [w for w in caught if issubclass(w.category, EnergyWidthWarning)]
    err = capsys.readouterr().err
    assert err == ("warning: energy_bits=7 saturates: K=4 full-scale 6-bit pixels sum to 252 "
                   "> 127; energy_bits >= 8 never saturates\n")
    assert json.loads(out.with_suffix(".json").read_text())["parameters"][
        "weight_frac_bits"] == 0                         # built with F = 0: a second config


def test_verilog_max_segment_frames_option(tmp_path):
    """--max-segment-frames sets K_max (DPConfig.max_segment_frames): the manifest's
    parameter, the SEGMENT_FRAMES range and BUILD_SEGMENT.k_max; below K it is refused with
    DPConfig's message."""
    out = tmp_path / "axi.v"
    toml = tmp_path / "p.toml"
    toml.write_text("width = 8\nheight = 6\nmax_segment_frames = 5\n")
    argv = ["-o", out, "--top", "axi", "--config", toml, "--max-segment-frames", 12]
    assert verilog_command.main(parse(argv)) == 0                  # the option wins
    manifest = json.loads((tmp_path / "axi.json").read_text())
    assert manifest["parameters"]["max_segment_frames"] == 12
    assert manifest["registers"]["SEGMENT_FRAMES_SEGMENT_FRAMES_MAX"] == 12
    header = (tmp_path / "dptbd_regs.h").read_text()
    assert "#define DPTBD_AXI__IDENTIFICATION__BUILD_SEGMENT__K_MAX_reset 0xc\n" in header
    with pytest.raises(ConfigError, match=r"^max_segment_frames must be an integer in "
                                          r"\[segment_frames=4, 65535\], got 3$"):
        verilog_command.main(parse(["-o", tmp_path / "b.v", "--max-segment-frames", 3]))
    assert not (tmp_path / "b.v").exists()


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


@pytest.mark.parametrize("family, options, latency", [
    (None, {"line_buffer_style": "bram", "sideband_delay": "registers", "max_tree": "compact",
            "state_store_style": "memory", "histogram_style": "memory"}, 14),
    ("ice40", {"line_buffer_style": "bram", "sideband_delay": "memory", "max_tree": "compact",
               "state_store_style": "memory", "histogram_style": "memory"}, 14),
    ("ecp5", {"line_buffer_style": "lutram", "sideband_delay": "registers", "max_tree": "split",
              "state_store_style": "dp16kd", "histogram_style": "dp16kd"}, 18),
])
def test_verilog_family_builds_the_familys_core_options(tmp_path, capsys, family, options,
                                                         latency):
    out = tmp_path / "dp.v"
    argv = ["-o", out, "--width", 8, "--height", 6, "--fractional-lut", "--external-state-store"]
    assert verilog_command.main(parse(argv + ([] if family is None else ["--family", family]))) == 0
    manifest = json.loads((tmp_path / "dp.json").read_text())
    assert manifest["core_options"] == options and manifest["latency"] == latency
    said = capsys.readouterr().out
    assert ("  core options: " + ", ".join(f"{k}={v}" for k, v in options.items())
            + ("" if family is None else f" (the {family} build)")) in said.splitlines()


def test_verilog_family_ecp5_builds_the_line_buffer_in_dp16kds_at_640_wide(tmp_path, capsys):
    """At 640 wide the ECP5 build has its line buffer and its prefetch FIFO in DP16KDs."""
    out = tmp_path / "dp.v"
    argv = ["-o", out, "--width", 640, "--height", 512, "--state-store", "axi", "--family",
            "ecp5"]
    assert verilog_command.main(parse(argv)) == 0
    options = {"line_buffer_style": "dp16kd", "sideband_delay": "registers",
               "max_tree": "split", "state_store_style": "dp16kd", "histogram_style": "dp16kd"}
    assert json.loads((tmp_path / "dp.json").read_text())["core_options"] == options
    # the line buffer, 640 x 28 bits: two 18 x 1024; the prefetch FIFO, 64 x 64 bits: four
    assert out.read_text().count("DP16KD #(") == 2 + 4
    assert ("  core options: " + ", ".join(f"{k}={v}" for k, v in options.items())
            + " (the ecp5 build)") in capsys.readouterr().out.splitlines()


def test_verilog_family_refuses_a_radius_it_cannot_build(tmp_path):
    out = tmp_path / "dp.v"
    with pytest.raises(ConfigError, match=r"^radius=2 is beyond the ice40 family's resources: "
                                          r"radius must be in \[1, 1\] for ice40 "
                                          r"\(docs/synthesis.md\); build for ecp5$"):
        verilog_command.main(parse(["-o", out, "--radius", 2, "--family", "ice40"]))
    assert not out.exists()
    assert verilog_command.main(parse(["-o", out, "--width", 16, "--height", 8, "--radius", 2,
                                       "--family", "ecp5"])) == 0


def test_verilog_state_store_axi_writes_the_axi4_port_and_its_layout(tmp_path, capsys):
    out = tmp_path / "dp.v"
    args = parse(["-o", out, "--width", 640, "--height", 512, "--state-store", "axi",
                  "--axi-data-bits", 128, "--axi-burst-beats", 8, "--state-base", "0x80000000"])
    assert verilog_command.main(args) == 0
    assert "module dptbd_dp(" in out.read_text()
    manifest = json.loads((tmp_path / "dp.json").read_text())
    assert manifest["top"] == "DPPipelineAxi"
    assert manifest["state_store"] == {
        "kind": "axi4", "prefix": "m_axi_state", "data_bits": 128, "id_bits": 1,
        "burst_beats": 8, "address_bits": 32, "base_address": 0x80000000, "outstanding": 4,
        "slot_bits": 16, "states_per_beat": 8, "beat_bytes": 16, "burst_bytes": 128,
        "frame_bytes": 640 * 512 * 2}
    names = {p["name"]: p["width"] for p in manifest["ports"]}
    assert names["m_axi_state_araddr"] == 32 and names["m_axi_state_wdata"] == 128
    assert names["m_axi_state_wstrb"] == 16 and names["m_axi_state_awlen"] == 8
    assert "state store: AXI4 128-bit, 8 states of 16 bits per beat, bursts of 8 beats, " \
           "655360 bytes per frame from 0x80000000" in capsys.readouterr().out


def test_verilog_top_axi_state_store_axi_writes_the_package_with_the_port(tmp_path, capsys):
    out = tmp_path / "core.v"
    args = parse(["-o", out, "--top", "axi", "--width", 16, "--height", 12, "--state-store",
                  "axi", "--axi-data-bits", 32, "--axi-burst-beats", 4, "--axi-id-bits", 3,
                  "--state-base", "0x1000"])
    assert verilog_command.main(args) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["core.v", "core.json", "dptbd_regs.h", "core.sdc", "core.xdc", "component.xml",
         "core.core", "core_regs.md", "core_regs.xml", "core_regs_html"])
    assert "module dptbd_axi(" in out.read_text()
    manifest = json.loads((tmp_path / "core.json").read_text())
    assert manifest["top"] == "AXITopStore"
    assert manifest["state_store"]["base_address"] == 0x1000
    assert manifest["state_store"]["frame_bytes"] == 16 * 12 * 2
    names = {p["name"]: p["width"] for p in manifest["ports"]}
    assert names["m_axi_state_arid"] == 3 and names["m_axi_state_wdata"] == 32
    assert "state_store_read_addr" not in names
    assert manifest["registers"]["REG_STATE_BASE"] == 0x058
    assert manifest["registers"]["STATE_BASE_RESET"] == 0x1000
    header = (tmp_path / "dptbd_regs.h").read_text()
    for line in ("    uint32_t STATE_BASE;\n",
                 "    uint32_t STATE_READ_ERRORS;\n",
                 "    uint32_t STATE_WRITE_ERRORS;\n",
                 "    uint32_t STATE_BASE_ACTIVE;\n",
                 "#define DPTBD_AXI__CONTROL__STATE_BASE__STATE_BASE_reset 0x1000\n",
                 "#define DPTBD_AXI__STATUS__ERROR__STATE_READ_bm 0x20\n",
                 "#define DPTBD_AXI__STATUS__ERROR__STATE_WRITE_bm 0x40\n",
                 "#define DPTBD_AXI__IDENTIFICATION__BUILD_STATE_BYTES__FRAME_BYTES_reset 0x180\n"):
        assert line in header
    assert "on the AXI4 manager port m_axi_state_* (32-bit data, 32-bit addresses, 384 " \
           "bytes from STATE_BASE) (generated by dptbd verilog --top axi --state-store axi)" \
        in (tmp_path / "core.core").read_text()
    assert "state store: AXI4 32-bit, 2 states of 16 bits per beat, bursts of 4 beats, " \
           "384 bytes per frame from 0x1000" in capsys.readouterr().out


def test_verilog_top_axi_on_chip_has_none_of_it(tmp_path):
    out = tmp_path / "core.v"
    assert verilog_command.main(parse(["-o", out, "--top", "axi", "--width", 16,
                                       "--height", 12])) == 0
    manifest = json.loads((tmp_path / "core.json").read_text())
    assert "state_store" not in manifest and manifest["top"] == "AXITop"
    assert not any("STATE" in name for name in manifest["registers"])
    assert "m_axi_state" not in out.read_text()


def test_verilog_on_chip_build_has_no_state_store_entry(tmp_path):
    out = tmp_path / "dp.v"
    assert verilog_command.main(parse(["-o", out, "--width", 8, "--height", 6])) == 0
    assert "state_store" not in json.loads((tmp_path / "dp.json").read_text())
    assert "m_axi_state" not in out.read_text()


@pytest.mark.parametrize("argv, error, message", [
    (["--axi-data-bits", 32], ValueError, "--axi-data-bits applies to --state-store axi only"),
    (["--axi-id-bits", 2, "--state-base", 0], ValueError,
     "--axi-id-bits, --state-base apply to --state-store axi only"),
    (["--state-store", "axi", "--top", "seg"], ValueError,
     "--state-store axi applies to --top dp and --top axi only; dptbd_seg keeps its state "
     "store on chip"),
    (["--state-store", "axi", "--top", "axi", "--axi-address-bits", 40], ConfigError,
     "address_bits=40: dptbd_axi's STATE_BASE register holds 32 bits; use address_bits <= 32"),
    (["--state-store", "axi", "--top", "axi", "--state-base", "0x40"], ConfigError,
     "base_address=0x40 is not aligned to the burst size of 128 bytes (16 beats of 8)"),
    (["--state-store", "axi", "--top", "axi", "--width", 10, "--height", 3,
      "--axi-data-bits", 128], ConfigError,
     "width*height=30 is not a multiple of the 8 states per 128-bit beat; choose a frame "
     "size or data_bits that divides it"),
    (["--state-store", "axi", "--external-state-store"], ValueError,
     "--state-store axi and --external-state-store exclude each other: the state store is "
     "either behind the AXI4 port or outside the module"),
    (["--state-store", "axi", "--axi-data-bits", 16], ConfigError,
     "data_bits must be one of (32, 64, 128), got 16"),
    (["--state-store", "axi", "--state-base", "0x1010"], ConfigError,
     "base_address=0x1010 is not aligned to the burst size of 128 bytes (16 beats of 8)"),
    (["--state-store", "axi", "--axi-address-bits", 12], ConfigError,   # 128 x 128 x 2 bytes
     "the state of a frame ends at 0x8000 (base_address=0x0 + 32768 bytes), beyond "
     "address_bits=12 (0x1000); use more address bits or a lower base"),
])
def test_verilog_state_store_refusals(tmp_path, argv, error, message):
    with pytest.raises(error, match=whole(message)):
        verilog_command.main(parse(["-o", tmp_path / "dp.v", *argv]))
    assert not (tmp_path / "dp.v").exists()


ECP5_OPTIONS = {"line_buffer_style": "lutram", "sideband_delay": "registers", "max_tree": "split",
                "state_store_style": "dp16kd", "histogram_style": "dp16kd"}
ICE40_OPTIONS = {"line_buffer_style": "bram", "sideband_delay": "memory", "max_tree": "compact",
                 "state_store_style": "memory", "histogram_style": "memory"}
DEFAULT_OPTIONS = {"line_buffer_style": "bram", "sideband_delay": "registers",
                   "max_tree": "compact", "state_store_style": "memory",
                   "histogram_style": "memory"}


@pytest.mark.parametrize("top, module", [("seg", "dptbd_seg"), ("axi", "dptbd_axi")])
@pytest.mark.parametrize("family, options, extra", [
    (None, DEFAULT_OPTIONS, 0), ("ice40", ICE40_OPTIONS, 0), ("ecp5", ECP5_OPTIONS, 4)])
def test_verilog_family_applies_to_every_top(tmp_path, capsys, top, module, family, options,
                                             extra):
    """The DPCore inside dptbd_seg / dptbd_axi gets the family's options (ECP5's split max
    tree: 4 cycles more, in the manifest's latency and dp_latency); without --family,
    DPCore's defaults."""
    out = tmp_path / f"{top}.v"
    toml = tmp_path / "p.toml"
    toml.write_text("width = 8\nheight = 6\ncandidate_count = 2\n")
    argv = ["-o", out, "--top", top, "--config", toml]
    assert verilog_command.main(parse(argv + ([] if family is None
                                              else ["--family", family]))) == 0
    manifest = json.loads((tmp_path / f"{top}.json").read_text())
    assert manifest["module"] == module and manifest["core_options"] == options
    assert (manifest["dp_latency"], manifest["latency"]) == (11 + extra, 14 + extra)
    assert f"module {module}(" in out.read_text()
    said = capsys.readouterr().out
    assert ("  core options: " + ", ".join(f"{k}={v}" for k, v in options.items())
            + ("" if family is None else f" (the {family} build)")) in said.splitlines()


@pytest.mark.parametrize("top", ["dp", "seg", "axi"])
def test_verilog_family_refuses_a_radius_it_cannot_build_for_every_top(tmp_path, top):
    out = tmp_path / "t.v"
    with pytest.raises(ConfigError, match=whole(
            "radius=2 is beyond the ice40 family's resources: radius must be in [1, 1] for "
            "ice40 (docs/synthesis.md); build for ecp5")):
        verilog_command.main(parse(["-o", out, "--top", top, "--width", 16, "--height", 8,
                                    "--radius", 2, "--family", "ice40"]))
    assert list(tmp_path.iterdir()) == []


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


# ---- --pixels-per-clock ------------------------------------------------------------------
@pytest.mark.parametrize("p", [2, 4])
def test_pixels_per_clock_builds_the_beat_pipeline(tmp_path, capsys, p):
    out = tmp_path / "dp.v"
    args = parse(["-o", out, "--width", 12, "--height", 8, "--pixels-per-clock", p])
    assert verilog_command.main(args) == 0
    assert "module dptbd_dp(" in out.read_text()
    manifest = json.loads(out.with_suffix(".json").read_text())
    assert manifest["top"] == "DPPipelineWide" and manifest["parameters"]["pixels_per_clock"] == p
    assert manifest["latency"] == 11                                  # F = 0 (binary LUT)
    names = {port["name"]: port["width"] for port in manifest["ports"]}
    assert names["pixels__payload"] == 8 * p + 1                     # P pixels + first
    assert names["states__payload"] == p * (10 + 4) + 3               # P (E, d) + end flags
    assert manifest["layouts"]["pixel"]["pixel_1"] == {"offset": 8, "width": 8}
    assert manifest["layouts"]["state"]["energy_1"] == {"offset": 14, "width": 10}
    assert "latency 11 cycles" in capsys.readouterr().out


@pytest.mark.parametrize("p", [2, 4])
def test_pixels_per_clock_builds_the_wide_segmenter(tmp_path, capsys, p):
    out = tmp_path / "seg.v"
    toml = tmp_path / "seg.toml"
    toml.write_text("width = 12\nheight = 8\ncandidate_count = 3\n")
    args = parse(["-o", out, "--top", "seg", "--config", toml, "--pixels-per-clock", p])
    assert verilog_command.main(args) == 0
    assert "module dptbd_seg(" in out.read_text()
    manifest = json.loads(out.with_suffix(".json").read_text())
    assert manifest["top"] == "DPSegmenterWide"
    assert manifest["parameters"]["pixels_per_clock"] == p
    assert manifest["latency"] == 11 + 3 and manifest["scan_cycles"] == manifest["derived"][
        "n_bins"] + 4
    names = {port["name"]: port["width"] for port in manifest["ports"]}
    assert names["pixels__payload"] == 8 * p + 1                      # P pixels + first
    assert names["candidates__payload"] == manifest["layouts"]["candidate_width"]
    assert manifest["layouts"]["pixel"]["pixel_1"] == {"offset": 8, "width": 8}
    assert "latency 14 cycles" in capsys.readouterr().out


@pytest.mark.parametrize("p", [2, 4])
def test_pixels_per_clock_builds_the_wide_axi_package(tmp_path, p):
    out = tmp_path / "dptbd_axi.v"
    toml = tmp_path / "axi.toml"
    toml.write_text("width = 12\nheight = 8\ncandidate_count = 3\n")
    assert verilog_command.main(parse(["-o", out, "--top", "axi", "--config", toml,
                                       "--pixels-per-clock", p])) == 0
    manifest = json.loads(out.with_suffix(".json").read_text())
    assert manifest["top"] == "AXITopWide" and manifest["parameters"]["pixels_per_clock"] == p
    names = {port["name"]: port["width"] for port in manifest["ports"]}
    assert names["s_axis_video_tdata"] == 8 * p and "m_axis_state_tdata" not in names
    video = manifest["streams"]["s_axis_video"]
    assert video["pixels_per_beat"] == p
    assert video["layout"]["pixel_1"] == {"offset": 8, "width": 8}
    header = (tmp_path / "dptbd_regs.h").read_text()
    assert f"#define DPTBD_PIXELS_PER_CLOCK {p}u\n" in header
    core = (tmp_path / "dptbd_axi.core").read_text()
    assert f", {p} pixels per clock (generated by dptbd verilog --top axi " \
           f"--pixels-per-clock {p})" in core


def test_pixels_per_clock_with_an_external_store_and_from_toml(tmp_path):
    toml = tmp_path / "p.toml"
    toml.write_text("width = 12\nheight = 8\npixels_per_clock = 4\n")
    out = tmp_path / "dp.v"
    assert verilog_command.main(parse(["-o", out, "--config", toml,
                                       "--external-state-store"])) == 0
    manifest = json.loads(out.with_suffix(".json").read_text())
    assert manifest["top"] == "DPCoreWide"
    names = {port["name"]: port["width"] for port in manifest["ports"]}
    assert names["state_store__read_data"] == 4 * (10 + 4)             # one beat of states
    assert verilog_command.main(parse(["-o", tmp_path / "one.v", "--config", toml,
                                       "--pixels-per-clock", 1, "--width", 12])) == 0
    one = json.loads((tmp_path / "one.json").read_text())
    assert one["top"] == "DPPipeline" and one["parameters"]["pixels_per_clock"] == 1


@pytest.mark.parametrize("p", [2, 4])
def test_pixels_per_clock_with_the_axi_state_store(tmp_path, p):
    out = tmp_path / "dp.v"
    assert verilog_command.main(parse(["-o", out, "--width", 64, "--height", 16,
                                       "--pixels-per-clock", p, "--state-store", "axi"])) == 0
    manifest = json.loads(out.with_suffix(".json").read_text())
    assert manifest["top"] == "DPPipelineAxi" and manifest["parameters"]["pixels_per_clock"] == p
    assert manifest["state_store"]["states_per_beat"] == 4              # 16-bit slots, 64-bit
    names = {port["name"]: port["width"] for port in manifest["ports"]}
    assert names["pixels__payload"] == 8 * p + 1 and names["m_axi_state_wdata"] == 64


@pytest.mark.parametrize("p", [2, 4])
def test_pixels_per_clock_builds_the_axi_package_with_the_axi_state_store(tmp_path, p):
    out = tmp_path / "dptbd_axi.v"
    assert verilog_command.main(parse(["-o", out, "--top", "axi", "--width", 16, "--height",
                                       12, "--pixels-per-clock", p,
                                       "--state-store", "axi", "--axi-data-bits", 128,
                                       "--axi-burst-beats", 4])) == 0
    manifest = json.loads(out.with_suffix(".json").read_text())
    assert manifest["top"] == "AXITopStore" and manifest["parameters"]["pixels_per_clock"] == p
    assert manifest["streams"]["s_axis_video"]["pixels_per_beat"] == p
    assert manifest["state_store"]["data_bits"] == 128
    names = {port["name"]: port["width"] for port in manifest["ports"]}
    assert names["s_axis_video_tdata"] == 8 * p and names["m_axi_state_wdata"] == 128
    header = (tmp_path / "dptbd_regs.h").read_text()
    assert f"#define DPTBD_PIXELS_PER_CLOCK {p}u\n" in header
    assert "#define DPTBD_AXI__CONTROL__STATE_BASE__STATE_BASE_bm 0xffffffff\n" in header
    core = (tmp_path / "dptbd_axi.core").read_text()
    assert f"from STATE_BASE), {p} pixels per clock (generated by dptbd verilog --top axi " \
           f"--state-store axi --pixels-per-clock {p})" in core


@pytest.mark.parametrize("argv, error, message", [
    (["--width", 12, "--pixels-per-clock", 3], ConfigError,
     "pixels_per_clock must be one of (1, 2, 4), got 3"),
    (["--width", 10, "--pixels-per-clock", 4], ConfigError,
     "width=10 is not a multiple of pixels_per_clock=4: a beat of P pixels never straddles "
     "two rows"),
    (["--width", 12, "--pixels-per-clock", 4, "--top", "axi", "--state-output"], ValueError,
     "pixels_per_clock=4 has no m_axis_state; --state-output takes one pixel per clock"),
    (["--width", 16, "--height", 12, "--pixels-per-clock", 4, "--state-store", "axi",
      "--axi-data-bits", 32], ConfigError,
     "data_bits=32 holds 2 16-bit state slot(s) per beat, fewer than the 4 states of a store "
     "word at pixels_per_clock=4 (a word is never split over beats); use data_bits >= 64"),
])
def test_pixels_per_clock_refusals(tmp_path, argv, error, message):
    out = tmp_path / "dp.v"
    with pytest.raises(error, match=whole(message)):
        verilog_command.main(parse(["-o", out, "--height", 8, *argv]))
    assert not out.exists()
