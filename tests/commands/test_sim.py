"""``dptbd sim``: refusals before any simulation (both simulators), missing tools, the
summary on both simulators, Verilator's build cache."""

from __future__ import annotations

import argparse
import re
import shutil

import numpy as np
import pytest

from dptbd import cli
from dptbd.commands import sim as sim_command
from dptbd.errors import ConfigError
from dptbd.sim import verilator
from helpers.refusals import whole


def parse(module, argv):
    parser = argparse.ArgumentParser()
    module.add_arguments(parser)
    return parser.parse_args([str(a) for a in argv])


def refused_before_simulation(tmp_path, argv, exception, message, simulator="verilator"):
    args = parse(sim_command, [*argv, "--simulator", simulator, "--build-dir",
                               tmp_path / "build"])
    with pytest.raises(exception, match=whole(message)):
        sim_command.main(args)
    assert not (tmp_path / "build").exists(), "nothing may be built for refused input"


SIMULATORS = pytest.mark.parametrize("simulator", ["verilator", "icarus"])


@SIMULATORS
def test_sim_refuses_a_scene_of_the_wrong_size(tmp_path, simulator):
    scene = tmp_path / "s.npy"
    np.save(scene, np.zeros((3, 12, 15), dtype=np.uint16))
    refused_before_simulation(tmp_path, ["--width", 16, "--height", 12, "--scene", scene],
                              ValueError, "scene frames are 15x12 (W x H) but the "
                              "configuration is width=16 x height=12", simulator)


@SIMULATORS
def test_sim_refuses_pixels_wider_than_input_bits(tmp_path, simulator):
    scene = tmp_path / "s.npy"
    frames = np.zeros((3, 12, 16), dtype=np.uint16)
    frames[2, 5, 7] = 64
    np.save(scene, frames)
    refused_before_simulation(tmp_path, ["--width", 16, "--height", 12, "--input-bits", 6,
                                         "--scene", scene],
                              ValueError, "scene pixels must fit input_bits=6 (0 … 63); "
                              "found 1 outside, e.g. [64]", simulator)


@SIMULATORS
def test_sim_refuses_a_lut_of_the_wrong_shape(tmp_path, simulator):
    lut = tmp_path / "w.npy"
    np.save(lut, np.ones((9, 9)))
    refused_before_simulation(tmp_path, ["--width", 16, "--height", 12, "--weights", lut],
                              ConfigError, "weights must have shape (10, 9) for radius=1 "
                              "([predecessor direction 0..9, move 0..8]), got (9, 9)",
                              simulator)


@SIMULATORS
@pytest.mark.parametrize("argv, exception, message", [
    (["--segment-stride", 2], ConfigError,
     "segment_stride=2 is not supported by the gateware: only non-overlapping segments "
     "(segment_stride == segment_frames == 4) are implemented, with a single state store"),
    (["--width", 4, "--height", 4], ConfigError,
     "width=4 x height=4 is too small for the read-ahead of radius=1: the gateware needs "
     "width*height - radius*(width+1) > write latency 12 cycles, but it is 11; each state "
     "must be written before the next frame reads it; use a larger frame"),
    (["--waves", "x.vcd"], ValueError,
     "--waves x.vcd: the simulation writes FST; give a path ending in .fst"),
    (["--valid-pause", 1.0], ValueError, "--valid-pause must be in [0, 1), got 1.0"),
    (["--ready-pause", -0.1], ValueError, "--ready-pause must be in [0, 1), got -0.1"),
    (["--frames", 0], ValueError, "--frames must be an integer in [1, inf), got 0"),
    (["--scene", "missing.npy"], FileNotFoundError, "scene file missing.npy does not exist"),
    (["--candidate-count", 3], ValueError,
     "--candidate-count applies to --design segmenter only"),
    (["--design", "segmenter", "--width", 16, "--height", 12], ConfigError,
     "--design segmenter: n = 0 candidate points per segment (0.2 % of 16x12 = 192 pixels "
     "rounds to 0) gives a segmenter that emits no points; give --candidate-count 1 … 192"),
    (["--design", "segmenter", "--width", 16, "--height", 12, "--candidate-count", 0],
     ConfigError, "--design segmenter: n = 0 candidate points per segment gives a segmenter "
     "that emits no points; give --candidate-count 1 … 192"),
])
def test_sim_refuses_bad_options(tmp_path, argv, exception, message, simulator):
    refused_before_simulation(tmp_path, argv, exception, message, simulator)


def test_sim_refuses_an_unknown_simulator_or_design(capsys):
    for argv, err in ((["--simulator", "xsim"], "argument --simulator: invalid choice: 'xsim' "
                                               "(choose from 'verilator', 'icarus')"),
                      (["--design", "core"], "argument --design: invalid choice: 'core' "
                                            "(choose from 'dp', 'segmenter')")):
        with pytest.raises(SystemExit):
            parse(sim_command, argv)
        assert capsys.readouterr().err.splitlines()[-1].endswith(err)


NO_VERILATOR = ("compiled RTL simulation needs verilator (Debian package 'verilator'); install "
                "it (bash scripts/setup.sh setup) or use the Icarus simulator instead (dptbd sim "
                "--simulator icarus)")


def test_sim_without_verilator_names_it_and_the_icarus_fallback(tmp_path, capsys, no_verilator):
    build = tmp_path / "build"
    argv = ["sim", "--width", "16", "--height", "12", "--frames", "2", "--build-dir", str(build)]
    assert cli.main(argv) == 2
    captured = capsys.readouterr()
    assert captured.err == f"dptbd sim: error: {NO_VERILATOR}\n"
    assert captured.out == "" and not build.exists()


def test_sim_without_a_compiler_names_every_missing_tool(tmp_path, capsys, monkeypatch):
    def raises():
        raise verilator.ToolMissingError("compiled RTL simulation needs a C++ compiler (Debian "
                                         "package 'g++') and make (Debian package 'make'); …")

    monkeypatch.setattr(verilator, "check_tools", raises)
    build = tmp_path / "build"
    assert cli.main(["sim", "--width", "16", "--height", "12", "--build-dir", str(build)]) == 2
    assert capsys.readouterr().err == (
        "dptbd sim: error: compiled RTL simulation needs a C++ compiler (Debian package 'g++') "
        "and make (Debian package 'make'); …\n")
    assert not build.exists()


def test_sim_without_icarus_names_it_and_the_verilator_fallback(tmp_path, capsys, monkeypatch):
    real = shutil.which
    monkeypatch.setattr(shutil, "which",
                        lambda name, *a, **k: None if name == "vvp" else real(name, *a, **k))
    build = tmp_path / "build"
    assert cli.main(["sim", "--simulator", "icarus", "--width", "16", "--height", "12",
                     "--build-dir", str(build)]) == 2
    assert capsys.readouterr().err == (
        "dptbd sim: error: --simulator icarus needs Icarus Verilog (vvp not on the PATH); "
        "install it (bash scripts/setup.sh setup) or use --simulator verilator\n")
    assert not build.exists()


VERILATOR = pytest.mark.skipif(
    any(shutil.which(t) is None for t in ("verilator", "g++", "make")),
    reason="needs Verilator, g++ and make")


@pytest.fixture(scope="module")
def verilator_root(tmp_path_factory):
    """A build root of its own for the cache test (nothing else builds there); the other
    runs here build in the default root, sharing its builds and runtime libraries with
    the rest of the suite (the waves build: sim/verilator/test_init.py's trace test)."""
    return tmp_path_factory.mktemp("verilator")


SMALL = ["--width", 16, "--height", 12, "--segment-frames", 3, "--frames", 4,
         "--scenario", "edges"]


@VERILATOR
def test_sim_on_verilator_caches_its_build(capsys, verilator_root):
    root = verilator_root                   # nothing else here builds this key (no waves)
    assert sim_command.main(parse(sim_command, [*SMALL, "--build-dir", root])) == 0
    assert re.search(r"^build                   compiled in [0-9.]+ s \(", capsys.readouterr().out,
                     re.M)
    assert sim_command.main(parse(sim_command, [*SMALL, "--build-dir", root])) == 0
    second = capsys.readouterr().out
    assert re.search(r"^build                   from the cache in [0-9.]+ s \(", second, re.M)
    assert "782 first input to last output" in second
    built = [p.name for p in root.iterdir() if p.name.startswith("16x12")
             and "-dp-" in p.name and "waves" not in p.name]
    assert len(built) == 1, built


ICARUS = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")


@pytest.mark.parametrize("simulator, speed", [
    pytest.param("verilator", r"[0-9.]+ M cycles/s \(Verilator: \d+ cycles, drain included, in ",
                 marks=VERILATOR),
    pytest.param("icarus", r"\d+ cycles/s while streaming \(Icarus: ", marks=ICARUS)])
def test_sim_reports_the_exact_cycle_count_and_the_verdict(tmp_path, capsys, simulator, speed):
    waves = tmp_path / "dp.fst"
    root = [] if simulator == "verilator" else ["--build-dir", tmp_path / "build"]
    args = parse(sim_command, [*SMALL, "--simulator", simulator, "--waves", waves, *root])
    assert sim_command.main(args) == 0
    out = capsys.readouterr().out
    assert f"  dptbd_dp on {simulator.capitalize()}\n" in out
    assert "simulated cycles        782 first input to last output  (= T*W*H + latency " \
           "= 768 + 14)\n" in out
    assert "frames simulated        4 (768 pixels, 768 states out)\n" in out
    assert "cycles per pixel        1.01823\n" in out
    assert re.search(f"^simulator speed         {speed}", out, re.M)
    assert f"waveform                {waves.resolve()}\n" in out
    assert "verdict                 bit-exact against dptbd.model.fixed: bit-exact: 768 words " \
           "(4 frames)\n" in out
    assert waves.stat().st_size > 0


@VERILATOR
def test_sim_on_verilator_with_pauses_and_waves(tmp_path, capsys):
    waves = tmp_path / "dp.fst"
    args = parse(sim_command, [*SMALL, "--valid-pause", 0.3, "--ready-pause", 0.4,
                               "--waves", waves])
    assert sim_command.main(args) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.startswith("simulated cycles"))
    assert "T*W*H" not in line and int(line.split()[2]) > 782      # pauses: no exact count
    assert f"waveform                {waves.resolve()}\n" in out
    assert "verdict                 bit-exact against dptbd.model.fixed" in out
    assert waves.stat().st_size > 0


@VERILATOR
def test_sim_on_verilator_runs_the_segmenter(capsys):
    args = parse(sim_command, ["--width", 16, "--height", 12, "--segment-frames", 3,
                               "--frames", 7, "--design", "segmenter", "--candidate-count", 2])
    assert sim_command.main(args) == 0
    out = capsys.readouterr().out
    assert "dptbd sim: 16x12, K=3, B_in=8, B_E=16, F=8, r=1, truncate, n=2, C=4\n" in out
    assert "  dptbd_seg on Verilator\n" in out
    assert "frames simulated        7 (1344 pixels, 6 candidate-list words out)\n" in out
    # the histogram scan (1028 cycles) is longer than a 16 x 12 frame: stalls (2443: the
    # DP's input credit, decided a cycle early, holds the
    # input one cycle sooner under back-pressure than an exact credit would: 2441)
    assert "simulated cycles        2443 first input to last output  " \
           "(!= S*K*W*H + latency + 1 = 1170)\n" in out
    assert "verdict                 bit-exact against dptbd.model.fixed and " \
           "dptbd.model.segmentation: bit-exact: 2 lists, 4 records, 6 words\n" in out
