"""``dptbd run``, the main job: what it writes, its options, overwriting, recorded data, and
bad input refused with a clear message (exit 2) and nothing left in the output folder."""

import contextlib
import io
import json
import re
import shutil

import numpy as np
import pytest
from PIL import Image

from dptbd.evaluation.run import figures as run_figures
from dptbd.cli import main

SMALL = """\
name = "small"
[scene]
size = [32, 32]
frames = 24
snr = 5.0
seed = 3
[[scene.targets]]
start = [6.0, 6.0]
velocity = [0.8, 0.6]
[segmentation]
false_alarm_rate = 0.005
"""


@pytest.fixture
def small(tmp_path):
    path = tmp_path / "inputs" / "small.toml"
    path.parent.mkdir()
    path.write_text(SMALL)
    return path


def leftovers(folder):
    """Everything in ``folder`` except the inputs folder (partial or output folders)."""
    return sorted(p.name for p in folder.iterdir() if p.name != "inputs")


def test_builtin_scenario_writes_table_figures_and_bits_per_segment(tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "FPGA -> DSP: 327680 bits per segment" in text
    for name in ("table.md", "table.csv", "tracks.csv", "candidates.csv", "summary.json",
                 "scenario.toml", "raw_frame.png", "accumulated.png", "tracks.png"):
        assert (out / name).stat().st_size > 0, name
    summary = json.loads((out / "summary.json").read_text())
    assert summary["tool"] == "dptbd run" and len(summary["table"]) == 2
    bits = summary["bits_per_segment"]
    assert bits["image_bits"] == 128 * 128 * 20 and bits["word_bits"] == 35
    # by default the DSP receives the gateware segmenter's lists, selected for n_hw = 2n = 66
    # into at most C = 128 records, with s calibrated on the first K frames (s = 2, not
    # DPConfig's configuration-only s = 5), and trims each to n = 33
    seg = summary["segmenter"]
    assert summary["lists"] == "gateware" and summary["candidates_per_frame"] == 33
    assert (seg["candidate_count"], seg["candidate_capacity"]) == (66, 128)
    assert seg["histogram_shift"] == 2 and "first K = 6 frames" in seg["histogram_shift_from"]
    gw, dsp = bits["gateware_lists"], bits["dsp_lists"]
    # the stale threshold scatters the count around n_hw (seed 0: mean 57.9, max 104); with
    # s = 5 the lists would average 14.5 records
    assert 40 <= gw["records_mean"] <= 90 and 33 < gw["records_max"] <= 128
    assert gw["bits_mean"] == pytest.approx((gw["records_mean"] + 1) * 35, abs=1)
    assert 100 < gw["reduction"] < 275            # more than n records, fewer than the image
    # the DSP keeps at most n per list: trimmed (the first list after reset is empty)
    assert dsp["records_max"] == 33 and 25 <= dsp["records_mean"] <= 33
    assert "confirmed track ids" in (out / "table.md").read_text()
    assert summary["rtl"]["checked"] is False
    header = (out / "table.csv").read_text().splitlines()[0]
    assert "frames_until_output" in header and "pd" in header and "track_ids" in header
    for name in ("raw_frame.png", "accumulated.png", "tracks.png"):
        with Image.open(out / name) as img:
            assert img.format == "PNG" and min(img.size) >= 400
    assert not list(tmp_path.glob(".r.partial-*"))


def test_options_seed_snr_target_and_scenario_file(tmp_path, small, capsys):
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(small), "--seed", "5", "--snr", "6",
                 "--target", "20,4,0.2,0.9", "--out", str(out)]) == 0
    effective = (out / "scenario.toml").read_text()
    assert "seed = 5" in effective and "snr = 6.0" in effective
    assert "start = [20.0, 4.0]" in effective and "velocity = [0.2, 0.9]" in effective
    rows = json.loads((out / "summary.json").read_text())["table"]
    assert [r["start"] for r in rows] == [[20.0, 4.0]]
    # the written scenario reruns the same job
    again = tmp_path / "again"
    assert main(["run", "--no-progress", "--scenario", str(out / "scenario.toml"),
                 "--out", str(again)]) == 0
    assert (again / "table.md").read_text() == (out / "table.md").read_text()


def test_refuses_to_overwrite_unless_forced(tmp_path, small, capsys):
    out = tmp_path / "r"
    args = ["run", "--no-progress", "--scenario", str(small), "--out", str(out)]
    assert main(args) == 0
    before = (out / "summary.json").read_bytes()
    capsys.readouterr()
    assert main(args) == 2
    assert capsys.readouterr().err == (f"dptbd run: error: --out {out} exists; pass --force to "
                                       f"replace it, or choose another folder\n")
    assert (out / "summary.json").read_bytes() == before
    assert main(args + ["--seed", "9", "--force"]) == 0
    assert json.loads((out / "summary.json").read_text())["scenario"]["scene"]["seed"] == 9
    assert leftovers(tmp_path) == ["r"]
    # --force never deletes a folder that dptbd run did not write
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep")
    assert main(["run", "--no-progress", "--scenario", str(small), "--out", str(mine),
                 "--force"]) == 2
    assert capsys.readouterr().err == (
        f"dptbd run: error: --out {mine} is not the folder of an earlier dptbd run (no "
        f"summary.json from it); --force will not replace it\n")
    assert (mine / "notes.txt").read_text() == "keep"


def _bad_inputs(inputs):
    """name -> (extra arguments, message fragment)."""
    rng = np.random.default_rng(0)
    cases = {}
    cases["missing file"] = (["--input", str(inputs / "nope.npy")], "does not exist")
    (inputs / "broken.npy").write_bytes(b"\x93NUMPY garbage")
    cases["unreadable file"] = (["--input", str(inputs / "broken.npy")], "damaged or truncated")
    (inputs / "text.npy").write_bytes(b"these are not frames\n")
    cases["not a .npy file"] = (["--input", str(inputs / "text.npy")],
                                "is not a NumPy .npy file")
    np.save(inputs / "objects.npy", np.array([{"a": 1}], dtype=object), allow_pickle=True)
    cases["object array"] = (["--input", str(inputs / "objects.npy")], "holds Python objects")
    snr = "(001's SNR = (target mean - noise mean) / sigma) must be a finite real number in (0, inf)"
    cases["negative --snr"] = (["--snr", "-1"], f"--snr {snr}, got -1.0\n")
    cases["zero --snr"] = (["--snr", "0"], f"--snr {snr}, got 0.0\n")
    cases["nan --snr"] = (["--snr", "nan"], f"--snr {snr}, got nan\n")
    cases["inf --snr"] = (["--snr", "inf"], f"--snr {snr}, got inf\n")
    cases["negative target SNR"] = (["--target", "20,4,0.2,0.9,-2"],
                                    f"--target '20,4,0.2,0.9,-2': SNR {snr}, got -2.0\n")
    (inputs / "snr.toml").write_text(SMALL.replace("snr = 5.0", "snr = -5.0"))
    cases["negative TOML snr"] = (["--scenario", str(inputs / "snr.toml")],
                                  "[scene] snr must be a finite real number in (0, inf), got -5.0\n")
    np.save(inputs / "empty.npy", np.zeros((0, 16, 16), np.uint8))
    cases["empty sequence"] = (["--input", str(inputs / "empty.npy")], "empty")
    np.save(inputs / "short.npy", rng.integers(0, 255, (3, 16, 16)).astype(np.uint8))
    cases["shorter than a segment"] = (["--input", str(inputs / "short.npy")],
                                       "shorter than one segment")
    np.save(inputs / "float.npy", rng.random((8, 16, 16)))
    cases["float data"] = (["--input", str(inputs / "float.npy")], "must be integers")
    sizes = inputs / "sizes"
    sizes.mkdir()
    Image.fromarray(np.zeros((16, 16), np.uint8)).save(sizes / "f0.png")
    Image.fromarray(np.zeros((16, 18), np.uint8)).save(sizes / "f1.png")
    cases["mixed sizes"] = (["--input", str(sizes)], "mixed sizes")
    depths = inputs / "depths"
    depths.mkdir()
    Image.fromarray(np.zeros((16, 16), np.uint8)).save(depths / "f0.png")
    Image.fromarray(np.zeros((16, 16), np.uint16)).save(depths / "f1.png")
    cases["mixed dtypes"] = (["--input", str(depths)], "mixed bit depths")
    (inputs / "nothing").mkdir()
    cases["empty folder"] = (["--input", str(inputs / "nothing")], "empty")
    (inputs / "unknown.toml").write_text(SMALL.replace("seed = 3", "seed = 3\ncolour = 1"))
    cases["unknown TOML key"] = (["--scenario", str(inputs / "unknown.toml")],
                                 "unknown key(s) ['colour'] in [scene]")
    (inputs / "assoc.toml").write_text(SMALL + "[association]\ngatee = 3\n")
    cases["unknown association key"] = (["--scenario", str(inputs / "assoc.toml")],
                                        "unknown key(s) ['gatee'] in [association]")
    (inputs / "range.toml").write_text(SMALL + "[association]\nmax_misses = 300\n")
    cases["value out of range"] = (["--scenario", str(inputs / "range.toml")],
                                   "max_misses must be an integer in [0, 255]")
    cases["seed with recorded data"] = (["--input", str(inputs / "short.npy"), "--seed", "1"],
                                        "--seed applies to a simulated scene")
    return cases


def test_bad_input_is_refused_by_name_and_leaves_nothing(tmp_path, capsys):
    inputs = tmp_path / "inputs"
    inputs.mkdir()
    for name, (extra, message) in _bad_inputs(inputs).items():
        out = tmp_path / "out"
        assert main(["run", "--no-progress", "--out", str(out)] + extra) == 2, name
        err = capsys.readouterr().err
        assert err.startswith("dptbd run: error:") and message in err, (name, err)
        assert "Traceback" not in err
        assert "pickled" not in err or name == "object array", (name, err)
        assert leftovers(tmp_path) == [], name


def test_a_failure_while_writing_leaves_no_folder(tmp_path, small, capsys, monkeypatch):
    def disk_full(*args, **kwargs):
        raise OSError(28, "No space left on device", str(tmp_path / "x.png"))

    monkeypatch.setattr(run_figures, "figure_tracks", disk_full)
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(small), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "No space left on device" in err and "Traceback" not in err
    assert leftovers(tmp_path) == []
    # and an existing run folder survives a failed --force run untouched
    monkeypatch.undo()
    assert main(["run", "--no-progress", "--scenario", str(small), "--out", str(out)]) == 0
    before = sorted(p.name for p in out.iterdir())
    monkeypatch.setattr(run_figures, "figure_tracks", disk_full)
    assert main(["run", "--no-progress", "--scenario", str(small), "--out", str(out),
                 "--force"]) == 2
    assert sorted(p.name for p in out.iterdir()) == before and leftovers(tmp_path) == ["r"]


def _bright_sequence(t=36, h=32, w=32, bits=8):
    """Noise with one bright target moving (0.5, 0.75) px/frame: recorded data, no truth."""
    rng = np.random.default_rng(2)
    top = (1 << bits) - 1
    frames = rng.normal(top * 0.2, top * 0.03, (t, h, w))
    for k in range(t):
        frames[k, int(4 + 0.5 * k), int(3 + 0.6 * k)] += top * 0.4
    return np.clip(np.rint(frames), 0, top).astype(np.uint8 if bits == 8 else np.uint16)


@pytest.mark.parametrize("kind", ["npz", "png16"])
def test_recorded_data_gives_tracks_and_figures_without_truth(tmp_path, capsys, kind):
    inputs = tmp_path / "inputs"
    inputs.mkdir()
    if kind == "npz":
        seq = _bright_sequence()
        np.savez(inputs / "seq.npz", frames=seq, other=np.zeros(3))
        src = ["--input", str(inputs / "seq.npz")]
    else:
        seq = _bright_sequence(bits=16)
        folder = inputs / "frames"
        folder.mkdir()
        for i, f in enumerate(seq):
            Image.fromarray(f).save(folder / f"img{i}.png")
        src = ["--input", str(folder)]
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--out", str(out)] + src) == 0
    text = capsys.readouterr().out
    assert "recorded data" in text and "confirmed tracks (" in text
    summary = json.loads((out / "summary.json").read_text())
    # named after the input, not after the built-in scenario
    name = "seq.npz" if kind == "npz" else "frames"
    assert summary["scenario"]["name"] == name and summary["source"].startswith(f"{name}: ")
    assert "paper001" not in text and f'name = "{name}"' in (out / "scenario.toml").read_text()
    assert summary["table"] == [] and summary["false_tracks"] is None
    assert summary["input_bits"] == (8 if kind == "npz" else 16)
    assert len(summary["tracks"]) >= 1
    track = summary["tracks"][0]
    assert track["target"] is None and abs(track["velocity"][0] - 0.5) < 0.3
    for name in ("raw_frame.png", "accumulated.png", "tracks.png"):
        assert (out / name).stat().st_size > 0


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


@pytest.mark.slow
@VERILATOR
def test_rtl_at_640x512_takes_the_axi_state_store(tmp_path, capsys):
    """A 640 x 512 scenario (12 frames: two segments of K = 6): its 6.5 Mbit of state
    exceed the largest device's block RAM, so --rtl runs dptbd_axi --state-store axi (about
    3 minutes on a loaded 2-core machine, the build included)."""
    scenario = tmp_path / "sensor.toml"
    scenario.write_text(SENSOR)
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(scenario), "--rtl",
                 "--rtl-build-dir", str(tmp_path / "build"), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    # 12 frames of 327 680 pixels at one per clock, + latency 17 + 1
    line = ("RTL (dptbd_axi --state-store axi on Verilator) checked frames 0-11 of 12: "
            "bit-exact, 130 candidate-list words compared, 3932178 cycles")
    assert f"\n{line}\n" in text
    rtl = json.loads((out / "summary.json").read_text())["rtl"]
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
    scenario = tmp_path / "rd.toml"
    scenario.write_text(RANGE_DOPPLER)
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(scenario), "--rtl",
                 "--rtl-build-dir", str(tmp_path / "build"), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    # 12 frames of 1 048 576 pixels at one per clock, + latency 17 + 1
    line = ("RTL (dptbd_axi --state-store axi on Verilator) checked frames 0-11 of 12: "
            "bit-exact, 95 candidate-list words compared, 12582930 cycles")
    assert f"\n{line}\n" in text
    rtl = json.loads((out / "summary.json").read_text())["rtl"]
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


def test_ideal_lists_option_and_bad_lists_value(tmp_path, small, capsys):
    out = tmp_path / "r"
    assert main(["run", "--no-progress", "--scenario", str(small), "--lists", "ideal",
                 "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    n = summary["candidates_per_frame"]
    assert summary["lists"] == "ideal"
    assert summary["bits_per_segment"]["dsp_lists"]["records_max"] <= n
    assert 'lists = "ideal"' in (out / "scenario.toml").read_text()
    bad = tmp_path / "inputs" / "bad.toml"
    bad.write_text(small.read_text().replace("[segmentation]", '[segmentation]\nlists = "two-pass"'))
    assert main(["run", "--no-progress", "--scenario", str(bad), "--out", str(tmp_path / "b")]) == 2
    assert "lists must be one of 'gateware', 'ideal'" in capsys.readouterr().err
    assert leftovers(tmp_path) == ["r"]


def test_segmenter_settings_come_from_the_data_unless_given():
    from dptbd.config import DPConfig
    from dptbd.dsp.association import AssociationConfig
    from dptbd.evaluation.chain import segmenter_settings

    cfg = DPConfig(width=128, height=128, segment_frames=6, input_bits=12, energy_bits=16)
    frames = np.full((12, 128, 128), 600, np.uint16)
    frames[8, 5, 5] = 4000                    # after the first segment: not calibrated on
    got = segmenter_settings(cfg, frames, 33, AssociationConfig())
    # the first K = 6 frames: K * max = 3600 needs 12 bits: 2^10 bins reach it with s = 2
    # (DPConfig's configuration-only default: 15 - 10 = 5; the whole sequence: 6 * 4000
    # needs 15 bits, s = 5 too)
    assert cfg.bin_shift == 5 and got.bin_shift == 2
    assert segmenter_settings(cfg, frames, 33, AssociationConfig(),
                              calibration_frames=12).bin_shift == 5
    with pytest.raises(ValueError, match=r"^calibration_frames must be an integer in \[1, inf\), got 0$"):
        segmenter_settings(cfg, frames, 33, AssociationConfig(), calibration_frames=0)
    # the gateware selects 2n = 66 (headroom 2), the DSP trims to 33; C = min(2 * 66, 128)
    assert got.n_candidates == 66 and got.record_capacity == 128
    assert segmenter_settings(cfg, frames, 33, AssociationConfig(), 1.0).n_candidates == 33
    mine = DPConfig(width=128, height=128, segment_frames=6, input_bits=12, energy_bits=16,
                    histogram_shift=4, candidate_capacity=40)
    kept = segmenter_settings(mine, frames, 33, AssociationConfig())
    assert kept.bin_shift == 4 and kept.record_capacity == 40 and kept.n_candidates == 40


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


def test_scenario_file_with_recorded_data_is_named_after_it(tmp_path):
    from dptbd.evaluation.run.scenario import parse_scenario

    sc = parse_scenario({"input": {"path": "clip.npz"}}, tmp_path)
    assert sc.name == "clip.npz" and sc.input_path == tmp_path / "clip.npz"
    sc = parse_scenario({"name": "mine", "input": {"path": "clip.npz"}}, tmp_path)
    assert sc.name == "mine"


@pytest.fixture(scope="module")
def default_run(tmp_path_factory):
    """``dptbd run`` with no scene options (the built-in scenario, seed 0), run once for
    this module: (printed output, summary.json)."""
    out = tmp_path_factory.mktemp("run") / "r"
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["run", "--no-progress", "--out", str(out)]) == 0
    return buf.getvalue(), json.loads((out / "summary.json").read_text())


def test_run_prints_the_first_level_table(default_run):
    out, _ = default_run
    assert "| 1 | (30, 100) | (0.8, -0.4) | 16 |" in out
    assert "| 2 | (54, 40) | (0.4, 0.6) | 16 |" in out


def test_default_run_confirms_both_targets_with_sane_figures(default_run):
    _, summary = default_run
    rows, tracks = summary["table"], {t["track"]: t for t in summary["tracks"]}
    assert [r["target"] for r in rows] == [1, 2]
    for r in rows:
        # a confirmed track on each target, and each of its ids is a track of that target
        assert r["track_ids"], r
        assert all(tracks[i]["target"] == r["target"] for i in r["track_ids"])
        assert 0.0 <= r["pd"] <= 1.0 and r["detections"] <= r["accumulated_frames"] == 16
        assert r["pd"] == pytest.approx(r["detections"] / 16, abs=1e-4)
        assert 0.0 <= r["mean_false_points"] <= 33
        assert 1 <= r["segments_until_confirmation"] <= 16
        assert 6 <= r["frames_until_output"] <= 100
        assert 0 <= r["track_length_after_output"] <= r["track_length"] <= 100
        assert r["frames_until_output"] + r["track_length_after_output"] <= 100
        assert 0.0 <= r["rms_error"] < 2.5
    # most confirmed tracks follow a target (seed 0: 3 tracks, 1 false)
    assert 0 <= summary["false_tracks"] < len(tracks)
    assert sum(1 for t in tracks.values() if t["target"] == "false") == summary["false_tracks"]


# ---- --dsp c: the DSP stage on the C firmware ------------------------------------------------

def test_dsp_c_writes_the_same_tables_tracks_and_figures(tmp_path, small, capsys):
    """The C firmware gives the Python model's tracks bit for bit: every file but the
    summary's ``dsp`` key and its time is the same, and so is what is printed."""
    outs = {}
    for dsp in ("python", "c"):
        outs[dsp] = tmp_path / dsp
        assert main(["run", "--no-progress", "--scenario", str(small), "--dsp", dsp,
                     "--out", str(outs[dsp])]) == 0
        outs[dsp + "-printed"] = capsys.readouterr().out
    py, c = outs["python"], outs["c"]
    assert sorted(p.name for p in py.iterdir()) == sorted(p.name for p in c.iterdir())
    for path in py.iterdir():
        if path.name != "summary.json":
            assert path.read_bytes() == (c / path.name).read_bytes(), path.name
    summary_py, summary_c = (json.loads((o / "summary.json").read_text()) for o in (py, c))
    assert "dsp" not in summary_py and summary_c.pop("dsp") == "c"
    for s in (summary_py, summary_c):
        s.pop("seconds")
    assert summary_py == summary_c
    printed_py, printed_c = (re.sub(r"(in |\()\d+\.\d s", r"\1T s", outs[k + "-printed"])
                             .replace(str(outs[k]), "OUT") for k in ("python", "c"))
    assert printed_c == printed_py.replace("  DSP stage:", "  DSP stage (C firmware):")


def test_dsp_c_without_a_compiler_is_refused_before_any_work(tmp_path, small, capsys,
                                                             monkeypatch):
    monkeypatch.setenv("CC", "no-such-cc")
    assert main(["run", "--no-progress", "--scenario", str(small), "--dsp", "c",
                 "--out", str(tmp_path / "r")]) == 2
    captured = capsys.readouterr()
    assert captured.err == (
        "dptbd run: error: --dsp c: no C compiler: 'no-such-cc' ($CC) is not on PATH; the DSP "
        "firmware needs one (Debian: apt-get install gcc, or clang; or set CC to a compiler)\n")
    assert captured.out == "" and leftovers(tmp_path) == []


def test_dsp_value_is_refused_by_the_command_line(tmp_path, small, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "--scenario", str(small), "--dsp", "asm", "--out", str(tmp_path / "r")])
    assert exc.value.code == 2
    assert ("argument --dsp: invalid choice: 'asm' (choose from 'python', 'c')"
            in capsys.readouterr().err)
