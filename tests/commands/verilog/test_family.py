"""``dptbd verilog --family``: the family's core options in every top, recorded in the manifest,
and a radius the family cannot build refused."""

from __future__ import annotations

import json

import pytest

from dptbd.commands import verilog as verilog_command
from dptbd.errors import ConfigError
from helpers.command_args import parser_of
from helpers.refusals import whole

parse = parser_of(verilog_command)


@pytest.mark.parametrize("family, options, latency", [
    (None, {"line_buffer_style": "bram", "sideband_delay": "registers", "max_tree": "compact",
            "state_store_style": "memory", "histogram_style": "memory",
            "control_style": "generic", "output_queue_style": "binary",
            "register_read": "one_level", "credit_ready": "one", "lut_write": "case"}, 14),
    ("ice40", {"line_buffer_style": "bram", "sideband_delay": "memory", "max_tree": "compact",
               "state_store_style": "memory", "histogram_style": "memory",
               "control_style": "generic", "output_queue_style": "binary",
               "register_read": "one_level", "credit_ready": "one", "lut_write": "case"}, 14),
    ("ecp5", {"line_buffer_style": "lutram", "sideband_delay": "registers", "max_tree": "split",
              "state_store_style": "dp16kd", "histogram_style": "dp16kd",
              "control_style": "registered", "output_queue_style": "one_hot",
              "register_read": "two_level", "credit_ready": "per_load",
              "lut_write": "predecoded"}, 18),
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
               "max_tree": "split", "state_store_style": "dp16kd", "histogram_style": "dp16kd",
               "control_style": "registered", "output_queue_style": "one_hot",
               "register_read": "two_level", "credit_ready": "per_load",
               "lut_write": "predecoded"}
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


ECP5_OPTIONS = {"line_buffer_style": "lutram", "sideband_delay": "registers", "max_tree": "split",
                "state_store_style": "dp16kd", "histogram_style": "dp16kd",
                "control_style": "registered", "output_queue_style": "one_hot",
                "register_read": "two_level", "credit_ready": "per_load",
                "lut_write": "predecoded"}


ICE40_OPTIONS = {"line_buffer_style": "bram", "sideband_delay": "memory", "max_tree": "compact",
                 "state_store_style": "memory", "histogram_style": "memory",
                 "control_style": "generic", "output_queue_style": "binary",
                 "register_read": "one_level", "credit_ready": "one", "lut_write": "case"}


DEFAULT_OPTIONS = {"line_buffer_style": "bram", "sideband_delay": "registers",
                   "max_tree": "compact", "state_store_style": "memory",
                   "histogram_style": "memory", "control_style": "generic",
                   "output_queue_style": "binary",
                   "register_read": "one_level", "credit_ready": "one", "lut_write": "case"}


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
