"""``dptbd compare`` (:mod:`dptbd.commands.compare`): its arguments reach the job
(:func:`dptbd.evaluation.compare.compare_job`), its result is printed, refusals exit 2 with
the message, and the help quotes the real defaults."""

from __future__ import annotations

import argparse
import pathlib
import re

import pytest

from dptbd import cli
from dptbd.commands import compare as command
from dptbd.evaluation import compare as compare_package, sweep
from dptbd.evaluation.compare import SynthOptions, job


def _parse(argv):
    parser = argparse.ArgumentParser()
    command.add_arguments(parser)
    return parser.parse_args(argv)


class _Outcome:
    def text(self):
        return "the tables\nwrote somewhere"


@pytest.fixture
def job_calls(monkeypatch):
    """Record the calls of the job (which then does nothing) instead of running it."""
    calls = []

    def fake(config, out, **kw):
        calls.append((config, out, kw))
        return _Outcome()
    monkeypatch.setattr(compare_package, "compare_job", fake)
    return calls


def test_arguments_reach_the_job_and_its_text_is_printed(job_calls, capsys):
    args = _parse(["--config", "c.toml", "--out", "o", "--trials", "5", "--seed", "3", "--snr",
                   "1.5", "2.5", "--bootstrap", "9", "--workers", "2", "--force", "--no-progress",
                   "--rtl", "--tie-rule", "gateware-bins", "--scheduler", "tcp://h:8786",
                   "--dashboard"])
    assert command.main(args) == 0
    assert job_calls == [(pathlib.Path("c.toml"), pathlib.Path("o"), {
        "force": True, "trials": 5, "seed": 3, "snr": [1.5, 2.5], "bootstrap": 9,
        "tie_rule": "gateware-bins", "workers": 2, "progress": False, "rtl": True,
        "synth": None, "scheduler": "tcp://h:8786", "dashboard": True})]
    assert capsys.readouterr().out == "the tables\nwrote somewhere\n"


def test_defaults_reach_the_job(job_calls):
    assert command.main(_parse([])) == 0
    assert job_calls == [(None, pathlib.Path("compare-out"), {
        "force": False, "trials": None, "seed": None, "snr": None, "bootstrap": None,
        "tie_rule": None, "workers": None, "progress": True, "rtl": False, "synth": None,
        "scheduler": None, "dashboard": False})]


def test_synthesis_options_reach_the_job(job_calls, tmp_path):
    args = _parse(["--synth", "--synth-variant", "top", "--synth-seeds", "4", "5", "--device",
                   "up5k", "--package", "sg48", "--freq", "48", "--synth-size", "64",
                   "--synth-cache", str(tmp_path)])
    assert command.main(args) == 0
    assert job_calls[0][2]["synth"] == SynthOptions(
        variant="top", device="up5k", package="sg48", seeds=(4, 5), target_mhz=48.0, size=64,
        cache_dir=tmp_path)


@pytest.mark.parametrize("argv, message", [
    (["--trials", "0"], "trials must be an integer in [1, inf), got 0"),
    (["--snr"], "snr must hold at least 2 value(s), got [] (an empty list)"),
    (["--snr", "2.0", "2.0"], "snr must be strictly increasing, but snr[1] = 2 <= snr[0] = 2"),
    (["--bootstrap", "-1"], "bootstrap must be an integer in [0, 1000000], got -1"),
    (["--workers", "0"], "workers must be an integer in [1, 1024], got 0"),
    (["--workers", "1025"], "workers must be an integer in [1, 1024], got 1025"),
    (["--synth", "--synth-size", "2"], "--synth-size must be an integer in [3, 4096], got 2"),
    (["--synth", "--synth-seeds", "1", "1"], "--synth-seeds must be distinct, got [1, 1]"),
    (["--synth", "--device", "xc7"], "--device must be one of ('lp384', 'lp1k', 'lp4k', 'lp8k', "
     "'hx1k', 'hx4k', 'hx8k', 'up3k', 'up5k', 'u1k', 'u2k', 'u4k'), got 'xc7'"),
])
def test_cli_exits_2_with_the_message(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.setattr(job, "run_compare", lambda *a, **k: pytest.fail("work started"))
    out = tmp_path / "out"
    assert cli.main(["compare", "--out", str(out)] + argv) == 2
    assert capsys.readouterr().err == f"dptbd compare: error: {message}\n"
    assert not out.exists()


@pytest.mark.parametrize("text, message", [
    ("[[config]]\nenergy_bitz = 9\n",
     "config[0]: unknown configuration key(s) ['energy_bitz']; allowed: ['adc_gain', "
     "'adc_offset', 'energy_bits', 'histogram_bits', 'histogram_shift', 'input_bits', 'lut', "
     "'name', 'rounding', 'weight_frac_bits', 'weights']"),
    ("[sweep]\ninput_bits = [0]\n", "sweep.input_bits must be an integer in [1, 16], got 0"),
    ("[[config]]\ninput_bits = 8\nweight_frac_bits = -1\n",
     "config[0]: weight_frac_bits must be an integer in [0, 16], got -1"),
])
def test_cli_exits_2_on_a_bad_file(tmp_path, monkeypatch, capsys, text, message):
    monkeypatch.setattr(job, "run_compare", lambda *a, **k: pytest.fail("work started"))
    path = tmp_path / "c.toml"
    path.write_text(text)
    assert cli.main(["compare", "--config", str(path), "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == f"dptbd compare: error: {message}\n"
    assert not (tmp_path / "o").exists(), "an output folder was created before the error"


def test_cli_exits_2_when_a_tool_is_missing(tmp_path, monkeypatch, capsys):
    from dptbd.hw.flow.synth import ToolNotFoundError

    def missing():
        raise ToolNotFoundError("yosys not found")
    monkeypatch.setattr(sweep, "check_tools", missing)
    monkeypatch.setattr(job, "run_compare", lambda *a, **k: pytest.fail("work started"))
    assert cli.main(["compare", "--synth", "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == "dptbd compare: error: yosys not found\n"


def test_cli_runs_the_job_and_prints_what_it_wrote(tmp_path, capsys):
    path = tmp_path / "c.toml"
    path.write_text('trials = 1\nsize = 16\nframes = 4\nsegment_frames = 4\nsnr = [1.5, 2.5]\n'
                    'false_alarm_rate = 0.02\nbootstrap = 0\n[sweep]\n[[config]]\nname = "four"\n'
                    'input_bits = 4\n')
    out = tmp_path / "o"
    assert cli.main(["compare", "--config", str(path), "--out", str(out), "--workers", "1",
                     "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("| configuration | B_in/B_E/F |")
    assert re.search(r"^1 trials x 1 segments x 2 SNRs \(\+ noise only\), 1 configurations "
                     r"\(1 distinct\), seed 2024: ", printed, re.M)
    assert printed.endswith(f"wrote {out / 'compare_pd.csv'}, {out / 'compare_pfa.csv'}, "
                            f"{out / 'compare_equal_pfa.csv'}, "
                            f"{out / 'compare_configs.csv'}, {out / 'compare_summary.json'}, "
                            f"{out / 'compare_pd.png'}, {out / 'compare_pfa.png'}, "
                            f"{out / 'compare_loss.png'}\n")


def test_cli_tie_rules_are_the_specs(capsys):
    parser = argparse.ArgumentParser(prog="dptbd compare")
    command.add_arguments(parser)
    rule = next(a for a in parser._actions if a.dest == "tie_rule")
    assert command.TIE_RULES == rule.choices == compare_package.TIE_RULES
    assert "default random," in rule.help
    with pytest.raises(SystemExit) as exc:
        parser.parse_args(["--tie-rule", "raster"])
    assert exc.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1] == (
        "dptbd compare: error: argument --tie-rule: invalid choice: 'raster' (choose from "
        "'random', 'gateware', 'gateware-bins')")


def test_cli_help_quotes_the_real_defaults():
    parser = argparse.ArgumentParser()
    command.add_arguments(parser)
    helps = {a.dest: a.help for a in parser._actions}
    run = compare_package.DEFAULT_RUN
    assert f"default {run['trials']}," in helps["trials"]
    assert f"default {run['seed']}," in helps["seed"]
    assert f"default {run['bootstrap']}," in helps["bootstrap"]
    assert "default " + " ".join(f"{x:g}" for x in run["snr"]) + "," in helps["snr"]
    defaults = SynthOptions()
    args = parser.parse_args([])
    assert (args.synth_variant, args.device, args.package, tuple(args.synth_seeds), args.freq,
            args.synth_size) == (defaults.variant, defaults.device, defaults.package,
                                 defaults.seeds, defaults.target_mhz, defaults.size)
