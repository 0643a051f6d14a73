"""The dptbd command line: jobs run, bad input refused with a clear message."""

import contextlib
import io
import json

import numpy as np
import pytest

from dptbd.cli import main
from dptbd.evaluation.table1 import DETECTORS, SETTINGS, table1_rows


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


def test_table1_one_trial_dp_beats_single_frame():
    rows = table1_rows(trials=1)
    assert len(rows) == len(SETTINGS) * len(DETECTORS)
    pd = {name: np.mean([r.counts.pd for r in rows if r.detector == name]) for name in DETECTORS}
    assert pd["direction-weighted DP"] > pd["single frame"] + 0.2
    for r in rows:
        assert r.counts.frames == 24 and r.counts.mean_false_points <= 33


def test_table1_refuses_bad_trials_and_overwrite(tmp_path, capsys):
    assert main(["table1", "--trials", "0"]) == 2
    assert "trials must be >= 1" in capsys.readouterr().err
    existing = tmp_path / "t.md"
    existing.write_text("mine")
    assert main(["table1", "--trials", "1", "--markdown", str(existing)]) == 2
    assert capsys.readouterr().err == (f"dptbd table1: error: --markdown {existing} exists; pass "
                                       f"--force to overwrite it\n")
    assert existing.read_text() == "mine"


def test_unknown_command_exits_with_usage():
    with pytest.raises(SystemExit) as exc:
        main(["frobnicate"])
    assert exc.value.code == 2
