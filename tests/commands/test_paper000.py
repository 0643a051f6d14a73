"""``dptbd paper000``: a tiny run prints the tables and writes the summary; outputs checked first."""

from __future__ import annotations

import json

from dptbd import cli

TINY = ["paper000", "--cases", "5.1 eq (15)", "--seeds", "2", "--gain", "", "--frames", "3",
        "--workers", "1"]


def test_a_tiny_run_prints_the_tables_and_writes_the_summary(tmp_path, capsys):
    out = tmp_path / "s.json"
    assert cli.main(TINY + ["--json", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "| 5.1 eq (15) | target |" in printed and "model engine, 1 worker(s)" in printed
    summary = json.loads(out.read_text())
    assert summary["engine"] == "model" and list(summary["cases"]) == ["5.1 eq (15)"]


def test_an_existing_output_is_refused_before_the_run(tmp_path, capsys):
    out = tmp_path / "s.json"
    out.write_text("keep")
    assert cli.main(TINY + ["--json", str(out)]) == 2
    assert capsys.readouterr().err == (f"dptbd paper000: error: --json {out} exists; pass "
                                       f"--force to overwrite it\n")
    assert out.read_text() == "keep"


def test_the_summary_is_strict_json_with_null_where_a_number_is_not_finite(tmp_path, capsys):
    """One scene: no paired interval (NaN); Pd never reaches 0.5 in the grid: the SNRs of
    the crossing are +inf, the loss NaN, its interval (-inf, +inf). All written as null."""
    def refuse(name):
        raise ValueError(f"{name} is not JSON")

    out = tmp_path / "s.json"
    assert cli.main(["paper000", "--cases", "5.1 eq (15)", "--seeds", "1", "--gain", "DP eq (15)",
                     "--snr", "0,1", "--trials", "2", "--noise-trials", "2", "--frames", "3",
                     "--workers", "1", "--json", str(out)]) == 0
    assert ("SNR at Pd 0.5: fixed inf dB, float inf dB, loss +nan dB [-inf, +inf]"
            in capsys.readouterr().out)
    summary = json.loads(out.read_text(), parse_constant=refuse)
    target = summary["cases"]["5.1 eq (15)"]["target"]
    assert (target["lo"], target["hi"]) == (None, None) and isinstance(target["delta"], float)
    assert summary["gain"]["DP eq (15)"]["losses"] == [
        dict(level=level, loss=None, lo=None, hi=None, snr_fixed=None, snr_float=None)
        for level in (0.5, 0.9)]
