"""to_verilog: no ``always @*`` block, so a reset held from power-up resets in 4-state
simulation (``iverilog -g2012``), where Amaranth's own conversion loads X."""

import shutil
import subprocess

import pytest
from amaranth.back import verilog
from amaranth.hdl import Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.hw.flow.to_verilog import to_verilog

needs_icarus = pytest.mark.skipif(shutil.which("iverilog") is None,
                                  reason="needs Icarus Verilog")


class Credit(wiring.Component):
    """``ready``: a register, 0 in reset, then 1; ``count``: cycles since reset."""

    valid: In(1)
    ready: Out(1)
    count: Out(4)

    def elaborate(self, platform):
        m = Module()
        m.d.sync += [self.ready.eq(1), self.count.eq(self.count + 1)]
        return m


# rst high from time 0 by its declaration (no event), valid high in every cycle.
BENCH = """\
`timescale 1ns/1ps
module tb;
  reg clk = 0, rst = 1;
  wire ready; wire [3:0] count;
  top dut(.clk(clk), .rst(rst), .valid(1'b1), .ready(ready), .count(count));
  always #5 clk = ~clk;
  integer cycle;
  initial begin
    for (cycle = 0; cycle < 7; cycle = cycle + 1) begin
      @(negedge clk);
      if (cycle == 2) rst = 0;
      $display("%0d %b %b %h", cycle, rst, ready, count);
    end
    $finish;
  end
endmodule
"""


def _simulate(text, tmp_path) -> list[str]:
    (tmp_path / "top.v").write_text(text)
    (tmp_path / "tb.v").write_text(BENCH)
    subprocess.run(["iverilog", "-g2012", "-s", "tb", "-o", str(tmp_path / "tb.vvp"),
                    str(tmp_path / "tb.v"), str(tmp_path / "top.v")], check=True)
    run = subprocess.run(["vvp", "-n", str(tmp_path / "tb.vvp")], capture_output=True,
                         text=True, check=True)
    return run.stdout.split("\n")[:7]


def test_no_combinational_always_block():
    text = to_verilog(Credit(), "top")
    assert "module top(" in text
    assert "always @*" not in text
    assert "always @(posedge clk)" in text


@needs_icarus
def test_reset_from_power_up_resets_ready_and_count(tmp_path):
    # cycle, rst, ready, count at each falling edge: ready low in the 2 reset cycles and in
    # the first after it, count 0 until the first rising edge after the reset.
    assert _simulate(to_verilog(Credit(), "top"), tmp_path) == [
        "0 1 0 0", "1 1 0 0", "2 0 0 0", "3 0 1 1", "4 0 1 2", "5 0 1 3", "6 0 1 4"]


@needs_icarus
def test_amaranth_conversion_loads_x_in_the_same_bench(tmp_path):
    """Why to_verilog exists: with Amaranth's own conversion, ``ready`` (whose ``always @*``
    block reads only ``rst``, constant from time 0) is X during the reset and in the cycle
    after it."""
    lines = _simulate(verilog.convert(Credit(), name="top", emit_src=False), tmp_path)
    assert [line.split()[2] for line in lines] == ["x", "x", "x", "1", "1", "1", "1"]
