"""dptbd.sim.sim_job: settings, configuration and scene checks (whole messages), the
missing-tool sentences of both commands, the printed summary."""

import pathlib
import re
import shutil

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.sim.sim_job import (SimOutcome, SimSettings, sim_config, sim_frames,
                                      simulator_tools_missing, summary_lines)
from helpers.refusals import whole

CFG = DPConfig(width=16, height=12, segment_frames=3)


@pytest.mark.parametrize("settings, message", [
    (SimSettings(valid_pause=1.0), "--valid-pause must be in [0, 1), got 1.0"),
    (SimSettings(ready_pause=-0.1), "--ready-pause must be in [0, 1), got -0.1"),
    (SimSettings(waves=pathlib.Path("x.vcd")),
     "--waves x.vcd: the simulation writes FST; give a path ending in .fst"),
])
def test_settings_refusals(settings, message):
    with pytest.raises(ValueError, match=whole(message)):
        settings.check()


def test_sim_config():
    assert sim_config(CFG, "segmenter", 2).n_candidates == 2
    with pytest.raises(ValueError, match=whole(
            "--candidate-count applies to --design segmenter only")):
        sim_config(CFG, "dp", 2)
    with pytest.raises(ConfigError, match=whole(
            "--design segmenter: n = 0 candidate points per segment (0.2 % of 16x12 = 192 "
            "pixels rounds to 0) gives a segmenter that emits no points; give "
            "--candidate-count 1 … 192")):
        sim_config(CFG, "segmenter")


def test_sim_frames(tmp_path):
    frames, text = sim_frames(CFG, scenario="edges", seed=1)
    assert frames.shape == (6, 12, 16) and text.startswith("scenario edges (seed 1): ")
    scene = tmp_path / "s.npy"
    np.save(scene, np.zeros((5, 12, 16), np.uint16))
    frames, text = sim_frames(CFG, scene=scene, frames=2)
    assert frames.shape == (2, 12, 16) and text.startswith(f"{scene}: ")
    with pytest.raises(ValueError, match=whole(f"--frames 9 but {scene} holds 5 frames")):
        sim_frames(CFG, scene=scene, frames=9)
    (tmp_path / "t.npy").write_text("text")
    with pytest.raises(ValueError, match=f"^{re.escape(str(tmp_path / 't.npy'))} is not a .npy "
                                         f"array: "):
        sim_frames(CFG, scene=tmp_path / "t.npy")


def test_missing_icarus_is_named_with_the_option_of_each_command(monkeypatch):
    real = shutil.which
    monkeypatch.setattr(shutil, "which",
                        lambda name, *a, **k: None if name == "iverilog" else real(name, *a, **k))
    assert simulator_tools_missing("icarus") == (
        "--simulator icarus needs Icarus Verilog (iverilog not on the PATH); install it (bash "
        "scripts/setup.sh setup) or use --simulator verilator")
    assert simulator_tools_missing("icarus", "--rtl-simulator") == (
        "--rtl-simulator icarus needs Icarus Verilog (iverilog not on the PATH); install it "
        "(bash scripts/setup.sh setup) or use --rtl-simulator verilator")


def test_missing_verilator_names_the_icarus_fallback_of_each_command(no_verilator):
    assert simulator_tools_missing("verilator").endswith(
        "or use the Icarus simulator instead (dptbd sim --simulator icarus)")
    assert simulator_tools_missing("verilator", "--rtl-simulator").startswith(
        "--rtl: compiled RTL simulation needs verilator")
    assert simulator_tools_missing("verilator", "--rtl-simulator").endswith(
        "(--rtl-simulator icarus)")


def test_summary_lines_say_whether_the_count_is_exact():
    frames = np.zeros((4, 12, 16), np.uint8)
    outcome = SimOutcome(finished=True, passed=True, report="bit-exact: 768 words", outputs=768,
                         cycles=782, latency=14, speed="fast", build="cached")
    lines = summary_lines(CFG, frames, SimSettings(), outcome)
    assert lines == [
        "", "frames simulated        4 (768 pixels, 768 states out)",
        "simulated cycles        782 first input to last output  (= T*W*H + latency = 768 + 14)",
        "cycles per pixel        1.01823", "simulator speed         fast",
        "build                   cached",
        "verdict                 bit-exact against dptbd.model.fixed: bit-exact: 768 words"]
    paused = summary_lines(CFG, frames, SimSettings(valid_pause=0.5), outcome)
    assert paused[2] == "simulated cycles        782 first input to last output"
    outcome.passed, outcome.cycles = False, 790
    lines = summary_lines(CFG, frames, SimSettings(), outcome)
    assert lines[2].endswith("  (!= T*W*H + latency = 782)")
    assert lines[-1] == "verdict                 NOT bit-exact: bit-exact: 768 words"
