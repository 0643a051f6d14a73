"""Equivalence from reset under a proven invariant (``dptbd.sim.mutation.invariant``): the
checker and its assertion in the original's netlist, the invariants' file and its refusals;
with Yosys: an invariant that does not hold is refused with its counterexample, and (slow)
a mutant the slice kills is refused under a true invariant. The entries proven under an
invariant are proven again with the registry's (``test_equivalents.py``, slow)."""

from __future__ import annotations

import pytest
from helpers.refusals import whole
from helpers.yosys_marks import needs_yosys

from dptbd.sim.mutation import invariant as I
from dptbd.sim.mutation.equivalents import load_registry, mutation_key

PREPARED = """module \\other
  wire width 3 \\a
end
module \\dptbd_dp
  wire width 7 \\core.addr
  wire input 2 \\clk
  wire \\core.flag
  connect \\core.flag \\clk
end
"""
ADDR = I.Invariant("the address below 120", (("a", "core.addr"), ("f", "core.flag")),
                   "a <= 7'd119 || f")


def test_the_checker_reads_each_signal_at_its_width():
    assert I.signal_widths(PREPARED, "dp", ADDR) == {"a": 7, "f": 1}
    assert I.checker_verilog(ADDR, {"a": 7, "f": 1}) == (
        "module dptbd_invariant(input [6:0] a, input [0:0] f, output holds);\n"
        "  assign holds = a <= 7'd119 || f;\nendmodule\n")


def test_with_checker_asserts_the_checker_in_the_top_only():
    text = I.with_checker(PREPARED, "dp", ADDR)
    assert text.startswith(PREPARED.split("  connect \\core.flag")[0])
    assert text.endswith("""  connect \\core.flag \\clk
  wire \\dptbd_invariant_holds
  cell \\dptbd_invariant \\dptbd_invariant
    connect \\a \\core.addr
    connect \\f \\core.flag
    connect \\holds \\dptbd_invariant_holds
  end
  cell $assert \\dptbd_invariant_assert
    connect \\A \\dptbd_invariant_holds
    connect \\EN 1'1
  end
end
""")


def test_a_signal_the_top_does_not_have_is_refused():
    missing = I.Invariant("x", (("a", "a"),), "a")      # \\a is a wire of another module
    with pytest.raises(I.InvariantError, match=whole(
            "invariant 'x': dptbd_dp has no wire 'a' (signal 'a'); name a wire of the "
            "prepared, flattened netlist")):
        I.with_checker(PREPARED, "dp", missing)


GOOD = """
[[invariant]]
design = "dp"
mutation = 'mutate -mode inv -module dptbd_dp -cell $1 -port Y -portbit 0 -src /x/hw/a.py:3'
name = "the address below 120"
signals = { a = "core.addr", f = "core.flag" }
holds = "a <= 7'd119 || f"
"""


def test_parse_reads_an_invariant_keyed_by_its_mutation():
    key = ("dp", mutation_key("mutate -mode inv -module dptbd_dp -cell $1 -port Y -portbit 0 "
                              "-src hw/a.py:9"))
    assert I.parse_invariants(GOOD) == {key: ADDR}


@pytest.mark.parametrize("text, message", [
    ("x = ", "invariants: not TOML: Invalid value (at end of document)"),
    ("[other]\n", "invariants: the file holds [[invariant]] tables only"),
    (GOOD.replace('name = "the address below 120"\n', ""),
     "invariants: invariant 1: keys design, holds, mutation, signals; every invariant has "
     "exactly design, mutation, name, signals, holds"),
    (GOOD.replace('holds = "a <= 7\'d119 || f"', 'holds = " "'),
     "invariants: invariant 1: design, mutation, name and holds are non-empty strings, "
     "signals a non-empty table of wire names"),
    (GOOD.replace('{ a = "core.addr", f = "core.flag" }', "{}"),
     "invariants: invariant 1: design, mutation, name and holds are non-empty strings, "
     "signals a non-empty table of wire names"),
    (GOOD.replace('design = "dp"', 'design = "dp8"'),
     "invariants: invariant 1: design must be one of segmenter, axi, dp, dp2, dp4, got "
     "'dp8'"),
    (GOOD + GOOD, "invariants: invariant 2: a second invariant for the same mutation"),
])
def test_parse_refuses(text, message):
    with pytest.raises(ValueError, match=whole(message)):
        I.parse_invariants(text)


def test_the_checked_in_invariants_belong_to_proven_entries():
    invariants = I.load_invariants()
    for design, key in invariants:
        entry = load_registry(design)[key]
        assert entry.shown == "proven" and "prove_under_invariant" in entry.why
    assert invariants, "no invariant checked in"


#: ``dptbd_dp``'s output valid register inverted (#99 of ``--seed 1``, killed by the slice):
#: valid from reset on.
VALID_INVERTED = ("mutate -mode inv -module dptbd_dp -cell $flatten\\core.\\output_fifo.$57 "
                  "-port Q -portbit 0 -wire states__valid -wirebit 0 "
                  "-src amaranth/lib/stream.py:49")
#: ``dptbd_dp``'s controller never valid: false from the first accepted pixel on.
NEVER_VALID = I.Invariant("the controller never valid", (("v", "core.controller.valid"),),
                          "!v")
#: The line buffer's pointer below its depth W = 12: true (it counts modulo W).
POINTER = I.Invariant("the line buffer's pointer below W",
                      (("p", "core.line_buffer.pointer"),), "p <= 4'd11")


@needs_yosys
def test_an_invariant_that_does_not_hold_is_refused():
    from dptbd.sim.mutation.run import config

    with pytest.raises(I.InvariantError, match=whole(
            "invariant 'the controller never valid' of dp refused: fails (PDR: the "
            "invariant fails in cycle 2 after reset); a mutant is proven only under an "
            "invariant proven from reset")):
        I.prove_under_invariant(config("dp"), "dp", "mutate -mode inv", NEVER_VALID,
                                pdr_seconds=30)


@needs_yosys
@pytest.mark.slow
def test_a_mutant_the_slice_kills_is_not_equivalent_under_a_true_invariant():
    from dptbd.sim.mutation.run import config

    proof = I.prove_under_invariant(config("dp"), "dp", VALID_INVERTED, POINTER,
                                    pdr_seconds=60)
    assert (proof.verdict, proof.detail) == (
        "not equivalent", "under \"the line buffer's pointer below W\" (signal "
        "correspondence): PDR: an output differs in cycle 0 after reset")
