"""``dptbd.hw.flow.yosys``: the Yosys cell-count parsers.

Checked on excerpts captured from Yosys 0.23 runs of the pipeline; a real Yosys run is in
``test_synth.py`` (through :func:`~dptbd.hw.flow.synth.synthesize`).
"""

import json

import pytest

from dptbd.hw.flow.yosys import parse_yosys_stat_json, parse_yosys_stat_text

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
