"""``dptbd.hw.flow.synth``: report parsing, tool errors, and one small real Yosys run.

The parsers are checked on excerpts captured from Yosys 0.23 and nextpnr-ice40 0.4 runs of
the pipeline; nextpnr itself is replaced by small shell scripts that write such a log, so
the default suite never places and routes (``-m slow`` does, on a tiny configuration).
"""

import dataclasses
import json
import pathlib
import shutil
import stat
import textwrap
import warnings

import pytest

from dptbd.config import DPConfig
from dptbd.hw.flow.synth import (
    CellCounts, PnrRun, SynthResult, SynthToolError, ToolNotFoundError, ToolTimeoutError,
    parse_nextpnr_log, parse_nextpnr_report, parse_yosys_stat_json, parse_yosys_stat_text,
    pick_clock, require_tool, run_nextpnr, synthesize,
)

needs_yosys = pytest.mark.skipif(shutil.which("yosys") is None, reason="yosys not installed")
needs_nextpnr = pytest.mark.skipif(shutil.which("nextpnr-ice40") is None,
                                   reason="nextpnr-ice40 not installed")

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

NEXTPNR_UTILISATION = """\
Info: Device utilisation:
Info: \t         ICESTORM_LC:  {lc:4d}/ 7680    {lcp}%
Info: \t        ICESTORM_RAM:    {ram:2d}/   32    {ramp}%
Info: \t               SB_IO:    55/  256    21%
Info: \t               SB_GB:     6/    8    75%
Info: \t        ICESTORM_PLL:     0/    2     0%
Info: \t         SB_WARMBOOT:     0/    1     0%

Info: Placed 0 cells based on constraints.
"""

NEXTPNR_PASS_LOG = """\
Warning: No PCF file specified; IO pins will be placed automatically

Info: Packing constants..
Info: promoting clk$SB_IO_IN (fanout 2749)
""" + NEXTPNR_UTILISATION.format(lc=4418, lcp=57, ram=14, ramp=43) + """\
Info: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 108.08 MHz (PASS at 100.00 MHz)

Info: Routing..
Info: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 103.86 MHz (PASS at 100.00 MHz)

Info: Slack histogram:
Info:  legend: * represents 6 endpoint(s)
1 warning, 0 errors

Info: Program finished normally.
"""

NEXTPNR_TIMING_FAIL_LOG = """\
""" + NEXTPNR_UTILISATION.format(lc=4370, lcp=56, ram=16, ramp=50) + """\
Info: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 99.04 MHz (FAIL at 100.00 MHz)
Warning: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 99.45 MHz (FAIL at 100.00 MHz)
"""

NEXTPNR_NO_FIT_LOG = """\
Info: Constraining chains...
Info:       67 LCs used to legalise carry chains.

Info: Annotating ports with timing budgets for target frequency 100.00 MHz
""" + NEXTPNR_UTILISATION.format(lc=4479, lcp=58, ram=34, ramp=106) + """\
ERROR: Unable to place cell 'core.weight_lut.column_3.0.0_RAM', no BELs remaining to \
implement cell type 'ICESTORM_RAM'
1 warning, 1 error
"""

NEXTPNR_REPORT_JSON = json.dumps({
    "critical_paths": [],
    "fmax": {"clk$SB_IO_IN_$glb_clk": {"achieved": 99.4530029296875, "constraint": 100}},
    "utilization": {"ICESTORM_LC": {"available": 7680, "used": 4370},
                    "ICESTORM_RAM": {"available": 32, "used": 16}},
})

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
    with pytest.raises(ValueError, match="top module"):
        parse_yosys_stat_json(json.dumps(data))


def test_yosys_stat_text_matches_json():
    assert parse_yosys_stat_text(YOSYS_LOG) == parse_yosys_stat_json(YOSYS_STAT_JSON)
    with pytest.raises(ValueError, match="Number of cells"):
        parse_yosys_stat_text("nothing here")


def test_nextpnr_log_takes_the_post_route_fmax():
    rep = parse_nextpnr_log(NEXTPNR_PASS_LOG)
    assert rep.fmax == {"clk$SB_IO_IN_$glb_clk": 103.86}
    assert rep.utilisation["ICESTORM_LC"] == (4418, 7680)
    assert rep.utilisation["ICESTORM_RAM"] == (14, 32)
    assert rep.utilisation["SB_WARMBOOT"] == (0, 1)
    assert rep.errors == () and rep.over_capacity == () and rep.no_fit_error is None


def test_nextpnr_log_timing_failure_still_gives_fmax():
    assert parse_nextpnr_log(NEXTPNR_TIMING_FAIL_LOG).fmax == {"clk$SB_IO_IN_$glb_clk": 99.45}


def test_nextpnr_log_no_fit():
    rep = parse_nextpnr_log(NEXTPNR_NO_FIT_LOG)
    assert rep.fmax == {}
    assert rep.over_capacity == ("ICESTORM_RAM",)
    assert "no BELs remaining" in rep.no_fit_error


def test_nextpnr_report_json():
    rep = parse_nextpnr_report(NEXTPNR_REPORT_JSON)
    assert rep.fmax == {"clk$SB_IO_IN_$glb_clk": pytest.approx(99.453)}
    assert rep.utilisation == {"ICESTORM_LC": (4370, 7680), "ICESTORM_RAM": (16, 32)}


def test_pick_clock():
    assert pick_clock({"clk$SB_IO_IN_$glb_clk": 1.0}) == "clk$SB_IO_IN_$glb_clk"
    two = {"clk$SB_IO_IN_$glb_clk": 1.0, "other_clk": 2.0}
    assert pick_clock(two, "clk") == "clk$SB_IO_IN_$glb_clk"
    assert pick_clock(two, "nope") is None


def test_result_median_and_fit():
    def run(seed, fmax, fits=True):
        return PnrRun(seed=seed, fits=fits, fmax_mhz=fmax, target_mhz=100.0,
                      utilisation={"ICESTORM_LC": (10, 20)}, seconds=1.0)
    res = SynthResult(variant="core", device="hx8k", package="ct256", target_mhz=100.0,
                      params={"energy_bits": 16}, cells=CellCounts({"SB_LUT4": 5}),
                      runs=(run(1, 103.0), run(2, 99.0), run(3, 107.0)),
                      yosys_seconds=1.0, verilog_seconds=1.0)
    assert res.fmax_median_mhz == 103.0 and res.fits and res.meets_target
    assert res.used("ICESTORM_LC") == 10 and res.available("ICESTORM_LC") == 20
    assert json.loads(json.dumps(res.to_dict()))["runs"][1]["meets_target"] is False
    no = dataclasses.replace(res, runs=(run(1, None, fits=False),))
    assert no.fits is False and no.fmax_median_mhz is None and no.meets_target is None
    assert dataclasses.replace(res, runs=()).fits is None


# ---- tool handling ---------------------------------------------------------------------


def test_missing_tool_names_the_debian_package():
    with pytest.raises(ToolNotFoundError, match=r"apt-get install nextpnr-ice40"):
        require_tool("/nonexistent/bin/nextpnr-ice40")
    with pytest.raises(ToolNotFoundError, match=r"Debian package 'yosys'"):
        synthesize(DPConfig(width=8, height=6), yosys="/nonexistent/yosys", seeds=())


def test_missing_nextpnr_is_reported_before_any_work(tmp_path):
    with pytest.raises(ToolNotFoundError, match="nextpnr-ice40"):
        synthesize(DPConfig(width=8, height=6), yosys=shutil.which("sh"),
                   nextpnr="/nonexistent/nextpnr-ice40", workdir=tmp_path)
    assert list(tmp_path.iterdir()) == []


def test_bad_arguments():
    with pytest.raises(ValueError, match="variant"):
        synthesize(DPConfig(), variant="board")
    with pytest.raises(ValueError, match="device"):
        synthesize(DPConfig(), device="ecp5")
    with pytest.raises(ValueError, match="lut_style must be one of 'auto', 'bram', 'logic'"):
        synthesize(DPConfig(), lut_style="distributed", yosys="/nonexistent/yosys")


def fake_nextpnr(folder: pathlib.Path, log: str, rc: int, sleep: float = 0) -> str:
    """A stand-in for nextpnr-ice40: writes ``log`` to its ``-l`` file, exits with ``rc``."""
    (folder / "canned.log").write_text(log)
    script = folder / "fake-nextpnr"
    script.write_text(textwrap.dedent(f"""\
        #!/bin/sh
        while [ $# -gt 0 ]; do
          if [ "$1" = "-l" ]; then cp "{folder / 'canned.log'}" "$2"; fi
          shift
        done
        sleep {sleep}
        exit {rc}
        """))
    script.chmod(script.stat().st_mode | stat.S_IXUSR)
    return str(script)


@pytest.mark.skipif(shutil.which("sh") is None, reason="needs a POSIX shell")
def test_run_nextpnr_outcomes(tmp_path):
    netlist = tmp_path / "netlist.json"
    netlist.write_text("{}")
    ok = run_nextpnr(netlist, seed=7, nextpnr=fake_nextpnr(tmp_path, NEXTPNR_PASS_LOG, 0))
    assert ok.fits and ok.fmax_mhz == 103.86 and ok.meets_target and ok.seed == 7
    assert ok.clock == "clk$SB_IO_IN_$glb_clk" and ok.used("ICESTORM_RAM") == 14

    no = run_nextpnr(netlist, seed=1, nextpnr=fake_nextpnr(tmp_path, NEXTPNR_NO_FIT_LOG, 255))
    assert not no.fits and no.fmax_mhz is None and no.utilisation["ICESTORM_RAM"] == (34, 32)
    assert no.error.startswith("over capacity: ICESTORM_RAM 34/32; nextpnr: Unable to place")

    with pytest.raises(SynthToolError, match="nextpnr failed") as info:
        run_nextpnr(netlist, seed=1, nextpnr=fake_nextpnr(tmp_path, "ERROR: bad json\n", 1))
    assert "bad json" in str(info.value)

    with pytest.raises(ToolTimeoutError, match="timed out"):
        run_nextpnr(netlist, seed=1, timeout=0.5,
                    nextpnr=fake_nextpnr(tmp_path, NEXTPNR_PASS_LOG, 0, sleep=5))


# ---- real tools ------------------------------------------------------------------------

#: The smallest useful pipeline: 8x6, 2-bit pixels, 4-bit energy, F = 0 (about 6 s of CPU
#: in Yosys 0.23, ~600 LUTs).
TINY = DPConfig(width=8, height=6, segment_frames=2, input_bits=2, energy_bits=4,
                weight_frac_bits=0)


@needs_yosys
def test_real_yosys_on_a_tiny_pipeline(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = synthesize(TINY, variant="top", seeds=(), workdir=tmp_path)
    c = res.cells
    assert 100 < c.lut4 < 5000 and 100 < c.dff < 5000 and 0 < c.carry < c.lut4
    assert 1 <= c.bram <= 32
    assert res.runs == () and res.fits is None and res.fmax_median_mhz is None
    assert (tmp_path / "netlist.json").exists() and (tmp_path / "yosys.log").exists()
    assert res.tools["yosys"].startswith("Yosys")


@needs_yosys
def test_lut_style_moves_the_weight_lut_out_of_block_ram(tmp_path):
    """``lut_style="logic"``: the M = 9 column memories (10 x 9 bits) leave block RAM.

    F = 8 as in the real configurations (Yosys keeps TINY's 1-bit columns in logic anyway);
    about 30 s of CPU for the two Yosys runs.
    """
    cfg = dataclasses.replace(TINY, weight_frac_bits=8)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bram = synthesize(cfg, variant="core", seeds=(), workdir=tmp_path / "bram",
                          lut_style="bram")
        auto = synthesize(cfg, variant="core", seeds=(), workdir=tmp_path / "auto")
    assert bram.params["lut_style"] == "bram" and auto.params["lut_style"] == "logic"
    assert bram.cells.bram - auto.cells.bram == cfg.n_moves
    assert auto.cells.dff > bram.cells.dff
    manifest = json.loads((tmp_path / "auto" / "dptbd_dp.json").read_text())
    assert manifest["lut_style"] == "logic"


@pytest.mark.slow
@needs_yosys
@needs_nextpnr
def test_real_place_and_route_of_a_tiny_pipeline(tmp_path, request):
    # pyproject's addopts deselect ``slow``; should they not, skip unless -m was given.
    if not request.config.getoption("markexpr", ""):
        pytest.skip("nextpnr place and route (~40 s): run with -m slow")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = synthesize(TINY, variant="core", seeds=(1,), workdir=tmp_path)
    assert res.fits is True
    assert 20 < res.fmax_median_mhz < 500
    assert 0 < res.used("ICESTORM_LC") <= res.available("ICESTORM_LC") == 7680
