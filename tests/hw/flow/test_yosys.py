"""``dptbd.hw.flow.yosys``: the Yosys cell-count parsers.

Checked on excerpts captured from Yosys 0.23 and 0.70 runs of the pipeline; real Yosys runs
are in ``test_synth.py`` (through :func:`~dptbd.hw.flow.synth.synthesize`).
"""

import dataclasses
import json

import pytest

from dptbd.hw.flow.family import ECP5, ICE40
from dptbd.hw.flow.yosys import (
    CellCounts, block_breakdown, parse_yosys_stat_json, parse_yosys_stat_text, yosys_script,
)

# ---- captured samples ------------------------------------------------------------------

#: ``stat -json`` of Yosys 0.23 on the pipeline: the same counts under the module and the design.
_DPTBD_DP_STAT = {
    "num_wires": 1365,
    "num_cells": 7217,
    "num_cells_by_type": {
        "SB_CARRY": 1373, "SB_DFF": 2188, "SB_DFFE": 86, "SB_DFFESR": 234,
        "SB_DFFSR": 209, "SB_LUT4": 3111, "SB_RAM40_4K": 16,
    },
}
YOSYS_STAT_JSON = json.dumps({
    "creator": "Yosys 0.23 (git sha1 7ce5011c24b)",
    "invocation": "stat -json ",
    "modules": {"\\dptbd_dp": _DPTBD_DP_STAT},
    "design": _DPTBD_DP_STAT,
}, indent=3)

YOSYS_LOG = """\
2.47. Printing statistics.

=== dptbd_dp ===

   Number of wires:               1365
   Number of wire bits:          14311
   Number of public wires:        1365
   Number of public wire bits:   14311
   Number of memories:               0
   Number of memory bits:            0
   Number of processes:              0
   Number of cells:               7217
     SB_CARRY                     1373
     SB_DFF                       2188
     SB_DFFE                        86
     SB_DFFESR                     234
     SB_DFFSR                      209
     SB_LUT4                      3111
     SB_RAM40_4K                    16

2.48. Executing CHECK pass (checking for obvious problems).
Checking module dptbd_dp...
Found and reported 0 problems.
"""

# ---- parsers ---------------------------------------------------------------------------


def test_yosys_stat_json():
    cells = parse_yosys_stat_json(YOSYS_STAT_JSON)
    assert (cells.lut4, cells.dff, cells.bram, cells.carry) == (3111, 2188 + 86 + 234 + 209,
                                                               16, 1373)


def test_yosys_stat_json_without_design_totals_uses_the_top_module():
    data = json.loads(YOSYS_STAT_JSON)
    del data["design"]
    data["modules"]["\\other"] = {"num_cells_by_type": {"SB_LUT4": 1}}
    assert parse_yosys_stat_json(json.dumps(data), top="dptbd_dp").lut4 == 3111
    with pytest.raises(ValueError, match=r"^stat -json output has no design totals and 2 modules; name the top "
                                         r"module$"):
        parse_yosys_stat_json(json.dumps(data))


def test_yosys_stat_text_matches_json():
    assert parse_yosys_stat_text(YOSYS_LOG) == parse_yosys_stat_json(YOSYS_STAT_JSON)
    with pytest.raises(ValueError, match=r"^no 'Number of cells:' line in the Yosys log$"):
        parse_yosys_stat_text("nothing here")


#: ``stat -json`` of Yosys 0.70 after ``synth_ecp5`` (flattened: ``$scopeinfo`` cells stand
#: for the flattened modules), counts of the 8x6 pipeline plus a multiplier and block RAMs.
_ECP5_FLAT = {"num_cells_by_type": {
    "$scopeinfo": 16, "CCU2C": 27, "L6MUX21": 13, "LUT4": 444, "PFUMX": 39,
    "TRELLIS_DPR16X4": 7, "TRELLIS_FF": 506, "DP16KD": 3, "MULT18X18D": 2}}

#: The same layout after ``synth_ecp5 -noflatten`` (counts shortened): the top instantiates
#: submodules by name; ``window`` has a submodule of its own.
_ECP5_HIER = json.dumps({"modules": {
    "\\dptbd_dp": {"num_cells_by_type": {
        "LUT4": 13, "TRELLIS_FF": 127, "dptbd_dp.window": 1, "dptbd_dp.weighted_0": 1,
        "dptbd_dp.weighted_1": 1}},
    "\\dptbd_dp.window": {"num_cells_by_type": {"LUT4": 20, "TRELLIS_FF": 81,
                                                 "dptbd_dp.window.line": 2}},
    "\\dptbd_dp.window.line": {"num_cells_by_type": {"DP16KD": 1, "TRELLIS_FF": 3}},
    "\\dptbd_dp.weighted_0": {"num_cells_by_type": {"LUT4": 4, "MULT18X18D": 1}},
    "\\dptbd_dp.weighted_1": {"num_cells_by_type": {"LUT4": 4, "MULT18X18D": 1}},
}, "design": {"num_cells_by_type": {"LUT4": 41}}})

#: Yosys 0.70's text ``stat`` (count first; ``$scopeinfo`` and ``submodules`` lines).
YOSYS_070_LOG = """\
=== dptbd_dp ===

        - processes
       16 cells
       16   $scopeinfo
     1036 submodules
       27   CCU2C
       13   L6MUX21
      444   LUT4
       39   PFUMX
        7   TRELLIS_DPR16X4
      506   TRELLIS_FF

3.52. Executing CHECK pass (checking for obvious problems).
"""


def test_ecp5_cell_classes():
    cells = parse_yosys_stat_json(json.dumps({"modules": {"\\dptbd_dp": _ECP5_FLAT},
                                              "design": _ECP5_FLAT}))
    assert (cells.lut4, cells.dff, cells.carry, cells.bram, cells.dsp, cells.lutram) == (
        444, 506, 27, 3, 2, 7)
    assert "$scopeinfo" not in cells.by_type
    assert cells.to_dict()["dsp"] == 2


def test_yosys_070_text_layout():
    cells = parse_yosys_stat_text(YOSYS_070_LOG)
    assert cells.by_type == {"CCU2C": 27, "L6MUX21": 13, "LUT4": 444, "PFUMX": 39,
                             "TRELLIS_DPR16X4": 7, "TRELLIS_FF": 506}


def test_block_breakdown_charges_each_module_its_own_cells():
    blocks = block_breakdown(_ECP5_HIER, "dptbd_dp")
    assert list(blocks) == ["dptbd_dp", "window", "window.line", "weighted_0", "weighted_1"]
    assert blocks["dptbd_dp"].by_type == {"LUT4": 13, "TRELLIS_FF": 127}
    assert blocks["window"].by_type == {"LUT4": 20, "TRELLIS_FF": 81}
    assert blocks["window.line"].by_type == {"DP16KD": 2, "TRELLIS_FF": 6}  # two instances
    assert blocks["weighted_1"].dsp == 1
    total = sum(blocks.values(), CellCounts({}))
    assert (total.lut4, total.dff, total.bram, total.dsp) == (41, 214, 2, 2)
    with pytest.raises(ValueError, match=r"^stat -json output has no module 'top'$"):
        block_breakdown(_ECP5_HIER, "top")


def test_yosys_script():
    assert yosys_script("d.v", top="t", family=ICE40, breakdown=False) == (
        "read_verilog d.v; synth_ice40 -top t -json netlist.json; "
        "tee -q -o yosys-stat.json stat -json")
    assert yosys_script("d.v", top="t", family=ECP5, breakdown=True) == (
        "read_verilog d.v; design -save rtl; synth_ecp5 -top t -noflatten; "
        "tee -q -o yosys-stat-hier.json stat -json; design -load rtl; "
        "synth_ecp5 -top t -json netlist.json; tee -q -o yosys-stat.json stat -json")


def test_yosys_script_with_other_synthesis_options():
    """``synth_args`` replaces the family's (``Family.synth_args``); ``()`` none."""
    ecp5 = dataclasses.replace(ECP5, synth_args=("-cmp2softlogic",))
    assert yosys_script("d.v", top="t", family=ecp5, breakdown=False) == (
        "read_verilog d.v; synth_ecp5 -top t -cmp2softlogic -json netlist.json; "
        "tee -q -o yosys-stat.json stat -json")
    assert yosys_script("d.v", top="t", family=ecp5, breakdown=False, synth_args=()) == (
        "read_verilog d.v; synth_ecp5 -top t -json netlist.json; "
        "tee -q -o yosys-stat.json stat -json")
    assert yosys_script("d.v", top="t", family=ECP5, breakdown=True,
                        synth_args=("-nowidelut", "-dff")) == (
        "read_verilog d.v; design -save rtl; synth_ecp5 -top t -nowidelut -dff -noflatten; "
        "tee -q -o yosys-stat-hier.json stat -json; design -load rtl; "
        "synth_ecp5 -top t -nowidelut -dff -json netlist.json; "
        "tee -q -o yosys-stat.json stat -json")
    assert yosys_script("d.v", top="t", family=ICE40, breakdown=False,
                        synth_args=["-dsp"]) == (
        "read_verilog d.v; synth_ice40 -top t -dsp -json netlist.json; "
        "tee -q -o yosys-stat.json stat -json")
