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
