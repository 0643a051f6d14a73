"""``dptbd.sim.coverage.code``: the .dat parser on a hand-written file, the Verilog line ->
Amaranth source map on a hand-written text in Yosys' style, point location, Verilator's
name escapes, and the refusal when ``verilator_coverage`` is not on PATH."""

from __future__ import annotations

import pytest
from helpers.refusals import whole

from dptbd.sim.coverage import code as C


def key(**fields) -> str:
    return "".join(f"\x01{k}\x02{v}" for k, v in fields.items())


DAT = "\n".join([
    "# SystemC::Coverage-3",
    f"C '{key(f='top.v', l=12, n=5, page='v_branch/top.sub', o='if', S=12, h='TOP.top.sub')}' 3",
    f"C '{key(f='top.v', l=12, n=6, page='v_branch/top.sub', o='else', h='TOP.top.sub')}' 0",
    f"C '{key(f='top.v', l=20, n=3, page='v_line/top', o='block', S='20-21', h='TOP.top')}' 7",
    f"C '{key(f='top.v', l=4, n=9, page='v_toggle/top', o='__024N[1]', h='TOP.top')}' 2",
    f"C '{key(f='top.v', l=4, n=9, page='v_toggle/top', o='__024N[1]', h='TOP.top')}' 5",
    f"C '{key(f='top.v', l=1, n=1, page='v_user/top', o='mine', h='TOP.top')}' 1",
    "",
])


def test_parse_dat_reads_every_field_and_adds_a_repeated_key():
    points = C.parse_dat(DAT)
    assert [(p.kind, p.module, p.line, p.column, p.what, p.span, p.count) for p in points] == [
        ("branch", "top.sub", 12, 5, "if", "12", 3),
        ("branch", "top.sub", 12, 6, "else", "", 0),
        ("line", "top", 20, 3, "block", "20-21", 7),
        ("toggle", "top", 4, 9, "__024N[1]", "", 7),      # the key twice: 2 + 5
    ]                                                      # v_user: not a kind reported
    assert [p.covered for p in points] == [True, False, True, True]
    assert C.unescape(points[3].what) == "$N[1]"
    assert C.unescape("dp__02ecore__03aq") == "dp.core:q"


def test_parse_dat_refuses_a_line_it_cannot_read():
    with pytest.raises(ValueError, match=whole(
            "coverage data line 2 is not C '<key>' <count>: \"C 'abc' x\"")):
        C.parse_dat("# SystemC::Coverage-3\nC 'abc' x\n")


# Yosys' write_verilog style of the coverage build's text: an if / else-if / else chain with
# its dptbd_cases attribute, a casez with per-item src comments, a register fed by an
# internal net, the time-0 trigger.
VERILOG = """\
module top(clk, a, b, q);
  reg \\$auto$verilog_backend.cc:2355:dump_module$1  = 0;
  (* src = "/nowhere/hw/x.py:5" *)
  output [1:0] q;
  reg [1:0] q = 2'h0;
  reg [1:0] \\$3 ;
  (* src = "/nowhere/hw/x.py:5" *)
  always @(posedge clk)
    q <= \\$3 ;
  always @* begin
    if (\\$auto$verilog_backend.cc:2355:dump_module$1 ) begin end
    \\$3  = q;
    (* dptbd_cases = "/nowhere/hw/x.py:10|/nowhere/hw/x.py:12|/nowhere/hw/x.py:15" *)
    (* src = "/nowhere/hw/x.py:10" *)
    if (a) begin
      \\$3  = 2'h1;
    end else if (b) begin
      \\$3  = 2'h2;
    end else begin
      \\$3  = 2'h3;
    end
    (* src = "/nowhere/hw/x.py:20" *)
    casez (a)
      /* src = "/nowhere/hw/x.py:21" */
      1'h0:
          \\$3  = 2'h0;
    endcase
  end
endmodule
"""


def test_source_map_names_the_amaranth_line_of_each_statement():
    srcmap, artefacts = C.source_map(VERILOG)
    lines = VERILOG.splitlines()
    at = {lines[n - 1].strip(): srcmap.get(n) for n in range(1, len(lines) + 1)}
    # not under the repository: the path as written
    assert at["if (a) begin"] == "/nowhere/hw/x.py:10"
    assert at["end else if (b) begin"] == "/nowhere/hw/x.py:12"       # the chain's 2nd case
    assert at["end else begin"] == "/nowhere/hw/x.py:15"              # m.Else: the 3rd
    assert at["casez (a)"] == "/nowhere/hw/x.py:20"
    assert at["1'h0:"] == "/nowhere/hw/x.py:21"
    assert at["always @* begin"] == "/nowhere/hw/x.py:5"      # $3 feeds q (x.py:5)
    assert at["reg [1:0] \\$3 ;"] == "/nowhere/hw/x.py:5"
    assert at["reg [1:0] q = 2'h0;"] == "/nowhere/hw/x.py:5"  # the port's src
    assert artefacts == {2, 11}


def test_registers_are_the_initialised_regs():
    text = VERILOG + "module \\top.sub (clk);\n  reg [3:0] \\count$2  = 4'h0;\nendmodule\n"
    assert C.registers(text) == {("top", "$auto$verilog_backend.cc:2355:dump_module$1"),
                                 ("top", "q"), ("top.sub", "count$2")}


def test_locate_a_chain_else_by_its_span_and_drop_the_trigger():
    srcmap, artefacts = C.source_map(VERILOG)
    line_else = C.Point("line", "top", "top.v", 17, 17, "else", "19-20", 0, "k1")
    branch = C.Point("branch", "top", "top.v", 15, 5, "if", "15-16", 1, "k2")
    trigger = C.Point("branch", "top", "top.v", 11, 5, "if", "11", 0, "k3")
    trigger_bit = C.Point("toggle", "top", "top.v", 2, 7,
                          "__024auto__024verilog_backend__02ecc__03a2355", "", 0, "k4")
    assert C.locate(line_else, srcmap) == "/nowhere/hw/x.py:15"
    assert C.locate(branch, srcmap) == "/nowhere/hw/x.py:10"
    assert C.usable([line_else, branch, trigger, trigger_bit], artefacts) == [line_else, branch]
    # a point of a vendor cell's model (an ECP5 build's DP16KD) is not the gateware's
    model = C.Point("branch", "DP16KD__D12_DB12_RBz1", "/somewhere/dptbd/sim/dp16kd.v", 15, 5,
                    "if", "15-16", 1, "k5")
    assert C.usable([model, branch], artefacts) == [branch]


def test_relative_src_is_repository_or_amaranth_relative():
    from dptbd.sim.coverage.code import _REPO
    assert C.relative_src(f"{_REPO}/hw/segmenter.py:183") == "hw/segmenter.py:183"
    assert C.relative_src("/x/site-packages/amaranth/lib/stream.py:50") == \
        "amaranth/lib/stream.py:50"


def test_relative_src_maps_another_checkouts_paths():
    """A build directory shared by two checkouts: the build's text holds the paths of the
    checkout that generated it; they map to this repository's files all the same."""
    assert C.relative_src("/work/other-checkout/hw/segmenter.py:183") == "hw/segmenter.py:183"
    assert C.relative_src("/srv/hw/clone/hw/flow/verilog.py:7") == "hw/flow/verilog.py:7"
    assert C.relative_src("/w/x/sim/coverage/code.py:1") == "sim/coverage/code.py:1"
    # not a file of this repository: left as it is
    assert C.relative_src("/w/x/hw/no_such_module.py:3") == "/w/x/hw/no_such_module.py:3"
    text = ('module dptbd_seg(clk);\n'
            '  (* src = "/work/other-checkout/hw/segmenter.py:201" *)\n'
            '  reg missed = 1\'h0;\n'
            'endmodule\n')
    srcmap, _ = C.source_map(text)
    assert srcmap[3] == "hw/segmenter.py:201"


def test_missing_verilator_coverage_is_named(monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))
    message = ("--coverage needs verilator_coverage (Debian package 'verilator', which "
               "installs it with verilator), and it is not on PATH")
    with pytest.raises(C.CoverageToolMissing, match=whole(message)):
        C.find_verilator_coverage()
    with pytest.raises(C.CoverageToolMissing, match=whole(message)):
        C.merge([tmp_path / "a.dat"], tmp_path / "m.dat")


def test_missing_verilator_coverage_through_the_command(monkeypatch, tmp_path, capsys):
    from dptbd.cli import main

    monkeypatch.setenv("PATH", str(tmp_path))
    out = tmp_path / "cov"
    assert main(["verify", "--cases", "segmenter-33x17-k2-n3", "--coverage", str(out)]) == 2
    assert capsys.readouterr().err == (
        "dptbd verify: error: --coverage needs verilator_coverage (Debian package "
        "'verilator', which installs it with verilator), and it is not on PATH\n")
    assert not out.exists()
