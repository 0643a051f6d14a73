"""``dptbd verify`` through the real CLI: the case list, its refusals, one case run and its JSON
(the campaign itself is tested in ``tests/sim/test_campaign.py``)."""

from __future__ import annotations

import json

from dptbd.cli import main


def test_verify_command_lists_and_refuses(capsys, tmp_path):
    assert main(["verify", "--list"]) == 0
    listed = capsys.readouterr().out
    assert "001-128x128-k8-in12-e16" in listed
    assert "axi-12x10-k2-faults          axi       8 runs  (--coverage only)\n" in listed
    assert main(["verify", "--cases", "nope"]) == 2
    assert capsys.readouterr().err == ("dptbd verify: error: unknown case(s) nope; dptbd verify "
                                       "--list names them\n")
    assert main(["verify", "--runs-scale", "0"]) == 2
    assert capsys.readouterr().err == ("dptbd verify: error: --runs-scale must be a finite real "
                                       "number in (0, inf), got 0.0\n")
    assert main(["verify", "--workers", "0"]) == 2
    assert capsys.readouterr().err == "dptbd verify: error: --workers must be an integer in [1, inf), got 0\n"
    existing = tmp_path / "out.json"
    existing.write_text("{}")
    assert main(["verify", "--json", str(existing)]) == 2
    assert capsys.readouterr().err == (f"dptbd verify: error: --json {existing} exists; "
                                       f"pass --force to overwrite it\n")
    assert existing.read_text() == "{}"
    assert main(["verify", "--json", str(tmp_path / "out.txt")]) == 2
    assert capsys.readouterr().err == (f"dptbd verify: error: --json {tmp_path / 'out.txt'} "
                                       f"must end in .json\n")


def test_verify_command_runs_one_case(capsys, tmp_path):
    out = tmp_path / "v.json"
    assert main(["verify", "--cases", "37x23-k3-in8-e12-f4", "--runs-scale", "0.05",
                 "--no-x-store", "--workers", "1", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "37x23-k3-in8-e12-f4" in text and "bit-exact" in text and "total:" in text
    data = json.loads(out.read_text())
    assert data["passed"] and data["words_compared"] > 0 and len(data["runs"]) == 1


def test_verify_coverage_refuses_an_existing_folder_and_unknown_cases(capsys, tmp_path):
    existing = tmp_path / "cov"
    existing.mkdir()
    assert main(["verify", "--cases", "segmenter-33x17-k2-n3", "--coverage", str(existing)]) == 2
    assert capsys.readouterr().err == (f"dptbd verify: error: --coverage {existing} exists; pass "
                                       f"--force to replace it, or choose another folder\n")
    (existing / "mine.txt").write_text("keep")
    assert main(["verify", "--cases", "segmenter-33x17-k2-n3", "--coverage", str(existing),
                 "--force"]) == 2
    assert capsys.readouterr().err == (
        f"dptbd verify: error: --coverage {existing} is not the folder of an earlier dptbd "
        f"verify --coverage run (no coverage.json from it); --force will not replace it\n")
    assert (existing / "mine.txt").read_text() == "keep"
    # the coverage run sets are cases of --coverage only
    assert main(["verify", "--cases", "axi-12x10-k2-faults"]) == 2
    assert capsys.readouterr().err == ("dptbd verify: error: unknown case(s) axi-12x10-k2-faults; "
                                       "dptbd verify --list names them\n")
