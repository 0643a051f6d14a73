"""``dptbd verilog``: the module and its manifest, overwriting, TOML parameters, LUT style,
the energy width and the segment length."""

from __future__ import annotations

import json
import tomllib
import warnings

import pytest

from dptbd.commands import verilog as verilog_command
from dptbd.config import EnergyWidthWarning
from dptbd.errors import ConfigError
from helpers.command_args import parser_of
from helpers.refusals import whole

parse = parser_of(verilog_command)


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
