"""The ``dptbd compare`` job (:mod:`dptbd.evaluation.compare.job`): every refusal before any
work, the files written, the output folder staged and replaced only when it is an earlier
compare run's, synthesis at its own frame size."""

from __future__ import annotations

import csv
import json
import re

import pytest

from dptbd.errors import ConfigError
from dptbd.evaluation import sweep
from dptbd.evaluation.compare import DATA_FILES, FIGURES, job
from dptbd.evaluation.compare.job import SynthOptions, compare_job, load_config, synthesise_all
from dptbd.evaluation.compare.spec import build_spec
from dptbd.evaluation.execution import ExecutionError
from helpers.refusals import whole


@pytest.fixture
def no_work(monkeypatch):
    """Fail the test if the Monte Carlo starts."""
    def boom(*a, **k):
        raise AssertionError("work started")
    monkeypatch.setattr(job, "run_compare", boom)


@pytest.mark.parametrize("text, kw, message", [
    ("frobnicate = 1\n", {}, "unknown parameter(s) ['frobnicate']; allowed: ['adc_low_sigma', "
     "'adc_span_sigma', 'bootstrap', 'chunk', 'false_alarm_rate', 'frames', 'mu', 'pd_levels', 'pfa', "
     "'radius', 'seed', 'segment_frames', 'segment_stride', 'sigma', 'size', 'snr', "
     "'thresholds', 'tie_rule', 'tolerance_db', 'trials', 'velocity', 'config', 'sweep']"),
    ("[[config]]\ninput_bits = 17\n", {}, "config[0]: input_bits must be an integer in [1, 16], got 17"),
    ("", {"snr": []}, "snr must hold at least 2 value(s), got [] (an empty list)"),
    ("", {"snr": [2.0, 1.5]}, "snr must be strictly increasing, but snr[1] = 1.5 <= snr[0] = 2"),
    ("", {"trials": 0}, "trials must be an integer in [1, inf), got 0"),
    ("tie_rule = 'raster'\n", {}, "tie_rule must be one of ('random', 'gateware', "
     "'gateware-bins'), got 'raster'"),
    ("", {"tie_rule": "ties"}, "tie_rule must be one of ('random', 'gateware', "
     "'gateware-bins'), got 'ties'"),
    ("", {"bootstrap": -1}, "bootstrap must be an integer in [0, 1000000], got -1"),
    ("", {"synth": SynthOptions(device="xc7")},
     "--device must be one of ('lp384', 'lp1k', 'lp4k', 'lp8k', 'hx1k', 'hx4k', 'hx8k', "
     "'up3k', 'up5k', 'u1k', 'u2k', 'u4k'), got 'xc7'"),
    ("", {"synth": SynthOptions(seeds=(1, 1))}, "--synth-seeds must be distinct, got [1, 1]"),
    ("", {"synth": SynthOptions(size=2)}, "--synth-size must be an integer in [3, 4096], got 2"),
])
def test_bad_parameters_are_refused_before_any_work(tmp_path, no_work, text, kw, message):
    config = tmp_path / "c.toml"
    config.write_text(text)
    out = tmp_path / "out"
    with pytest.raises(ConfigError, match=whole(message)):
        compare_job(config, out, **kw)
    assert not out.exists()


@pytest.mark.parametrize("workers", [0, 1025, 2.0])
def test_a_bad_worker_count_is_refused_before_any_work(tmp_path, no_work, workers):
    out = tmp_path / "out"
    with pytest.raises(ExecutionError, match=whole(
            f"workers must be an integer in [1, 1024], got {workers!r}")):
        compare_job(None, out, workers=workers)
    assert not out.exists()


def test_missing_or_broken_config_file_is_refused(tmp_path, no_work):
    missing = tmp_path / "nope.toml"
    with pytest.raises(FileNotFoundError, match=whole(f"--config {missing}: no such file")):
        compare_job(missing, tmp_path / "out")
    broken = tmp_path / "broken.toml"
    broken.write_text("trials 3\n")
    with pytest.raises(ConfigError, match=whole(
            f"--config {broken}: not valid TOML: Expected '=' after a key in a key/value pair "
            f"(at line 1, column 8)")):
        load_config(broken)
    assert load_config(None) == {}


def test_output_folder_is_refused_before_any_work(tmp_path, no_work):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep")
    with pytest.raises(FileExistsError, match=whole(
            f"--out {mine} exists; pass --force to replace it, or choose another folder")):
        compare_job(None, mine)
    with pytest.raises(FileExistsError, match=whole(
            f"--out {mine} is not the folder of an earlier dptbd compare run (no "
            f"compare_summary.json from it); --force will not replace it")):
        compare_job(None, mine, force=True)
    a_file = tmp_path / "file"
    a_file.write_text("")
    with pytest.raises(FileExistsError, match=whole(
            f"--out {a_file} exists and is not a folder; --force replaces only the folder of "
            f"an earlier dptbd compare run")):
        compare_job(None, a_file, force=True)
    nested = tmp_path / "no" / "out"
    with pytest.raises(FileNotFoundError, match=whole(
            f"--out {nested}: the folder {nested.parent} does not exist")):
        compare_job(None, nested)
    assert (mine / "notes.txt").read_text() == "keep"


def test_missing_synthesis_tool_is_refused_before_any_work(tmp_path, monkeypatch, no_work):
    from dptbd.hw.flow.synth import ToolNotFoundError

    def missing():
        raise ToolNotFoundError("yosys not found on PATH (Debian package 'yosys')")
    monkeypatch.setattr(sweep, "check_tools", missing)
    with pytest.raises(ToolNotFoundError, match=whole(
            "yosys not found on PATH (Debian package 'yosys')")):
        compare_job(None, tmp_path / "out", synth=SynthOptions())
    assert not (tmp_path / "out").exists()


def test_job_writes_tables_json_and_figures(tmp_path, small_sweep_toml):
    out = tmp_path / "out"
    outcome = compare_job(small_sweep_toml, out, workers=1, progress=False)
    assert outcome.paths == [out / name for name in DATA_FILES + FIGURES]
    assert sorted(p.name for p in out.iterdir()) == sorted(DATA_FILES + FIGURES)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "small.toml"]  # nothing staged
    for name in FIGURES:
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
    summary = json.loads((out / "compare_summary.json").read_text())
    assert summary["tool"] == "dptbd compare" and list(summary)[0] == "tool"
    assert summary["run"]["trials"] == 4 and len(summary["configs"]) == 3
    assert summary["run"]["candidate_count"] == 5 and summary["run"]["segments_per_trial"] == 3
    assert summary["run"]["synth"] is None and summary["run"]["total_seconds"] > 0
    assert {r["verdict"] for r in summary["configs"]} <= {"within", "beyond", "undecided"}
    text = outcome.text()
    assert "loss @Pd=0.5" in text and "loss @Pd=0.8" in text
    assert text.splitlines()[-1] == "wrote " + ", ".join(str(out / n) for n in DATA_FILES + FIGURES)
    assert re.search(r"^4 trials x 3 segments x 3 SNRs \(\+ noise only\), 3 configurations "
                     r"\(3 distinct\), seed 3: Monte Carlo [0-9.]+ s on 1 worker\(s\) "
                     r"\([0-9.]+ trials/s\), total [0-9.]+ s$", text, re.M)

    def rows(name):
        with (out / name).open() as fh:
            return list(csv.DictReader(fh))
    detectors = summary["detectors"]
    assert detectors[0] == "float paper" and len(detectors) == 4   # float + 3 fixed behaviours
    pd = rows("compare_pd.csv")
    assert len(pd) == len(detectors) * 3
    for r in pd:
        p, lo, hi = float(r["pd"]), float(r["pd_lo"]), float(r["pd_hi"])
        assert 0 <= lo <= p <= hi <= 1
        assert float(r["pd"]) == int(r["detections"]) / int(r["opportunities"])
        assert int(r["opportunities"]) == 4 * 3       # trials x segments (target always visible)
        assert float(r["candidates_per_frame"]) == 5.0  # exactly n for every detector and SNR
        assert 0 <= float(r["false_points_per_frame"]) <= 5.0
        if r["detector"] == "float paper":
            assert float(r["delta_pd"]) == 0.0
    pfa = rows("compare_pfa.csv")
    assert len(pfa) == len(detectors) * 3
    for d in detectors:
        curve = [float(r["pfa"]) for r in pfa if r["detector"] == d]
        assert len(curve) == 3 and curve == sorted(curve, reverse=True)   # a threshold sweep
    configs = rows("compare_configs.csv")
    # K = 4 here: the worst-case B_E is B_in + 2; F defaults to 8
    assert [r["name"] for r in configs] == ["exact-ish", "4/6/8 truncate paper",
                                            "6/8/8 truncate paper"]
    assert [r["widths"] for r in configs] == ["10/12/8", "4/6/8", "6/8/8"]
    assert [int(r["state_bits_per_pixel"]) for r in configs] == [12 + 4, 6 + 4, 8 + 4]
    assert all(float(r["noise_candidates_per_frame"]) == 5.0 for r in configs)
    for r, j in zip(configs, summary["configs"]):
        assert r["verdict"] == j["verdict"] and r["name"] in text
        assert r["verdict"] in text.split(r["name"] + " |", 1)[1].split("\n", 1)[0]
        for tag in ("pd50", "pd80"):
            lo, v, hi = (j[f"loss_{tag}_{k}"] for k in ("lo", "db", "hi"))
            if all(isinstance(x, (int, float)) for x in (lo, v, hi)):
                assert lo <= v <= hi
    choice = summary["choice"]
    by_name = {r["name"]: r for r in summary["configs"]}
    for key, ok in (("within", {"within"}), ("not_beyond", {"within", "undecided"})):
        if choice[key] is not None:
            assert by_name[choice[key]]["in_sweep"] and by_name[choice[key]]["verdict"] in ok
        else:
            assert not any(r["in_sweep"] and r["verdict"] in ok for r in summary["configs"])


def test_a_tie_rule_is_recorded_and_printed_unless_it_is_the_default(tmp_path):
    tiny = {"trials": 2, "size": 16, "frames": 4, "segment_frames": 4, "false_alarm_rate": 0.02,
            "bootstrap": 0, "snr": [1.5, 2.5], "sweep": {},
            "config": [{"name": "three", "input_bits": 3}]}
    line = (r"^2 trials x 1 segments x 2 SNRs \(\+ noise only\), 1 configurations "
            r"\(1 distinct\), seed 2024{}: Monte Carlo ")
    default = compare_job(tiny, tmp_path / "random", workers=1, progress=False)
    assert "tie_rule" not in default.summary["run"]
    assert "tie_rule" not in json.loads((tmp_path / "random" / "compare_summary.json").read_text())["run"]
    assert re.search(line.format(""), default.text(), re.M)
    for rule in ("gateware", "gateware-bins"):
        outcome = compare_job(dict(tiny, tie_rule="random"), tmp_path / rule, tie_rule=rule,
                              workers=1, progress=False)
        written = json.loads((tmp_path / rule / "compare_summary.json").read_text())
        assert outcome.summary["run"]["tie_rule"] == written["run"]["tie_rule"] == rule
        assert re.search(line.format(", tie rule " + rule), outcome.text(), re.M)
        # the histogram each configuration's candidates were selected on, under gateware-bins
        assert ("bin_shift" in written["configs"][0]) == (rule == "gateware-bins")
    # 3 bits ties: the gateware rule keeps fewer candidates than exactly n
    assert outcome.summary["configs"][0]["noise_candidates_per_frame"] < 5.0
    assert default.summary["configs"][0]["noise_candidates_per_frame"] == 5.0


def test_force_replaces_only_an_earlier_compare_run(tmp_path):
    tiny = {"trials": 1, "size": 16, "frames": 4, "segment_frames": 4, "false_alarm_rate": 0.02,
            "bootstrap": 0, "snr": [1.5, 2.5], "sweep": {}, "config": [{"input_bits": 4}]}
    out = tmp_path / "out"
    compare_job(tiny, out, workers=1, progress=False)
    (out / "stale.txt").write_text("from before")
    with pytest.raises(FileExistsError, match=whole(
            f"--out {out} exists; pass --force to replace it, or choose another folder")):
        compare_job(tiny, out, workers=1, progress=False)
    compare_job(dict(tiny, seed=5), out, force=True, workers=1, progress=False)
    assert not (out / "stale.txt").exists()                    # replaced as a whole
    assert json.loads((out / "compare_summary.json").read_text())["run"]["seed"] == 5
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_failure_while_writing_leaves_nothing(tmp_path, monkeypatch):
    def broken(summary, folder, **kw):
        (folder / "compare_pd.csv").write_text("half")
        raise OSError("disk full")
    monkeypatch.setattr(job, "write_outputs", broken)
    tiny = {"trials": 1, "size": 16, "frames": 4, "segment_frames": 4, "false_alarm_rate": 0.02,
            "bootstrap": 0, "snr": [1.5, 2.5], "sweep": {}, "config": [{"input_bits": 4}]}
    with pytest.raises(OSError, match=r"^disk full$"):
        compare_job(tiny, tmp_path / "out", workers=1, progress=False)
    assert list(tmp_path.iterdir()) == []


def test_synthesis_runs_at_synth_size_and_records_failures(monkeypatch, capsys, small_compare):
    from dptbd.hw.flow.synth import SynthToolError
    spec = build_spec(dict(small_compare, config=small_compare["config"][:2]))
    seen = []

    def fake(cfg, **kw):
        seen.append((cfg, kw))
        if cfg.input_bits == 4:
            raise SynthToolError("nextpnr died")
        return sweep.HardwareCost(lut4=10, ff=5, bram=1, carry=2, fmax_median_mhz=100.0,
                                  fmax_mhz=(100.0,), fits=True, logic_cells=12, device="hx8k",
                                  package="ct256", variant="core", width=cfg.width,
                                  height=cfg.height, seconds=1.0)

    monkeypatch.setattr(sweep, "hardware_cost", fake)
    hw = synthesise_all(spec, SynthOptions(size=128, seeds=(1, 2)), workers=4, progress=False)
    assert [(c.width, c.height) for c, _ in seen] == [(128, 128)] * 2
    assert [c.input_bits for c, _ in seen] == [8, 4]
    assert seen[0][1] == {"variant": "core", "device": "hx8k", "package": "ct256",
                          "seeds": (1, 2), "target_mhz": 100.0, "cache_dir": None, "jobs": 2}
    assert hw["eight"].lut4 == 10 and hw["four"].lut4 is None and "nextpnr died" in hw["four"].error
    assert capsys.readouterr().err == "dptbd compare: synthesis of 'four' failed: nextpnr died\n"
    assert spec.configs[0].cfg.width == 16  # the Monte Carlo's configuration is unchanged


def test_synth_options_recorded_in_the_summary():
    assert SynthOptions(seeds=(3, 4), size=64).to_dict() == {
        "variant": "core", "device": "hx8k", "package": "ct256", "seeds": [3, 4],
        "target_mhz": 100.0, "size": 64}
