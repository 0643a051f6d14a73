"""dptbd.evaluation.detectors.report: the table, the records, the run line, the figure and the
all-or-nothing --out folder of ``dptbd detectors``."""

import csv
import json
import math

import pytest
from PIL import Image

from dptbd.evaluation.detectors import report
from dptbd.evaluation.detectors.pd_vs_snr import CompareResult
from dptbd.evaluation.detectors.scoring import Counts
from dptbd.evaluation.detectors.report import (OUT_FILES, TOOL, describe_run, error_bars,
                                               figure_pd_vs_snr, format_table, rows, write_folder)
from helpers.refusals import whole

PARAMS = dict(scene="image", frames=9, first_frame=7, trials=2, noise_trials=5,
              false_alarm_rate=0.1, matched=False, preset_snr_db=10.0, gate=1, seed=6,
              snrs_db=(8.0, 12.0))


@pytest.fixture
def result():
    return CompareResult(
        detectors=("ca-cfar", "info"), snrs_db=(8.0, 12.0),
        thresholds={"ca-cfar": 3.5, "info": {8.0: 1.0, 12.0: 2.0}},
        false_alarms={"ca-cfar": Counts(9, 100), "info": Counts(10, 100)},
        detections={("ca-cfar", 8.0): Counts(1, 4), ("ca-cfar", 12.0): Counts(4, 4),
                    ("info", 8.0): Counts(0, 4), ("info", 12.0): Counts(2, 4)},
        params=PARAMS)


def test_format_table(result):
    lines = format_table(result).splitlines()
    assert lines[0] == "| detector | 8 dB | 12 dB | threshold | noise false alarms |"
    assert lines[2] == ("| `ca-cfar` | 0.25 [0.05, 0.70] | 1.00 [0.51, 1.00] | 3.5 | "
                        "9/100 = 0.0900 |")
    assert lines[3].startswith("| `info` | 0.00 [") and "| per SNR | 10/100 = 0.1000 |" in lines[3]


def test_rows_take_the_threshold_of_their_snr(result):
    records = rows(result)
    assert [(r["detector"], r["snr_db"], r["threshold"]) for r in records] == [
        ("ca-cfar", 8.0, 3.5), ("ca-cfar", 12.0, 3.5), ("info", 8.0, 1.0), ("info", 12.0, 2.0)]
    assert records[0]["pd"] == 0.25 and records[0]["noise_decisions"] == 100


def test_describe_run(result):
    assert describe_run(result, 3.4, ["info.sigma=2"]) == (
        "image scenes, 9 frames, frames 7..8 scored, 2 target scenes per SNR, 5 noise-only "
        "scenes, Pfa 0.1 per decision, preset SNR channel 10.0 dB, gate 1 cell, seed 6, 3 s; "
        "--set info.sigma=2")


def test_figure(tmp_path, result):
    figure_pd_vs_snr(result, tmp_path / "f.png")
    with Image.open(tmp_path / "f.png") as img:
        assert img.size == (640, 420)


@pytest.fixture
def ends():
    """Pd at the ends: 0 of 6 and 6 of 6 scored frames (the Wilson formula's rounding put
    0 of 6's lower bound at 2.8e-17, above Pd), and a detector with no scored frame."""
    return CompareResult(
        detectors=("ca-cfar", "info"), snrs_db=(6.0, 12.0),
        thresholds={"ca-cfar": 3.5, "info": 1.0},
        false_alarms={"ca-cfar": Counts(1, 120), "info": Counts(1, 120)},
        detections={("ca-cfar", 6.0): Counts(0, 6), ("ca-cfar", 12.0): Counts(6, 6),
                    ("info", 6.0): Counts(0, 0), ("info", 12.0): Counts(1, 6)},
        params=dict(PARAMS, snrs_db=(6.0, 12.0)))


def test_the_figure_draws_the_tables_intervals_and_none_where_pd_is_undefined(tmp_path, ends):
    records = {(r["detector"], r["snr_db"]): r for r in rows(ends)}
    assert (records[("ca-cfar", 6.0)]["pd_lo"], records[("ca-cfar", 12.0)]["pd_hi"]) == (0.0, 1.0)
    pd, below, above = error_bars(ends, "ca-cfar")
    assert pd == [0.0, 1.0] and below == [0.0, 1.0 - records[("ca-cfar", 12.0)]["pd_lo"]]
    assert above == [records[("ca-cfar", 6.0)]["pd_hi"], 0.0]
    pd, below, above = error_bars(ends, "info")
    r = records[("info", 12.0)]
    assert math.isnan(pd[0]) and pd[1] == r["pd"] == 1 / 6
    assert below == [0.0, r["pd"] - r["pd_lo"]] and above == [0.0, r["pd_hi"] - r["pd"]]
    assert format_table(ends).splitlines()[3] == (
        "| `info` | no scored frame | 0.17 [0.03, 0.56] | 1 | 1/120 = 0.0083 |")
    figure_pd_vs_snr(ends, tmp_path / "f.png")
    with Image.open(tmp_path / "f.png") as img:
        assert img.size == (640, 420)


def test_result_json_is_strict_with_null_for_an_undefined_pd(tmp_path, ends):
    def no_constant(name):
        raise ValueError(f"{name} is not JSON")

    out = write_folder(ends, tmp_path / "d", "TABLE", "NOTE", {"seed": 6})
    saved = json.loads((out / "result.json").read_text(), parse_constant=no_constant)
    undefined = [r for r in saved["rows"] if r["opportunities"] == 0]
    assert [(r["detector"], r["pd"], r["pd_lo"], r["pd_hi"]) for r in undefined] == [
        ("info", None, None, None)]


def test_write_folder_all_or_nothing(tmp_path, result, monkeypatch):
    out = write_folder(result, tmp_path / "d", "TABLE", "NOTE", {"seed": 6})
    assert sorted(p.name for p in out.iterdir()) == sorted(OUT_FILES)
    saved = json.loads((out / "result.json").read_text())
    assert saved["tool"] == TOOL == "dptbd detectors" and saved["params"]["snrs_db"] == [8.0, 12.0]
    assert (out / "table.md").read_text() == "TABLE\n\nNOTE\n"
    assert len(list(csv.DictReader(open(out / "table.csv")))) == 4
    with pytest.raises(FileExistsError, match=whole(
            f"--out {out} exists; pass --force to replace it, or choose another folder")):
        write_folder(result, out, "TABLE", "NOTE", {})
    def disk_full(*args):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(report, "figure_pd_vs_snr", disk_full)
    with pytest.raises(OSError, match=r"^\[Errno 28\] No space left on device$"):
        write_folder(result, tmp_path / "e", "TABLE", "NOTE", {})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d"]
