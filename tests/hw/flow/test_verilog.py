"""Verilog generation: the manifest, Icarus and Verilator on the output, and an Icarus run.

Both weight LUT storage styles are generated (``lut_style``: "small" and "core" use the
default, logic for r = 1; "small-bram" and "radius2" block RAM; "radius2-logic" logic), and
each is linted, compiled and, for r = 1, simulated against the golden model.

The Icarus run streams frames through the *generated Verilog* (the artefact the cocotb
harness will use) with random input gaps and back-pressure, and scores it against the golden
model like the Amaranth-simulator tests do.

Paper 000's family in Verilog (the end of the file): every variant converts, its ports are
the 001 ports plus the merit / penalty write ports of the LUTs it builds, and the default
build is unchanged.
"""

import json
import re
import shutil
import subprocess

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.layouts import pack_pixel, unpack_state
from dptbd.hw.flow.verilog import MODULE_NAME, build_top, generate_verilog
from dptbd.hw.schedule import PipelineSchedule
from helpers.refusals import whole
from helpers.family_harness import VARIANTS, family_reference_states, likelihood_merit, variant
from helpers.hw_harness import (
    assert_states_equal,
    assert_verilator_lints_clean,
    frames_to_stream,
    reference_states,
    refused,
)
from helpers.seg_harness import make_config

SMALL = DPConfig(width=5, height=4, segment_frames=3, energy_bits=12)
RADIUS2 = DPConfig(width=7, height=6, segment_frames=2, radius=2, rounding="half_up")

needs_iverilog = pytest.mark.skipif(shutil.which("iverilog") is None, reason="iverilog not installed")
needs_verilator = pytest.mark.skipif(shutil.which("verilator") is None, reason="verilator not installed")

ALL = ["small", "radius2", "core", "small-bram", "radius2-logic"]


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """``{name: (path of the .v, manifest)}`` for the configurations under test."""
    out = {}
    for name, cfg, external, style in [("small", SMALL, False, "auto"),
                                       ("radius2", RADIUS2, False, "auto"),
                                       ("core", SMALL, True, "auto"),
                                       ("small-bram", SMALL, False, "bram"),
                                       ("radius2-logic", RADIUS2, False, "logic")]:
        folder = tmp_path_factory.mktemp(name)
        text, info = generate_verilog(cfg, external_state_store=external, lut_style=style,
                                      manifest_path=folder / "dptbd_dp.json")
        path = folder / "dptbd_dp.v"
        path.write_text(text)
        assert json.loads((folder / "dptbd_dp.json").read_text()) == json.loads(json.dumps(info))
        out[name] = (path, info)
    return out


def declared_ports(text):
    """``{name: (direction, width)}`` of the ports of module ``dptbd_dp``."""
    body = text[text.index(f"module {MODULE_NAME}("):]
    body = body[:body.index("endmodule")]
    header = body[:body.index(");")]
    names = [n.strip() for n in header[header.index("(") + 1:].split(",")]
    ports = {}
    for direction, msb, name in re.findall(r"^\s*(input|output)\s+(?:\[(\d+):0\]\s+)?(\S+);",
                                           body, flags=re.M):
        ports[name] = (direction, int(msb) + 1 if msb else 1)
    assert sorted(ports) == sorted(names)
    return ports


@pytest.mark.parametrize("name", ALL)
def test_manifest_lists_exactly_the_verilog_ports(generated, name):
    path, info = generated[name]
    ports = declared_ports(path.read_text())
    assert ports == {p["name"]: (p["direction"], p["width"]) for p in info["ports"]}


def test_top_level_port_names(generated):
    ports = declared_ports(generated["small"][0].read_text())
    assert ports == {
        "clk": ("input", 1), "rst": ("input", 1),
        "pixels__payload": ("input", 9), "pixels__valid": ("input", 1),
        "pixels__ready": ("output", 1),
        "states__payload": ("output", 12 + 4 + 3), "states__valid": ("output", 1),
        "states__ready": ("input", 1),
        "lut_addr": ("input", 7), "lut_data": ("input", 9), "lut_we": ("input", 1),
        "segment_frames": ("input", 2), "segment_begin": ("output", 1),
        "events": ("output", 4),
    }
    core = declared_ports(generated["core"][0].read_text())
    assert core["state_store__read_addr"] == ("output", 5)
    assert core["state_store__read_data"] == ("input", 16)
    assert core["state_store__write_en"] == ("output", 1)


def test_manifest_contents(generated):
    info = generated["small"][1]
    assert info["module"] == "dptbd_dp" and info["top"] == "DPPipeline"
    assert info["latency"] == 14 and info["write_latency"] == 12
    assert info["parameters"]["width"] == 5 and info["parameters"]["segment_stride"] == 3
    assert info["layouts"]["pixel"] == {"pixel": {"offset": 0, "width": 8},
                                        "first": {"offset": 8, "width": 1}}
    assert info["layouts"]["state"]["end_of_segment"] == {"offset": 18, "width": 1}
    assert info["weight_codes"] == SMALL.weight_codes.tolist()
    assert generated["radius2"][1]["latency"] == 15


#: A weight LUT column memory (``reg [8:0] column_N [9:0]``), in both styles.
COLUMN_MEMORY = re.compile(r"reg \[\d+:0\] column_\d+ \[")
#: The ``"logic"`` style's attribute on a column memory.
LOGIC_COLUMN = re.compile(r'\(\* ram_style = "logic" \*\)\s*reg \[\d+:0\] column_\d+ \[')


@pytest.mark.parametrize("name, style, columns", [
    ("small", "logic", 9), ("core", "logic", 9), ("small-bram", "bram", 9),
    ("radius2", "bram", 25), ("radius2-logic", "logic", 25)])
def test_lut_style_in_verilog_and_manifest(generated, name, style, columns):
    """"auto" resolves to logic for r = 1 and block RAM for r = 2: M column memories, marked
    for logic in the ``"logic"`` style."""
    path, info = generated[name]
    text = path.read_text()
    assert info["lut_style"] == style
    assert len(COLUMN_MEMORY.findall(text)) == columns
    assert len(LOGIC_COLUMN.findall(text)) == (columns if style == "logic" else 0)


def test_lut_styles_have_the_same_manifest_but_for_the_style(generated):
    info_logic, info_bram = generated["small"][1], generated["small-bram"][1]
    assert {k: v for k, v in info_logic.items() if k != "lut_style"} == \
        {k: v for k, v in info_bram.items() if k != "lut_style"}


def test_unknown_lut_style_is_refused():
    with refused(ValueError, match=r"^lut_style must be one of 'auto', 'bram', 'logic', "
                                    r"got 'distributed'$"):
        generate_verilog(SMALL, lut_style="distributed")


@needs_iverilog
@pytest.mark.parametrize("name", ALL)
def test_icarus_compiles(generated, name, tmp_path):
    path, _ = generated[name]
    run = subprocess.run(["iverilog", "-g2012", "-o", str(tmp_path / "a.vvp"), str(path)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


@needs_verilator
@pytest.mark.parametrize("external", [False, True], ids=["pipeline", "core"])
def test_verilator_lints_clean_at_the_default_128x128(tmp_path, external):
    """The configuration users build first (``dptbd verilog`` with no options), not only the
    small ones: memory sizes and counter widths differ."""
    cfg = DPConfig()
    assert (cfg.width, cfg.height) == (128, 128)
    text, _ = generate_verilog(cfg, external_state_store=external)
    path = tmp_path / "dptbd_dp.v"
    path.write_text(text)
    assert_verilator_lints_clean(path, MODULE_NAME)


@needs_verilator
@pytest.mark.parametrize("name", ALL)
def test_verilator_lints_clean(generated, name):
    path, _ = generated[name]
    assert_verilator_lints_clean(path, MODULE_NAME)


TESTBENCH = """
module tb;
  reg clk = 0, rst = 1;
  reg [{pw}-1:0] pixels__payload = 0;
  reg pixels__valid = 0, states__ready = 0, lut_we = 0;
  reg [{aw}-1:0] lut_addr = 0;
  reg [{dw}-1:0] lut_data = 0;
  reg [{kw}-1:0] segment_frames = {k};
  wire pixels__ready, states__valid, segment_begin;
  wire [3:0] events;
  wire [{sw}-1:0] states__payload;
  dptbd_dp dut (.*);
  reg [{pw}-1:0] pixels [0:{n}-1];
  integer n_in = 0, n_out = 0, cycle = 0, seed = 1, out;
  always #5 clk = ~clk;
  initial begin
    $readmemh("{hexfile}", pixels);
    out = $fopen("{outfile}", "w");
    repeat (3) @(posedge clk);
    rst <= 0;
    #({timeout});
    $display("timeout");
    $finish;
  end
  always @(posedge clk) if (!rst) begin
    if (pixels__valid && pixels__ready) n_in = n_in + 1;
    if (states__valid && states__ready) begin
      $fdisplay(out, "%h", states__payload);
      n_out = n_out + 1;
      if (n_out == {n}) begin $fclose(out); $finish; end
    end
    if (!pixels__valid || pixels__ready) begin
      if (n_in < {n} && ($random(seed) & 3) != 0) begin
        pixels__valid <= 1;
        pixels__payload <= pixels[n_in];
      end else
        pixels__valid <= 0;
    end
    states__ready <= ($random(seed) % 5) != 0;
    cycle = cycle + 1;
  end
endmodule
"""


def icarus_states(cfg, frames, info, verilog_path, tmp_path, *, idle_inputs=(),
                  timeout=120) -> list:
    """Run :data:`TESTBENCH` on the module at ``verilog_path`` (manifest ``info``) with the
    pixels of ``frames`` under Icarus (4-state) and return the unpacked ``states`` words.
    ``idle_inputs``: further input ports the bench holds at 0 (e.g. the family's write
    ports). Fails on a compile error, a timeout or an X / Z on ``states__payload``."""
    stream = frames_to_stream(frames)
    (tmp_path / "pixels.hex").write_text(
        "".join(f"{pack_pixel(cfg, p, f):x}\n" for p, f in stream))
    widths = {p["name"]: p["width"] for p in info["ports"]}
    idle = "".join(f"  reg [{widths[name]}-1:0] {name} = 0;\n" for name in idle_inputs)
    (tmp_path / "tb.v").write_text(
        TESTBENCH.replace("  wire pixels__ready", idle + "  wire pixels__ready").format(
            pw=widths["pixels__payload"], sw=widths["states__payload"], aw=widths["lut_addr"],
            dw=widths["lut_data"], kw=widths["segment_frames"], k=cfg.segment_frames,
            n=len(stream), hexfile=tmp_path / "pixels.hex",
            outfile=tmp_path / "states.txt", timeout=10 * 20 * len(stream)))
    compile_ = subprocess.run(["iverilog", "-g2012", "-o", str(tmp_path / "tb.vvp"),
                               str(tmp_path / "tb.v"), str(verilog_path)],
                              capture_output=True, text=True)
    assert compile_.returncode == 0, compile_.stderr
    sim = subprocess.run(["vvp", "-n", str(tmp_path / "tb.vvp")], capture_output=True,
                         text=True, timeout=timeout)
    assert "timeout" not in sim.stdout, sim.stdout
    lines = (tmp_path / "states.txt").read_text().split()
    assert all(re.fullmatch(r"[0-9a-f]+", line) for line in lines), "X or Z on states__payload"
    return [unpack_state(cfg, int(line, 16)) for line in lines]


@needs_iverilog
@pytest.mark.parametrize("name", ["small", "small-bram"])
def test_icarus_simulation_matches_golden_model(generated, name, tmp_path):
    path, info = generated[name]
    cfg = SMALL
    frames = np.random.default_rng(17).integers(0, 256, size=(5, cfg.height, cfg.width))
    outputs = icarus_states(cfg, frames, info, path, tmp_path)
    assert_states_equal(outputs, reference_states(cfg, frames))


# Paper 000's family (docs/arithmetic.md §8)

PAPER001_PORTS = {"clk", "rst", "pixels__payload", "pixels__valid", "pixels__ready",
                  "states__payload", "states__valid", "states__ready", "lut_addr", "lut_data",
                  "lut_we", "segment_frames", "segment_begin", "events"}


def ports_of(info):
    return {p["name"]: (p["direction"], p["width"]) for p in info["ports"]}


@pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")
@pytest.mark.parametrize("name", VARIANTS)
def test_every_variant_converts_with_its_write_ports(name):
    cfg = make_config(**variant(name)[0])
    text, info = generate_verilog(cfg)
    ports = ports_of(info)
    extra = {}
    if "merit_codes" in cfg.family_fields_in_use:
        extra.update({"merit_addr": ("input", cfg.input_bits),
                      "merit_data": ("input", cfg.merit_width), "merit_we": ("input", 1)})
    if "penalty_codes" in cfg.family_fields_in_use:
        extra.update({"penalty_addr": ("input", (cfg.lut_entries - 1).bit_length()),
                      "penalty_data": ("input", cfg.penalty_width), "penalty_we": ("input", 1)})
    assert set(ports) == PAPER001_PORTS | set(extra)
    assert {k: ports[k] for k in extra} == extra
    assert info["latency"] == PipelineSchedule.from_config(cfg).latency
    assert "module dptbd_dp(" in text


@pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")
@pytest.mark.skipif(shutil.which("verilator") is None, reason="verilator not installed")
def test_all_family_blocks_lint_clean(tmp_path):
    """Merit LUT, penalty LUT (r = 2, block RAM), signed tree, forgetting, recursion."""
    cfg = make_config(**{**variant("recursive-r2-truncate")[0],
                         "merit_codes": np.arange(256) - 100, "energy_bits": 12})
    assert len(cfg.family_fields_in_use) == 4
    text, _ = generate_verilog(cfg)
    path = tmp_path / "dptbd_dp.v"
    path.write_text(text)
    assert_verilator_lints_clean(path, "dptbd_dp")


@pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")
@pytest.mark.parametrize("external", [False, True])
def test_the_paper001_build_is_unchanged_by_default_valued_family_fields(external):
    """§8 fields set to values that do not change the arithmetic build the §4-§5 pipeline:
    byte-identical Verilog, the 001 ports, the 001 latency."""
    base = DPConfig(width=8, height=8)
    explicit = base.replace(merit_codes=np.arange(256), penalty_codes=np.zeros((10, 9), int),
                            forgetting=1.0, forgetting_bits=5)
    assert explicit.is_paper001_datapath
    text, info = generate_verilog(base, external_state_store=external)
    assert generate_verilog(explicit, external_state_store=external)[0] == text
    assert {"merit_we", "penalty_we"}.isdisjoint(ports_of(info))
    if not external:
        assert set(ports_of(info)) == PAPER001_PORTS
    assert info["latency"] == 14 and info["schedule"]["faded"] == info["schedule"]["best"]


@pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")
@pytest.mark.skipif(shutil.which("iverilog") is None, reason="iverilog not installed")
def test_icarus_runs_the_family_verilog_bit_exact(tmp_path):
    """The generated Verilog of a variant with every block (merit LUT, penalty LUT, signed
    tree, forgetting, recursion) in a 4-state simulator, with random gaps and back-pressure
    (``icarus_states``' testbench, the write ports held idle), against the golden model."""
    cfg = make_config(**{**variant("recursive-r1")[0], "merit_codes": likelihood_merit()})
    assert len(cfg.family_fields_in_use) == 4
    text, info = generate_verilog(cfg)
    (tmp_path / "dptbd_dp.v").write_text(text)
    frames = np.random.default_rng(5).integers(0, 256, size=(5, cfg.height, cfg.width))
    outputs = icarus_states(cfg, frames, info, tmp_path / "dptbd_dp.v", tmp_path, timeout=300,
                            idle_inputs=("merit_addr", "merit_data", "merit_we",
                                         "penalty_addr", "penalty_data", "penalty_we"))
    assert_states_equal(outputs, family_reference_states(cfg, frames))


def test_build_top_with_an_axi_state_store():
    from dptbd.hw.axi_store.pipeline import DPPipelineAxi
    cfg = DPConfig(width=16, height=12)
    store = cfg.axi_store(data_bits=32, burst_beats=2)
    top = build_top(cfg, state_store=store)
    assert isinstance(top, DPPipelineAxi) and top.store is store
    with pytest.raises(ValueError, match=whole(
            "external_state_store and state_store exclude each other: the state store is "
            "either outside the module or behind its AXI4 port")):
        build_top(cfg, state_store=store, external_state_store=True)
    with pytest.raises(ValueError, match=whole(
            "state_store was made for another configuration than cfg")):
        build_top(cfg.replace(segment_frames=2), state_store=store)
