"""``dptbd detectors`` through the real CLI: exit 2 on bad input, ``--out`` and no silent overwrite."""

from __future__ import annotations

import argparse
import csv
import json

import pytest

from dptbd.cli import main as dptbd
from dptbd.commands import detectors as detectors_command
from dptbd.evaluation.detectors import DetectorError
from helpers.refusals import whole

#: the smallest real run: CA-CFAR on 9-frame images, 2 scored frames per scene
TINY = ["detectors", "--detectors", "ca-cfar", "--scene", "image", "--snr", "12", "--frames", "9",
        "--trials", "2", "--noise-trials", "5", "--pfa", "0.1", "--jobs", "1"]


@pytest.mark.parametrize("extra,name", [
    (["--detectors", "info,mht"], "unknown detector 'mht'"),
    (["--detectors", ""], "detectors must name at least one"),
    (["--pfa", "1.5"], "false_alarm_rate"),
    (["--pfa", "0.001"], "noise_trials"),
    (["--frames", "1"], "frames"),
    (["--trials", "0"], "trials"),
    (["--noise-trials", "-3"], "noise_trials"),
    (["--preset-snr-db", "90"], "preset_snr_db"),
    (["--snr", "nan"], "snr_db"),
    (["--jobs", "0"], "jobs"),
    (["--detectors", "dw-dp", "--frames", "6", "--noise-trials", "20"], "segment_frames=8"),
    (["--detectors", "dp-penalty", "--set", "dp-penalty.alpha=1.5"], "alpha (eq (22) coefficient)"),
    (["--detectors", "dp-amplitude", "--set", "dp-amplitude.alpha=-1"], "alpha (eq (22) coefficient)"),
    (["--detectors", "dp-likelihood", "--set", "dp-likelihood.epsilon=1"], "epsilon"),
    (["--detectors", "dp-likelihood", "--set", "dp-likelihood.sigma=0"], "sigma (printed delta"),
    (["--detectors", "info", "--set", "info.kernel=[[0.1,0.1,0.1],[0.1,0.1,0.1],[0.1,0.1,0.1]]"],
     "kernel must sum to 1"),
    (["--detectors", "info", "--set", "info.kernel=[[0.5,0.5]]"], "kernel must be 2-D with odd sides"),
    (["--detectors", "grid-bayes", "--set", "grid-bayes.birth=1.0"], "birth"),
    (["--detectors", "grid-bayes", "--set", "grid-bayes.death=0"], "death"),
    (["--set", "ca-cfar.n_ref=64"], "at least 67"),
    (["--set", "ca-cfar.n_ref=15"], "even"),
    (["--set", "ca-cfar.threshold=3"], "detector 'ca-cfar' has no parameter 'threshold'"),
    (["--set", "ca-cfar"], "expected DETECTOR.PARAMETER=VALUE"),
    (["--set", "mht.x=1"], "unknown detector 'mht'"),
    (["--set", "info.known_noise=true"], "not in --detectors"),
    (["--set", "ca-cfar.axis=5"], "axis must be -2 (range, rows) or -1 (Doppler, columns), got 5"),
    (["--set", "ca-cfar.axis=0"], "axis must be -2 (range, rows) or -1 (Doppler, columns), got 0"),
    (["--set", "ca-cfar.axis=-2.0"], "axis must be -2"),
    (["--detectors", "info", "--set", "info.sigma_kernel=-1"], "sigma_kernel (kernel standard deviation"),
    (["--detectors", "info", "--set", 'info.sigma_kernel="wide"'], "sigma_kernel (kernel standard deviation"),
    (["--detectors", "info", "--set", "info.sigma_kernel=0.5", "--set", "info.kernel=[[1]]"],
     "kernel or sigma_kernel, not both"),
    (["--detectors", "info", "--set", 'info.known_noise="yes"'], "known_noise must be true or false, got 'yes'"),
    (["--detectors", "grid-bayes", "--set", "grid-bayes.known_noise=1"], "known_noise must be true or false"),
])
def test_bad_input_exits_2_naming_the_parameter(extra, name, capsys, tmp_path):
    md = tmp_path / "t.md"
    assert dptbd(TINY + extra + ["--markdown", str(md)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("dptbd detectors: error:") and name in err
    assert not md.exists()


@pytest.mark.parametrize("jobs", ["0", "-2", "1025"])
def test_a_bad_worker_count_is_refused_whole(jobs, capsys):
    assert dptbd(TINY + ["--jobs", jobs]) == 2
    assert capsys.readouterr().err == (f"dptbd detectors: error: jobs must be an integer in "
                                       f"[1, 1024], got {jobs}\n")


@pytest.mark.parametrize("setting", ["ca-cfar.axis=5", "ca-cfar.axis=1"])
def test_bad_cfar_axis_is_refused_before_any_scene(setting, capsys, tmp_path, monkeypatch):
    """axis is checked when the detector is built, not after the noise scenes are made."""
    from dptbd.evaluation.detectors import pd_vs_snr

    def no_scenes(*args, **kwargs):
        raise AssertionError("scenes were generated before the parameters were checked")

    monkeypatch.setattr(pd_vs_snr, "_map", no_scenes)
    out = tmp_path / "cmp"
    assert dptbd(TINY + ["--set", setting, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "axis must be -2 (range, rows) or -1 (Doppler, columns)" in err and "Traceback" not in err
    assert not out.exists() and not list(tmp_path.iterdir())


def test_out_writes_table_csv_json_and_figure_and_never_overwrites(tmp_path, capsys):
    out = tmp_path / "cmp"
    assert dptbd(TINY + ["--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert sorted(p.name for p in out.iterdir()) == ["pd_vs_snr.png", "result.json", "table.csv", "table.md"]
    table = (out / "table.md").read_text()
    assert table.splitlines()[0] == "| detector | 12 dB | threshold | noise false alarms |"
    assert table.split("\n\n")[0] in printed
    rows = list(csv.DictReader(open(out / "table.csv")))
    assert [(r["detector"], float(r["snr_db"]), int(r["opportunities"])) for r in rows] == [("ca-cfar", 12.0, 4)]
    result = json.loads((out / "result.json").read_text())
    assert result["tool"] == "dptbd detectors" and result["rows"][0]["detections"] == int(rows[0]["detections"])
    assert f"| `ca-cfar` | {float(rows[0]['pd']):.2f} [" in table
    assert (out / "pd_vs_snr.png").read_bytes()[:4] == b"\x89PNG"

    # an existing folder is refused before any work, and left as it was
    (out / "notes.txt").write_text("mine")
    assert dptbd(TINY + ["--out", str(out)]) == 2
    assert capsys.readouterr().err == (f"dptbd detectors: error: --out {out} exists; pass --force "
                                       f"to replace it, or choose another folder\n")
    assert (out / "notes.txt").read_text() == "mine"
    # --force replaces an earlier dptbd detectors folder as a whole
    assert dptbd(TINY + ["--out", str(out), "--force"]) == 0
    assert not (out / "notes.txt").exists() and (out / "result.json").exists()
    capsys.readouterr()
    # ... but never a folder it did not write
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "data.csv").write_text("precious")
    assert dptbd(TINY + ["--out", str(foreign), "--force"]) == 2
    assert capsys.readouterr().err == (
        f"dptbd detectors: error: --out {foreign} is not the folder of an earlier dptbd detectors "
        f"run (no result.json from it); --force will not replace it\n")
    assert (foreign / "data.csv").read_text() == "precious"
    assert not list(tmp_path.glob(".*partial*"))  # no staging folder left behind


@pytest.mark.parametrize("option,name,message", [
    ("--markdown", "t.md", "{option} {path} exists; pass --force to overwrite it"),
    ("--figure", "f.png", "{option} {path} exists; pass --force to overwrite it"),
    ("--figure", "f.jpg", "{option} {path} must end in .png"),
    ("--markdown", "t.txt", "{option} {path} must end in .md"),
    ("--markdown", "missing/t.md", "{option} {path}: the folder {path.parent} does not exist"),
])
def test_single_files_are_checked_before_the_run(tmp_path, capsys, option, name, message):
    path = tmp_path / name
    if "missing" not in name:
        path.write_text("user file")
    assert dptbd(TINY + [option, str(path)]) == 2
    message = message.format(option=option, path=path)
    assert capsys.readouterr().err == f"dptbd detectors: error: {message}\n"
    if path.exists():
        assert path.read_text() == "user file"


def test_force_overwrites_single_files(tmp_path):
    md, png = tmp_path / "t.md", tmp_path / "f.png"
    md.write_text("old")
    png.write_text("old")
    assert dptbd(TINY + ["--markdown", str(md), "--figure", str(png), "--force"]) == 0
    assert md.read_text().startswith("| detector |") and png.read_bytes()[:4] == b"\x89PNG"

def test_single_file_inside_out_is_refused(tmp_path, capsys):
    out = tmp_path / "cmp"
    assert dptbd(TINY + ["--out", str(out), "--markdown", str(out / "t.md")]) == 2
    assert capsys.readouterr().err == (f"dptbd detectors: error: {out / 't.md'} is inside --out "
                                       f"{out}, which is written as a whole\n")


def test_set_passes_parameters_to_the_detectors(tmp_path):
    out = tmp_path / "cmp"
    assert dptbd(TINY + ["--set", "ca-cfar.n_ref=8", "--out", str(out)]) == 0
    assert "--set ca-cfar.n_ref=8" in (out / "table.md").read_text()
    assert json.loads((out / "result.json").read_text())["params"]["params"] == {"ca-cfar": {"n_ref": 8}}
    base = tmp_path / "base"
    assert dptbd(TINY + ["--out", str(base)]) == 0
    thr = [float(next(csv.DictReader(open(d / "table.csv")))["threshold"]) for d in (out, base)]
    assert thr[0] != thr[1]  # 8 reference cells: a different ratio statistic on the same noise


def run_cli(argv):
    parser = argparse.ArgumentParser()
    detectors_command.add_arguments(parser)
    return detectors_command.main(parser.parse_args(argv))


def test_command_writes_table_and_figure(tmp_path, capsys):
    md, png = tmp_path / "t.md", tmp_path / "f.png"
    assert run_cli(["--detectors", "ca-cfar,dw-dp", "--scene", "image", "--snr", "8", "--frames", "9",
                    "--trials", "2", "--noise-trials", "5", "--pfa", "0.1", "--jobs", "1",
                    "--markdown", str(md), "--figure", str(png)]) == 0
    out = capsys.readouterr().out
    assert "| `ca-cfar` |" in out and "| `dw-dp` |" in out and "image scenes, 9 frames" in out
    assert md.read_text().startswith("| detector | 8 dB |")
    assert png.read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(FileExistsError, match=whole(f"--markdown {md} exists; pass --force to "
                                                    "overwrite it")):
        run_cli(["--markdown", str(md)])
    with pytest.raises(DetectorError, match=(r"^unknown detector 'foo'; known: dw-dp, "
                                             r"dp-amplitude, dp-penalty, dp-likelihood, info, "
                                             r"grid-bayes, ca-cfar, pf-tbd$")):
        run_cli(["--detectors", "info,foo"])
    with pytest.raises(DetectorError, match=(r"^false_alarm_rate must be a finite real number "
                                             r"in \(0, 1\), got 2\.0$")):
        run_cli(["--detectors", "ca-cfar", "--pfa", "2", "--jobs", "1"])


@pytest.mark.parametrize("extra, message", [
    (["--roc-pfa", "0.1,1.5"], "roc false_alarm_rate must be a finite real number in (0, 1), got 1.5"),
    (["--roc-pfa", "0.05"], "false_alarm_rate=0.05 needs at least 20 noise-only decisions, 5 noise "
                            "trials give 10; raise noise_trials"),
    (["--detectors", "pf-tbd", "--set", "pf-tbd.particles=0"],
     "particles must be an integer in [1, 10000000], got 0"),
    (["--detectors", "pf-tbd", "--set", "pf-tbd.birth=1"], "birth must be a finite real number in (0, 1), got 1"),
])
def test_roc_and_particle_filter_refusals_are_whole(extra, message, capsys, tmp_path):
    roc = tmp_path / "roc.png"
    assert dptbd(TINY + extra + ["--roc", str(roc)]) == 2
    assert capsys.readouterr().err == f"dptbd detectors: error: {message}\n"
    assert not roc.exists()


def test_roc_records_and_figure_at_every_level(tmp_path):
    out, roc = tmp_path / "run", tmp_path / "roc.png"
    assert dptbd(TINY + ["--detectors", "ca-cfar,pf-tbd", "--set", "pf-tbd.particles=200",
                         "--set", "pf-tbd.birth_particles=200", "--roc-pfa", "0.2,0.5",
                         "--out", str(out), "--roc", str(roc)]) == 0
    assert roc.read_bytes()[:4] == b"\x89PNG"
    result = json.loads((out / "result.json").read_text())
    records = result["roc"]
    assert [(r["detector"], r["false_alarm_rate"]) for r in records] == [
        ("ca-cfar", 0.1), ("ca-cfar", 0.2), ("ca-cfar", 0.5),
        ("pf-tbd", 0.1), ("pf-tbd", 0.2), ("pf-tbd", 0.5)]
    for r in records:  # 5 noise-only scenes x 2 scored frames: at most floor(rate * 10) above
        assert r["noise_decisions"] == 10 and r["noise_false_alarms"] <= int(r["false_alarm_rate"] * 10)
        assert r["opportunities"] == 4
    for name in ("ca-cfar", "pf-tbd"):
        mine = [r for r in records if r["detector"] == name]
        assert [r["threshold"] for r in mine] == sorted((r["threshold"] for r in mine), reverse=True)
        assert [r["detections"] for r in mine] == sorted(r["detections"] for r in mine)
        row = next(r for r in result["rows"] if r["detector"] == name)
        assert (mine[0]["threshold"], mine[0]["detections"]) == (row["threshold"], row["detections"])
