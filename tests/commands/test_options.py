"""dptbd.commands.options: the DPConfig options and the simulator options shared by commands."""

import argparse
import json
import re
import pathlib

import numpy as np
import pytest

from dptbd.commands.options import (add_config_arguments, add_simulator_arguments,
                                    config_from_args, load_weights)
from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from helpers.refusals import whole


def parse(argv):
    parser = argparse.ArgumentParser()
    add_config_arguments(parser)
    return parser.parse_args([str(a) for a in argv])


def test_defaults_then_toml_then_options(tmp_path):
    assert config_from_args(parse([])) == DPConfig()
    toml = tmp_path / "p.toml"
    toml.write_text("width = 10\nheight = 8\n")
    cfg = config_from_args(parse(["--config", toml, "--height", 9]))
    assert (cfg.width, cfg.height) == (10, 9)


def test_max_segment_frames_option(tmp_path):
    """K_max has an option named after its DPConfig field; it overrides the TOML's."""
    assert parse([]).max_segment_frames is None
    assert config_from_args(parse(["--max-segment-frames", 9])).k_max == 9
    toml = tmp_path / "p.toml"
    toml.write_text("segment_frames = 3\nmax_segment_frames = 5\n")
    assert config_from_args(parse(["--config", toml])).max_segment_frames == 5
    assert config_from_args(parse(["--config", toml, "--max-segment-frames", 7])) == \
        DPConfig(segment_frames=3, max_segment_frames=7)
    with pytest.raises(ConfigError, match=rf"^max_segment_frames must be an integer in "
                                          rf"\[segment_frames=3, 65535\], got 2 "
                                          rf"\(from {re.escape(str(toml))}\)$"):
        config_from_args(parse(["--config", toml, "--max-segment-frames", 2]))


def test_config_refusals(tmp_path):
    with pytest.raises(FileNotFoundError, match=r"^config file missing.toml does not exist$"):
        config_from_args(parse(["--config", "missing.toml"]))
    toml = tmp_path / "p.toml"
    toml.write_text("radius = 3\n")
    with pytest.raises(ConfigError, match=whole(f"radius must be an integer in [1, 2], got 3 "
                                                f"(from {toml})")):
        config_from_args(parse(["--config", toml]))


def test_load_weights(tmp_path):
    w = np.full((10, 9), 0.5)
    np.save(tmp_path / "w.npy", w)
    (tmp_path / "w.json").write_text(json.dumps(w.tolist()))
    assert load_weights(tmp_path / "w.npy") == load_weights(tmp_path / "w.json") == w.tolist()
    with pytest.raises(FileNotFoundError, match=r"^weights file nope.npy does not exist$"):
        load_weights(pathlib.Path("nope.npy"))
    (tmp_path / "w.txt").write_text("1")
    with pytest.raises(ValueError, match=r"^weights file must be .npy or .json, got w.txt$"):
        load_weights(tmp_path / "w.txt")


def test_simulator_arguments_with_and_without_a_prefix():
    parser = argparse.ArgumentParser()
    add_simulator_arguments(parser)
    add_simulator_arguments(parser, prefix="rtl-", of=" of --rtl")
    args = parser.parse_args(["--rtl-simulator", "icarus", "--build-dir", "b"])
    assert (args.simulator, args.build_dir) == ("verilator", pathlib.Path("b"))
    assert (args.rtl_simulator, args.rtl_build_dir) == ("icarus", None)
    assert "simulator of --rtl: verilator" in parser.format_help()
