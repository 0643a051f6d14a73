"""The dptbd command line: jobs run, bad input refused with a clear message."""

import numpy as np
import pytest

from dptbd.cli import main
from dptbd.model.table1 import DETECTORS, SETTINGS, table1_rows


def test_run_prints_the_first_level_table(tmp_path, capsys):
    assert main(["run", "--seed", "1", "--no-progress", "--out", str(tmp_path / "r")]) == 0
    out = capsys.readouterr().out
    assert "| 1 | (30, 100) | (0.8, -0.4) | 16 |" in out
    assert "| 2 | (54, 40) | (0.4, 0.6) | 16 |" in out


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
    assert "pass --force" in capsys.readouterr().err
    assert existing.read_text() == "mine"


def test_unknown_command_exits_with_usage():
    with pytest.raises(SystemExit) as exc:
        main(["frobnicate"])
    assert exc.value.code == 2
