"""``dptbd run``, the main job: what it writes (tables, figures, summary, the bits per segment),
its scene options, recorded data, and the first-level table of the built-in scenario."""

import contextlib
import io
import json

import numpy as np
import pytest
from PIL import Image

from dptbd.cli import main
from helpers.run_command import leftovers


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
