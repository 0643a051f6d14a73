"""``dptbd run --rtl``: the FPGA stage's generated Verilog checked against the golden model on
Verilator or Icarus (``--rtl-frames``, ``--rtl-state-store``), the summary's line, and the
refusals before any work."""

import json
import re
import shutil

import numpy as np
import pytest

from dptbd.cli import main
from helpers.run_command import leftovers


VERILATOR = pytest.mark.skipif(
    any(shutil.which(t) is None for t in ("verilator", "g++", "make")),
    reason="needs Verilator, g++ and make")


@VERILATOR
def test_rtl_checks_every_frame_on_verilator_by_default(tmp_path, small, capsys):
    out = tmp_path / "r"
    build = tmp_path / "build"
    args = ["run", "--no-progress", "--scenario", str(small), "--rtl", "--rtl-build-dir",
            str(build), "--out", str(out)]
    assert main(args) == 0
    text = capsys.readouterr().out
    # 4 segments of 6 frames of 32 x 32: 4 * 6 * 1024 + latency 17 + 1 cycles
    line = ("RTL (dptbd_seg on Verilator) checked frames 0-23 of 24: bit-exact, 50 "
            "candidate-list words compared, 24594 cycles")
    assert f"\n{line}\n" in text and line in (out / "table.md").read_text()
    assert re.search(r"^  RTL: bit-exact: 4 lists, 46 records, 50 words — the generated Verilog "
                     r"\(dptbd_seg on Verilator\) matches the golden model on all 24 frames: 50 "
                     r"candidate-list words compared, 24594 cycles, ([0-9.]+ M|\d+) cycles/s "
                     r"\([0-9.]+ s in all\)$", text, re.M), text
    assert "  RTL: build compiled in " in text
    rtl = json.loads((out / "summary.json").read_text())["rtl"]
    assert rtl["passed"] and rtl["checked"] and rtl["summary"] == line
    assert (rtl["frames"], rtl["of_frames"], rtl["checked_frames"]) == (24, 24, [0, 23])
    assert (rtl["simulator"], rtl["design"], rtl["module"]) == ("verilator", "segmenter",
                                                                "dptbd_seg")
    assert (rtl["words_in"], rtl["words_compared"], rtl["cycles"]) == (24 * 1024, 50, 24594)
    assert rtl["cycles_per_second"] > 0 and rtl["build_cached"] is False
    # a second run reuses the build
    assert main(args + ["--force", "--rtl-frames", "12"]) == 0
    text = capsys.readouterr().out
    assert "  RTL: build from the cache in " in text
    line = ("RTL (dptbd_seg on Verilator) checked frames 0-11 of 24: bit-exact, 21 "
            "candidate-list words compared, 12306 cycles; frames 12-23 come from the golden "
            "model only (--rtl-frames 0 checks all)")
    assert f"\n{line}\n" in text
    assert json.loads((out / "summary.json").read_text())["rtl"]["build_cached"] is True


def _axi_store_args(tmp_path, small):
    return ["run", "--no-progress", "--scenario", str(small), "--rtl", "--rtl-build-dir",
            str(tmp_path / "build"), "--rtl-state-store", "axi", "--out", str(tmp_path / "r")]


@VERILATOR
def test_rtl_with_the_axi_state_store(tmp_path, small, capsys):
    """``--rtl-state-store axi`` with ideal lists: dptbd_dp with its state in the harness's
    AXI4 memory gives every (E, d) word of the golden model (dptbd_axi's build: the test
    below, ``-m slow``)."""
    out = tmp_path / "r"
    args = _axi_store_args(tmp_path, small)
    # ideal lists: dptbd_dp, every (E, d) word; the cycles simulated (64 of drain included;
    # the store's first pixel enters in cycle 5, docs/gateware.md)
    assert main(args + ["--lists", "ideal", "--rtl-frames", "12"]) == 0
    text = capsys.readouterr().out
    line = ("RTL (dptbd_dp --state-store axi on Verilator) checked frames 0-11 of 24: "
            "bit-exact, 12288 (E, d) words compared, 12373 cycles; frames 12-23 come from the "
            "golden model only (--rtl-frames 0 checks all)")
    assert f"\n{line}\n" in text
    rtl = json.loads((out / "summary.json").read_text())["rtl"]
    assert (rtl["design"], rtl["module"], rtl["state_store"], rtl["cycles_per_pixel"]) == (
        "dp", "dptbd_dp", "axi", 1.0)


@VERILATOR
@pytest.mark.slow
def test_rtl_with_the_axi_state_store_on_dptbd_axi(tmp_path, small, capsys):
    """``--rtl-state-store axi``: dptbd_axi with its state in the harness's AXI4 memory gives
    the lists, words and cycles dptbd_seg gives."""
    out = tmp_path / "r"
    args = _axi_store_args(tmp_path, small)
    assert main(args) == 0
    text = capsys.readouterr().out
    line = ("RTL (dptbd_axi --state-store axi on Verilator) checked frames 0-23 of 24: "
            "bit-exact, 50 candidate-list words compared, 24594 cycles")
    assert f"\n{line}\n" in text and line in (out / "table.md").read_text()
    assert re.search(r"^  RTL: bit-exact: 4 lists, 46 records, 50 words — the generated Verilog "
                     r"\(dptbd_axi --state-store axi on Verilator\) matches the golden model on "
                     r"all 24 frames: 50 candidate-list words compared, 24594 cycles, "
                     r"([0-9.]+ M|\d+) cycles/s \([0-9.]+ s in all\); 1.000 cycles per pixel "
                     r"with the AXI4 store at latency 0$", text, re.M), text
    rtl = json.loads((out / "summary.json").read_text())["rtl"]
    assert (rtl["simulator"], rtl["design"], rtl["module"], rtl["state_store"]) == (
        "verilator", "axi", "dptbd_axi", "axi")
    assert (rtl["words_in"], rtl["words_compared"], rtl["cycles"]) == (24 * 1024, 50, 24594)
    assert (rtl["data_bits"], rtl["burst_beats"], rtl["outstanding"]) == (64, 16, 4)
    assert (rtl["memory_latency"], rtl["cycles_per_pixel"]) == (0, 1.0)


def test_rtl_axi_store_on_icarus_is_refused(tmp_path, small, capsys, monkeypatch):
    from dptbd.sim import sim_job

    monkeypatch.setattr(sim_job, "simulator_tools_missing", lambda sim, option: None)
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(small), "--rtl", "--rtl-simulator",
                 "icarus", "--rtl-state-store", "axi", "--out", str(out)]) == 2
    assert capsys.readouterr().err == (
        "dptbd run: error: --rtl-state-store axi: only the Verilator harness models the AXI4 "
        "memory; use --rtl-simulator verilator\n")
    assert leftovers(tmp_path) == []
    with pytest.raises(SystemExit):
        main(["run", "--rtl", "--rtl-state-store", "dram"])
    assert capsys.readouterr().err.splitlines()[-1] == (
        "dptbd run: error: argument --rtl-state-store: invalid choice: 'dram' (choose from "
        "'auto', 'chip', 'axi')")


SENSOR = """\
name = "sensor-640x512"
[scene]
size = [512, 640]
frames = 12
snr = 3.0
seed = 1
[[scene.targets]]
start = [100.0, 200.0]
velocity = [0.8, 0.6]
[[scene.targets]]
start = [400.0, 500.0]
velocity = [-0.5, 0.7]
[segmentation]
false_alarm_rate = 0.0002
"""


def run_rtl_scenario(tmp_path, capsys, scenario_text):
    """``dptbd run --rtl`` on ``scenario_text`` (written beside its data in ``tmp_path``):
    what it printed and its summary's ``rtl`` section."""
    scenario = tmp_path / "scenario.toml"
    scenario.write_text(scenario_text)
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(scenario), "--rtl",
                 "--rtl-build-dir", str(tmp_path / "build"), "--out", str(out)]) == 0
    return capsys.readouterr().out, json.loads((out / "summary.json").read_text())["rtl"]


@pytest.mark.slow
@VERILATOR
def test_rtl_at_640x512_takes_the_axi_state_store(tmp_path, capsys):
    """A 640 x 512 scenario (12 frames: two segments of K = 6): its 6.5 Mbit of state
    exceed the largest device's block RAM, so --rtl runs dptbd_axi --state-store axi (about
    3 minutes on a loaded 2-core machine, the build included)."""
    text, rtl = run_rtl_scenario(tmp_path, capsys, SENSOR)
    # 12 frames of 327 680 pixels at one per clock, + latency 17 + 1
    line = ("RTL (dptbd_axi --state-store axi on Verilator) checked frames 0-11 of 12: "
            "bit-exact, 130 candidate-list words compared, 3932178 cycles")
    assert f"\n{line}\n" in text
    assert (rtl["state_store"], rtl["cycles_per_pixel"], rtl["words_in"]) == (
        "axi", 1.0, 12 * 640 * 512)


RANGE_DOPPLER = """\
[input]
path = "rd4096x256.npy"
[segmentation]
false_alarm_rate = 0.00005
"""


@pytest.mark.slow
@VERILATOR
def test_rtl_at_4096x256_range_doppler_takes_the_axi_state_store(tmp_path, capsys):
    """A 4096 x 256 range-Doppler map as recorded data (12 frames, 8-bit: K = 6, B_E = 16;
    21 Mbit of state): --rtl runs dptbd_axi --state-store axi (about 4 minutes on a loaded
    2-core machine, the build included)."""
    from dptbd.scenes.adc import quantise
    from dptbd.scenes.range_doppler import rd_scene, straight_track

    # benchmarks/bench_axi_store.py's range-Doppler scene: a Swerling 1 target at 10 dB
    rd = rd_scene((4096, 256), 12, straight_track((4096 / 3, 128.0), (2.0, 0.5), 12),
                  snr_db=10.0, seed=1)
    frames = quantise(np.swapaxes(rd.frames, 1, 2), 8, gain=16.0)
    np.save(tmp_path / "rd4096x256.npy", frames.astype(np.uint8))
    text, rtl = run_rtl_scenario(tmp_path, capsys, RANGE_DOPPLER)
    # 12 frames of 1 048 576 pixels at one per clock, + latency 17 + 1
    line = ("RTL (dptbd_axi --state-store axi on Verilator) checked frames 0-11 of 12: "
            "bit-exact, 95 candidate-list words compared, 12582930 cycles")
    assert f"\n{line}\n" in text
    assert (rtl["state_store"], rtl["cycles_per_pixel"], rtl["words_in"]) == (
        "axi", 1.0, 12 * 4096 * 256)


@pytest.mark.skipif(shutil.which("iverilog") is None, reason="Icarus Verilog not installed")
def test_rtl_on_icarus_checks_the_generated_verilog_against_the_model(tmp_path, small, capsys):
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(small), "--rtl",
                 "--rtl-simulator", "icarus", "--rtl-frames", "12",
                 "--rtl-build-dir", str(tmp_path / "build"), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "with cocotb + Icarus" in text
    assert re.search(r"^  RTL: bit-exact: 2 lists, 19 records, 21 words — the generated Verilog "
                     r"\(dptbd_seg on Icarus\) matches the golden model on the first 12 of 24 "
                     r"frames: 21 candidate-list words compared, 12306 cycles, \d+ cycles/s "
                     r"\([0-9.]+ s in all\); the model's output is used for the rest$", text, re.M)
    line = ("RTL (dptbd_seg on Icarus) checked frames 0-11 of 24: bit-exact, 21 candidate-list "
            "words compared, 12306 cycles; frames 12-23 come from the golden model only "
            "(--rtl-frames 0 checks all)")
    assert line in text and line in (out / "table.md").read_text()
    rtl = json.loads((out / "summary.json").read_text())["rtl"]
    assert rtl["passed"] and rtl["frames"] == 12 and rtl["summary"] == line
    assert rtl["checked"] and rtl["checked_frames"] == [0, 11]
    assert (rtl["simulator"], rtl["design"], rtl["module"]) == ("icarus", "segmenter",
                                                                "dptbd_seg")
    assert rtl["cycles_per_second"] > 0


def test_rtl_without_verilator_is_refused_before_any_work(tmp_path, small, capsys, no_verilator):
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(small), "--rtl",
                 "--rtl-build-dir", str(tmp_path / "build"), "--out", str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.err == (
        "dptbd run: error: --rtl: compiled RTL simulation needs verilator (Debian package "
        "'verilator'); install it (bash scripts/setup.sh setup) or use the Icarus simulator "
        "instead (--rtl-simulator icarus)\n")
    assert captured.out == "" and leftovers(tmp_path) == []


def test_rtl_without_icarus_is_refused_before_any_work(tmp_path, small, capsys, monkeypatch):
    real = shutil.which
    monkeypatch.setattr(shutil, "which",
                        lambda name, *a, **k: None if name == "iverilog" else real(name, *a, **k))
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(small), "--rtl", "--rtl-simulator",
                 "icarus", "--out", str(out)]) == 2
    assert capsys.readouterr().err == (
        "dptbd run: error: --rtl-simulator icarus needs Icarus Verilog (iverilog not on the "
        "PATH); install it (bash scripts/setup.sh setup) or use --rtl-simulator verilator\n")
    assert leftovers(tmp_path) == []


def test_rtl_options_are_refused_by_name(tmp_path, small, capsys):
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(small), "--rtl", "--rtl-frames", "-1",
                 "--out", str(out)]) == 2
    assert capsys.readouterr().err == "dptbd run: error: --rtl-frames must be an integer in [0, inf), got -1\n"
    with pytest.raises(SystemExit):
        main(["run", "--rtl", "--rtl-simulator", "xsim"])
    assert capsys.readouterr().err.splitlines()[-1] == (
        "dptbd run: error: argument --rtl-simulator: invalid choice: 'xsim' (choose from "
        "'verilator', 'icarus')")
    assert leftovers(tmp_path) == []


def test_rtl_summary_says_which_frames_were_checked(tmp_path, small, capsys, monkeypatch):
    """A stand-in for the simulation: the options reach run_rtl, the summary names the
    simulator, the frames checked, the words compared and the cycles."""
    from dptbd.evaluation.run import rtl as run_rtl

    calls = []

    def fake_rtl(frames, cfg, n_frames, build_dir, design="segmenter", simulator="verilator",
                 log=None, state_store="chip"):
        assert state_store == "auto"          # --rtl-state-store's default
        calls.append((n_frames, build_dir, design, simulator))
        total = frames.shape[0]
        n = total if not n_frames else n_frames
        return {"simulator": simulator, "design": design, "module": "dptbd_seg",
                "frames": min(n, total), "of_frames": total, "passed": True,
                "report": "bit-exact", "words_compared": 7, "cycles": 99,
                "cycles_per_second": 1234567, "seconds": 0.0}

    monkeypatch.setattr(run_rtl, "run_rtl", fake_rtl)
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(small), "--rtl", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    # the default: every frame, on Verilator, in its default build root
    assert calls == [(0, None, "segmenter", "verilator")]
    line = ("RTL (dptbd_seg on Verilator) checked frames 0-23 of 24: bit-exact, 7 "
            "candidate-list words compared, 99 cycles")
    assert f"\n{line}\n" in text and line in (out / "table.md").read_text()
    assert "golden model only" not in text
    assert ("  RTL: bit-exact — the generated Verilog (dptbd_seg on Verilator) matches the "
            "golden model on all 24 frames: 7 candidate-list words compared, 99 cycles, "
            "1.23 M cycles/s (0.0 s in all)\n") in text
    rtl = json.loads((out / "summary.json").read_text())["rtl"]
    assert rtl["summary"] == line and rtl["checked_frames"] == [0, 23]
    assert main(["run", "--no-progress", "--scenario", str(small), "--rtl", "--rtl-frames", "12",
                 "--rtl-simulator", "icarus", "--out", str(out), "--force"]) == 0
    text = capsys.readouterr().out
    assert calls[-1] == (12, None, "segmenter", "icarus")
    line = ("RTL (dptbd_seg on Icarus) checked frames 0-11 of 24: bit-exact, 7 candidate-list "
            "words compared, 99 cycles; frames 12-23 come from the golden model only "
            "(--rtl-frames 0 checks all)")
    assert f"\n{line}\n" in text
    assert "on the first 12 of 24 frames: " in text
    assert "; the model's output is used for the rest\n" in text
    rtl = json.loads((out / "summary.json").read_text())["rtl"]
    assert rtl["summary"] == line and rtl["checked_frames"] == [0, 11]
