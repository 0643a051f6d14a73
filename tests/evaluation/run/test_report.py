"""dptbd.evaluation.run.report: the run's tables, summary.json and its all-or-nothing folder."""

import csv
import json

import pytest

from dptbd.evaluation.run import figures as run_figures
from dptbd.evaluation.run.job import run_job
from dptbd.evaluation.run.report import (RUN_FILES, TOOL, format_run_tables, run_summary,
                                         write_run_folder)
from dptbd.evaluation.run.scenario import parse_scenario
from helpers.refusals import whole

SMALL = {"name": "small",
         "scene": {"size": [32, 32], "frames": 24, "snr": 5.0, "seed": 3,
                   "targets": [{"start": [6.0, 6.0], "velocity": [0.8, 0.6]}]},
         "segmentation": {"false_alarm_rate": 0.005}}


@pytest.fixture(scope="module")
def result():
    sc = parse_scenario(SMALL)
    sc.check()
    return run_job(sc)


def test_write_run_folder_writes_every_file(tmp_path, result):
    out = write_run_folder(result, tmp_path / "r")
    assert sorted(p.name for p in out.iterdir()) == sorted(RUN_FILES)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r"]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["tool"] == TOOL == "dptbd run" and summary["table"] == result.rows
    assert summary["dp_config"] == json.loads(json.dumps(result.cfg.to_mapping()))
    assert summary["rtl"] == {"checked": False, "summary": "RTL not simulated (golden model "
                              "only; --rtl checks the generated Verilog)"}
    assert (out / "table.md").read_text() == result.table_text + "\n"
    cands = list(csv.DictReader(open(out / "candidates.csv")))
    assert len(cands) == sum(len(c) for c in result.pipeline.candidates)
    assert 'name = "small"' in (out / "scenario.toml").read_text()


def test_run_summary_names_the_report_frame_and_the_time(result):
    summary = run_summary(result, 1.234)
    assert summary["seconds"] == 1.23 and summary["report_frame"] == 12
    assert summary["frames"] == 24 and summary["candidates_per_frame"] == result.input.count


def test_an_earlier_folder_is_refused_without_force_and_replaced_with_it(tmp_path, result):
    out = write_run_folder(result, tmp_path / "r")
    (out / "extra.txt").write_text("from the earlier run")
    with pytest.raises(FileExistsError, match=whole(
            f"--out {out} exists; pass --force to replace it, or choose another folder")):
        write_run_folder(result, out)
    write_run_folder(result, out, force=True)
    assert not (out / "extra.txt").exists()


def test_a_failing_figure_leaves_no_folder(tmp_path, result, monkeypatch):
    def disk_full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(run_figures, "figure_accumulated", disk_full)
    with pytest.raises(OSError, match=r"^\[Errno 28\] No space left on device$"):
        write_run_folder(result, tmp_path / "r")
    assert list(tmp_path.iterdir()) == []


def test_format_run_tables():
    assert format_run_tables(2.0, [], [], None) == "confirmed tracks (0):\n(none)"
    assert format_run_tables(2.0, [], [], {"summary": "RTL line"}).endswith("(none)\n\nRTL line")
