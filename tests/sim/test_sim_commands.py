"""``dptbd verilog`` and ``dptbd sim``: outputs, refusals before any simulation."""

from __future__ import annotations

import argparse
import json
import shutil

import numpy as np
import pytest

from dptbd.commands import sim as sim_command
from dptbd.commands import verilog as verilog_command
from dptbd.config import ConfigError


def parse(module, argv):
    parser = argparse.ArgumentParser()
    module.add_arguments(parser)
    return parser.parse_args([str(a) for a in argv])


def test_verilog_writes_module_and_manifest(tmp_path, capsys):
    out = tmp_path / "rtl" / "dp.v"
    args = parse(verilog_command, ["-o", out, "--width", 13, "--height", 7, "--radius", 2,
                                   "--rounding", "half_up"])
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
    args = parse(verilog_command, ["-o", out, "--width", 8, "--height", 6])
    with pytest.raises(FileExistsError, match="--force"):
        verilog_command.main(args)
    assert out.read_text() == "mine" and not (tmp_path / "dp.json").exists()
    (tmp_path / "other.json").write_text("{}")          # an existing manifest counts too
    with pytest.raises(FileExistsError, match="other.json"):
        verilog_command.main(parse(verilog_command, ["-o", tmp_path / "other.v"]))
    assert verilog_command.main(parse(verilog_command, ["-o", out, "--width", 8, "--height", 6,
                                                        "--force"])) == 0
    assert out.read_text().count("module dptbd_dp(") == 1


def test_verilog_reads_toml_and_options_override_it(tmp_path):
    toml = tmp_path / "p.toml"
    toml.write_text('width = 10\nheight = 8\nsegment_frames = 3\nrounding = "half_up"\n'
                    'weight_frac_bits = 4\n')
    out = tmp_path / "dp.v"
    assert verilog_command.main(parse(verilog_command, ["-o", out, "--config", toml,
                                                        "--height", 9])) == 0
    params = json.loads(out.with_suffix(".json").read_text())["parameters"]
    assert (params["width"], params["height"], params["segment_frames"]) == (10, 9, 3)
    assert (params["rounding"], params["weight_frac_bits"]) == ("half_up", 4)


def test_verilog_refuses_unknown_toml_keys_and_bad_values(tmp_path):
    toml = tmp_path / "p.toml"
    toml.write_text("width = 10\nhieght = 8\n")
    with pytest.raises(ConfigError, match=r"unknown parameter\(s\) \['hieght'\]"):
        verilog_command.main(parse(verilog_command, ["-o", tmp_path / "a.v", "--config", toml]))
    toml.write_text("width = [1, 2\n")
    with pytest.raises(ConfigError, match="not valid TOML"):
        verilog_command.main(parse(verilog_command, ["-o", tmp_path / "a.v", "--config", toml]))
    with pytest.raises(ConfigError, match="radius must be in"):
        verilog_command.main(parse(verilog_command, ["-o", tmp_path / "a.v", "--radius", 3]))
    assert not list(tmp_path.glob("*.v"))


@pytest.mark.parametrize("argv, radius, style", [
    ([], 1, "logic"), (["--lut-style", "auto", "--radius", 2], 2, "bram"),
    (["--lut-style", "bram"], 1, "bram"), (["--lut-style", "logic", "--radius", 2], 2, "logic"),
])
def test_verilog_lut_style(tmp_path, capsys, argv, radius, style):
    """--lut-style: the attribute on the LUT's column memories, the manifest, the summary."""
    out = tmp_path / "dp.v"
    assert verilog_command.main(parse(verilog_command, ["-o", out, "--width", 9,
                                                        "--height", 8, *argv])) == 0
    text = out.read_text()
    moves = (2 * radius + 1) ** 2
    assert text.count('(* ram_style = "logic" *)') == (moves if style == "logic" else 0)
    assert json.loads(out.with_suffix(".json").read_text())["lut_style"] == style
    assert f"weight LUT in {style}" in capsys.readouterr().out


def test_verilog_refuses_an_unknown_lut_style(tmp_path, capsys):
    with pytest.raises(SystemExit):
        parse(verilog_command, ["-o", tmp_path / "a.v", "--lut-style", "registers"])
    assert "invalid choice: 'registers'" in capsys.readouterr().err


def test_narrow_energy_width_warns_but_builds(tmp_path, capsys):
    out = tmp_path / "dp.v"
    args = parse(verilog_command, ["-o", out, "--width", 8, "--height", 6, "--input-bits", 6,
                                   "--energy-bits", 7])
    assert verilog_command.main(args) == 0
    assert "warning: energy_bits=7 saturates" in capsys.readouterr().err


# ---- dptbd sim ------------------------------------------------------------------------

def refused_before_simulation(tmp_path, argv, exception, match):
    args = parse(sim_command, [*argv, "--build-dir", tmp_path / "build"])
    with pytest.raises(exception, match=match):
        sim_command.main(args)
    assert not (tmp_path / "build").exists(), "nothing may be built for refused input"


def test_sim_refuses_a_scene_of_the_wrong_size(tmp_path):
    scene = tmp_path / "s.npy"
    np.save(scene, np.zeros((3, 12, 15), dtype=np.uint16))
    refused_before_simulation(tmp_path, ["--width", 16, "--height", 12, "--scene", scene],
                              ValueError, r"15x12 \(W x H\) but the configuration is width=16")


def test_sim_refuses_pixels_wider_than_input_bits(tmp_path):
    scene = tmp_path / "s.npy"
    frames = np.zeros((3, 12, 16), dtype=np.uint16)
    frames[2, 5, 7] = 64
    np.save(scene, frames)
    refused_before_simulation(tmp_path, ["--width", 16, "--height", 12, "--input-bits", 6,
                                         "--scene", scene],
                              ValueError, r"input_bits=6 \(0 … 63\); found 1 outside")


def test_sim_refuses_a_lut_of_the_wrong_shape(tmp_path):
    lut = tmp_path / "w.npy"
    np.save(lut, np.ones((9, 9)))
    refused_before_simulation(tmp_path, ["--width", 16, "--height", 12, "--weights", lut],
                              ConfigError, r"weights must have shape \(10, 9\)")


@pytest.mark.parametrize("argv, exception, match", [
    (["--segment-stride", 2], ConfigError, "segment_stride=2 is not supported"),
    (["--width", 4, "--height", 4], ConfigError, "too small for the read-ahead"),
    (["--waves", "x.vcd"], ValueError, "FST"),
    (["--valid-pause", 1.0], ValueError, r"--valid-pause must be in \[0, 1\)"),
    (["--frames", 0], ValueError, "--frames must be >= 1"),
    (["--scene", "missing.npy"], FileNotFoundError, "does not exist"),
])
def test_sim_refuses_bad_options(tmp_path, argv, exception, match):
    refused_before_simulation(tmp_path, argv, exception, match)


@pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")
def test_sim_runs_a_scene_and_reports_cycles(tmp_path, capsys):
    waves = tmp_path / "dp.fst"
    args = parse(sim_command, ["--width", 16, "--height", 12, "--segment-frames", 3,
                               "--frames", 4, "--scenario", "edges", "--waves", waves,
                               "--build-dir", tmp_path / "build"])
    assert sim_command.main(args) == 0
    out = capsys.readouterr().out
    assert "simulated cycles        782 first input to last output  (= T*W*H + latency " \
           "= 768 + 14)" in out
    assert "cycles per pixel        1.01823" in out
    assert "verdict                 bit-exact against dptbd.model.fixed" in out
    assert waves.stat().st_size > 0
