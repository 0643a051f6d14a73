"""``dptbd compare``: bad input refused before any work, exit status 2 naming the parameter,
the files written, synthesis at ``--synth-size``."""

from __future__ import annotations

import argparse
import json

import pytest

from dptbd.config import ConfigError
from dptbd.evaluation import compare as cmp
from dptbd.evaluation import sweep
from dptbd.evaluation.compare import build_spec


SMALL = {
    "trials": 6, "seed": 7, "snr": [1.5, 2.5, 3.5], "size": 16, "frames": 12,
    "velocity": [1.0, 0.0], "segment_frames": 4, "false_alarm_rate": 0.02, "chunk": 2,
    "bootstrap": 50, "thresholds": [2.0, 3.0, 4.0],
    "config": [{"name": "eight", "input_bits": 8},
               {"name": "four", "input_bits": 4, "energy_bits": 5},
               {"name": "cos", "input_bits": 8, "lut": "cosine", "weight_frac_bits": 2}],
    "sweep": {},
}


def _parse(argv):
    from dptbd.commands import compare as command
    parser = argparse.ArgumentParser()
    command.add_arguments(parser)
    return command, parser.parse_args(argv)


def _toml(path, text):
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("toml, argv, match", [
    ("frobnicate = 1\n", [], r"unknown parameter\(s\) \['frobnicate'\]"),
    ("[[config]]\ninput_bits = 8\nwidht = 3\n", [], r"unknown configuration key\(s\) \['widht'\]"),
    ("[[config]]\nsegment_frames = 8\n", [], "run-level parameters"),
    ("[[config]]\ninput_bits = 17\n", [], r"input_bits must be in \[1, 16\]"),
    ("[[config]]\ninput_bits = 8\nenergy_bits = 6\n", [], r"energy_bits must be in \[input_bits=8"),
    ("[[config]]\nrounding = 'nearest'\n", [], "rounding must be one of"),
    ("[sweep]\ninput_bits = [8]\nenergy_headroom = [-6]\n", [], r"energy_bits must be in \[input_bits=8"),
    ("", ["--snr"], r"snr must hold at least 2 value\(s\), got \[\] \(an empty list\)"),
    ("", ["--snr", "2.0", "1.5"], r"snr must be strictly increasing, but snr\[1\] = 1.5 <= snr\[0\] = 2"),
    ("snr = []\n", [], "an empty list"),
    ("", ["--trials", "0"], r"trials must be in \[1, inf\], got 0"),
    ("", ["--workers", "0"], "--workers must be >= 1"),
])
def test_bad_input_is_refused_before_any_work(tmp_path, monkeypatch, toml, argv, match):
    def boom(*a, **k):
        raise AssertionError("work started")
    monkeypatch.setattr(cmp, "run_compare", boom)
    monkeypatch.setattr(cmp, "make_plan", boom)
    out = tmp_path / "out"
    command, args = _parse(["--config", _toml(tmp_path / "c.toml", toml), "--out", str(out)] + argv)
    with pytest.raises(ConfigError, match=match):
        command.main(args)
    assert not out.exists()


def test_missing_file_and_existing_output_are_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(cmp, "run_compare", lambda *a, **k: pytest.fail("work started"))
    command, args = _parse(["--config", str(tmp_path / "nope.toml")])
    with pytest.raises(FileNotFoundError, match="no such file"):
        command.main(args)
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "mine.txt").write_text("keep")
    command, args = _parse(["--out", str(tmp_path / "out")])
    with pytest.raises(FileExistsError, match="--force"):
        command.main(args)


def test_command_writes_tables_json_and_figures(tmp_path, capsys):
    toml = """
trials = 4
seed = 3
snr = [1.5, 2.5, 3.5]
size = 16
frames = 12
segment_frames = 4
false_alarm_rate = 0.02
chunk = 2
bootstrap = 40
thresholds = [2.0, 3.0, 4.0]
[[config]]
name = "exact-ish"
input_bits = 10
[sweep]
input_bits = [4, 6]
"""
    out = tmp_path / "out"
    command, args = _parse(["--config", _toml(tmp_path / "c.toml", toml), "--out", str(out),
                            "--workers", "1", "--no-progress"])
    assert command.main(args) == 0
    from dptbd.evaluation.compare import DATA_FILES, FIGURES
    for name in DATA_FILES + FIGURES:
        assert (out / name).stat().st_size > 0, name
    summary = json.loads((out / "compare_summary.json").read_text())
    assert summary["run"]["trials"] == 4 and len(summary["configs"]) == 3
    assert summary["run"]["candidate_count"] == 5 and summary["run"]["segments_per_trial"] == 3
    assert {r["verdict"] for r in summary["configs"]} <= {"within", "beyond", "undecided"}
    for name in FIGURES:
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
    printed = capsys.readouterr().out
    assert "loss @Pd=0.5" in printed and "loss @Pd=0.8" in printed

    import csv
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
    assert all(float(r["noise_candidates_per_frame"]) == 5.0 for r in configs)
    for r, j in zip(configs, summary["configs"]):
        assert r["verdict"] == j["verdict"] and r["name"] in printed
        assert r["verdict"] in printed.split(r["name"] + " |", 1)[1].split("\n", 1)[0]
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
    # the same folder again needs --force
    with pytest.raises(FileExistsError):
        command.main(_parse(["--config", str(tmp_path / "c.toml"), "--out", str(out)])[1])


@pytest.mark.parametrize("argv, names", [
    (["--trials", "0"], ["trials", "[1, inf]"]),
    (["--snr"], ["snr", "at least 2"]),
    (["--snr", "2.0", "2.0"], ["snr", "strictly increasing"]),
    (["--bootstrap", "-1"], ["bootstrap", "[0, 1000000]"]),
    (["--workers", "0"], ["--workers", ">= 1"]),
    (["--synth", "--synth-size", "2"], ["--synth-size", "[3, 4096]"]),
    (["--synth", "--synth-seeds", "1", "1"], ["--synth-seeds", "distinct"]),
    (["--synth", "--device", "xc7"], ["--device", "hx8k"]),
])
def test_cli_exits_2_naming_the_parameter(tmp_path, monkeypatch, capsys, argv, names):
    from dptbd import cli
    monkeypatch.setattr(cmp, "run_compare", lambda *a, **k: pytest.fail("work started"))
    out = tmp_path / "out"
    assert cli.main(["compare", "--out", str(out)] + argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("dptbd compare: error:")
    for name in names:
        assert name in err
    assert not out.exists()


def test_cli_exits_2_on_unknown_keys_and_impossible_widths(tmp_path, monkeypatch, capsys):
    from dptbd import cli
    monkeypatch.setattr(cmp, "run_compare", lambda *a, **k: pytest.fail("work started"))
    for text, names in [("[[config]]\nenergy_bitz = 9\n", ["energy_bitz", "allowed"]),
                        ("[sweep]\ninput_bits = [0]\n", ["input_bits", "[1, 16]"]),
                        ("[[config]]\ninput_bits = 8\nweight_frac_bits = -1\n",
                         ["weight_frac_bits"])]:
        path = _toml(tmp_path / "c.toml", text)
        assert cli.main(["compare", "--config", path, "--out", str(tmp_path / "o")]) == 2
        err = capsys.readouterr().err
        for name in names:
            assert name in err, (text, err)
        assert not (tmp_path / "o").exists(), "an output folder was created before the error"


def test_cli_help_quotes_the_real_defaults():
    command, _ = _parse([])
    parser = argparse.ArgumentParser()
    command.add_arguments(parser)
    helps = {a.dest: a.help for a in parser._actions}
    run = cmp.DEFAULT_RUN
    assert f"default {run['trials']}," in helps["trials"]
    assert f"default {run['seed']}," in helps["seed"]
    assert f"default {run['bootstrap']}," in helps["bootstrap"]
    assert "default " + " ".join(f"{x:g}" for x in run["snr"]) + "," in helps["snr"]


def test_synthesis_runs_at_synth_size_and_records_failures(monkeypatch):
    from dptbd.commands import compare as command
    from dptbd.hw.flow.synth import SynthToolError
    spec = build_spec(dict(SMALL, config=SMALL["config"][:2]))
    seen = []

    def fake(cfg, **kw):
        seen.append(cfg)
        if cfg.input_bits == 4:
            raise SynthToolError("nextpnr died")
        return sweep.HardwareCost(lut4=10, ff=5, bram=1, carry=2, fmax_median_mhz=100.0,
                                  fmax_mhz=(100.0,), fits=True, logic_cells=12, device="hx8k",
                                  package="ct256", variant="core", width=cfg.width,
                                  height=cfg.height, seconds=1.0)

    monkeypatch.setattr(sweep, "hardware_cost", fake)
    _, args = _parse(["--synth", "--synth-size", "128", "--no-progress"])
    hw = command.synthesise_all(spec, args, workers=1)
    assert [(c.width, c.height) for c in seen] == [(128, 128)] * 2
    assert [c.input_bits for c in seen] == [8, 4]
    assert hw["eight"].lut4 == 10 and hw["four"].lut4 is None and "nextpnr died" in hw["four"].error
    assert spec.configs[0].cfg.width == 16  # the Monte Carlo's configuration is unchanged
