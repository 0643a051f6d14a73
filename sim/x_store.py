"""4-state (Icarus) check: an external state store's power-up contents never reach an output.

``docs/gateware.md`` (``DPCore``'s state-store port) promises that the store's contents at
power-up do not matter. A 2-state simulation cannot show that for X: an SRAM model that
powers up uninitialised (X in Icarus) or with arbitrary bits (direction codes above
M = START included) can only be checked in a 4-state simulator. :func:`run_x_store_check`
generates ``DPCore``'s Verilog (``generate_verilog(cfg, external_state_store=True)``),
wraps it in a plain Verilog testbench (:func:`testbench_verilog`) with a one-cycle
synchronous SRAM model whose contents are

``"x"``
    never initialised: every word (and the read register) is X until written;
``"random"``
    ``$random`` garbage of the full word width, so E takes any value and d any B_d-bit
    code, including the codes M+1 … 2**B_d − 1 that the pipeline never writes,

streams the frames with ``pixels.valid`` and ``states.ready`` held high, and checks every
cycle that no output bit of the module is X or Z, and afterwards that every ``states`` word
equals the golden model (:func:`dptbd.sim.scoreboard.expected_words`). Compiled with
``iverilog -g2012``, timescale 1ns/1ps. ``tests/sim/test_x_store.py`` runs it.

Two details of the bench, both outside the store question: ``states__payload`` is checked
from the first ``states.valid`` on (before it, the output FIFO's data register —
``ThermometerFIFO``, like ``SyncFIFOBuffered`` — has no initial value and ``valid`` is low), every
other output from the first clock edge; and ``rst`` is high from its declaration (a reset
from power-up, with no event at time 0), which the generated Verilog handles since it has no
``always @*`` block (:mod:`dptbd.hw.flow.to_verilog`).
"""

from __future__ import annotations

import pathlib
import re
import subprocess
import tempfile
from typing import NamedTuple

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.flow.verilog import MODULE_NAME, generate_verilog
from dptbd.hw.layouts import pack_pixel, unpack_state
from dptbd.sim.scoreboard import expected_words

__all__ = ["INITS", "XStoreCheck", "testbench_verilog", "run_x_store_check"]

#: Power-up contents of the store model: uninitialised (X) or ``$random`` bits.
INITS = ("x", "random")

_TB_MODULE = "tb_x_store"

_TEMPLATE = """\
`timescale 1ns/1ps
// DPCore ({module}) with an external one-cycle synchronous SRAM whose power-up
// contents are {init_text}. Written by dptbd.sim.x_store; do not edit.
module {tb};
  localparam integer PIXELS = {pixels};
  localparam integer WORDS = {words};
  localparam integer SW = {sw};
  reg clk = 0;
  reg rst = 1;   // from power-up, no event at time 0
  reg [{pw}-1:0] stream [0:PIXELS-1];
  integer fed = 0, got = 0, cycle = 0, x_cycles = 0, out_of_range = 0, seed = {seed}, i, out;
  reg payload_loaded = 0;
  wire pixels__valid = !rst && fed < PIXELS;
  wire [{pw}-1:0] pixels__payload = fed < PIXELS ? stream[fed] : {pw}'d0;
  wire pixels__ready, states__valid;
  wire [{ow}-1:0] states__payload;
  wire [{aw}-1:0] read_addr, write_addr;
  wire read_en, write_en;
  wire [SW-1:0] write_data;
  reg [SW-1:0] store [0:WORDS-1];
  reg [SW-1:0] read_data;

  {module} dut (
    .clk(clk), .rst(rst),
    .pixels__payload(pixels__payload), .pixels__valid(pixels__valid),
    .pixels__ready(pixels__ready),
    .states__payload(states__payload), .states__valid(states__valid), .states__ready(1'b1),
    .lut_addr({law}'d0), .lut_data({ldw}'d0), .lut_we(1'b0),
    .segment_frames({kw}'d{k}),
    .state_store__read_addr(read_addr), .state_store__read_en(read_en),
    .state_store__read_data(read_data),
    .state_store__write_addr(write_addr), .state_store__write_data(write_data),
    .state_store__write_en(write_en));

  // The SRAM: a read with read_en in cycle t presents the word in cycle t+1.
  always @(posedge clk) begin
    if (read_en) read_data <= store[read_addr];
    if (write_en) store[write_addr] <= write_data;
  end

  // Every output bit, every cycle; states__payload from the first states__valid on (before
  // it, the output FIFO's data register has no initial value and valid is low).
  wire [{all_w}-1:0] outputs = {{pixels__ready, states__valid, read_addr, read_en,
                                write_addr, write_data, write_en}};

  always @(posedge clk) begin
    if (states__valid !== 1'b0) payload_loaded = 1;
    if (^outputs === 1'bx || (payload_loaded && ^states__payload === 1'bx)) begin
      x_cycles = x_cycles + 1;
      if (x_cycles <= 5)
        $display("X_OUTPUT cycle=%0d ready=%b valid=%b payload=%b read=%b/%b write=%b/%b/%b",
                 cycle, pixels__ready, states__valid, states__payload, read_addr, read_en,
                 write_addr, write_data, write_en);
    end
    if (pixels__valid && pixels__ready) fed <= fed + 1;
    if (states__valid !== 1'b0) begin
      $fdisplay(out, "%h", states__payload);
      got = got + 1;
    end
    cycle = cycle + 1;
    if (got >= PIXELS) begin
      $fclose(out);
      $display("DONE cycles=%0d x_cycles=%0d out_of_range=%0d", cycle, x_cycles,
               out_of_range);
      $finish;
    end
    if (cycle > {timeout}) begin
      $fclose(out);
      $display("TIMEOUT cycles=%0d outputs=%0d x_cycles=%0d", cycle, got, x_cycles);
      $finish;
    end
  end

  always #5 clk = ~clk;

  initial begin
    $readmemh("{pixel_file}", stream);
    out = $fopen("{out_file}", "w");
{init_code}    repeat (3) @(posedge clk);
    rst <= 0;
  end
endmodule
"""

_RANDOM_INIT = """\
    // Arbitrary power-up bits: any E, any B_d-bit direction code (M+1 ... 2**B_d-1 too).
    for (i = 0; i < WORDS; i = i + 1) begin
      store[i] = {{$random(seed), $random(seed)}};
      if (store[i][SW-1:{eb}] > {m}) out_of_range = out_of_range + 1;
    end
    read_data = {{$random(seed), $random(seed)}};
"""


class XStoreCheck(NamedTuple):
    """Result of :func:`run_x_store_check` (a tuple ``(ok, report, words)``)."""

    ok: bool
    """No output bit was X/Z in any cycle and every ``states`` word matched the model."""
    report: str
    """One line of counts, then the first few problems (if any)."""
    words: int
    """Number of ``states`` words received."""


def testbench_verilog(cfg: DPConfig, info: dict, *, pixels: int, init: str, seed: int,
                      pixel_file: str | pathlib.Path, out_file: str | pathlib.Path) -> str:
    """The Verilog testbench around ``DPCore``'s module for ``cfg``.

    Parameters
    ----------
    cfg : DPConfig
        The configuration the module was generated for.
    info : dict
        Its manifest (``generate_verilog``): the port widths.
    pixels : int
        Number of pixels in ``pixel_file`` (whole frames, ``first`` on each frame's first).
    init : {"x", "random"}
        Power-up contents of the store model (module docstring).
    seed : int
        ``$random`` seed (``"random"`` only).
    pixel_file, out_file : path-like
        ``$readmemh`` file of packed pixels; file the ``states`` words are written to, one
        hex word a line (``x``/``z`` digits if a bit was X/Z).
    """
    if init not in INITS:
        raise ValueError(f"init must be one of {INITS}, got {init!r}")
    widths = {p["name"]: p["width"] for p in info["ports"]}
    sw = widths["state_store__read_data"]
    all_w = sum(widths[name] for name in (
        "pixels__ready", "states__valid", "state_store__read_addr",
        "state_store__read_en", "state_store__write_addr", "state_store__write_data",
        "state_store__write_en"))
    words = cfg.width * cfg.height
    init_code = (_RANDOM_INIT.format(eb=cfg.energy_bits, m=cfg.start_code)
                 if init == "random" else "")
    init_text = ("$random bits (E and d, out-of-range direction codes included)"
                 if init == "random" else "uninitialised (X)")
    return _TEMPLATE.format(
        module=MODULE_NAME, tb=_TB_MODULE, init_text=init_text, pixels=pixels, words=words,
        sw=sw, pw=widths["pixels__payload"], ow=widths["states__payload"],
        aw=widths["state_store__read_addr"], law=widths["lut_addr"],
        ldw=widths["lut_data"], kw=widths["segment_frames"], k=cfg.segment_frames,
        all_w=all_w, seed=seed, init_code=init_code,
        timeout=4 * pixels + 200, pixel_file=pathlib.Path(pixel_file).as_posix(),
        out_file=pathlib.Path(out_file).as_posix())


def _describe(cfg: DPConfig, index: int) -> str:
    per_frame = cfg.width * cfg.height
    frame, rest = divmod(index, per_frame)
    row, col = divmod(rest, cfg.width)
    return f"word {index} (frame {frame}, row {row}, col {col})"


def run_x_store_check(cfg: DPConfig, frames, *, init: str = "x", seed: int = 1,
                      lut_style: str = "auto",
                      directory: str | pathlib.Path | None = None) -> XStoreCheck:
    """Simulate ``DPCore`` for ``cfg`` in Icarus with a garbage external store; score it.

    Parameters
    ----------
    cfg : DPConfig
        The configuration (refused if the gateware does not implement it).
    frames : int or array_like
        ``(T, H, W)`` integer frames, or a number T of frames of uniformly random pixels
        drawn with ``seed``. Segments start at frame 0.
    init : {"x", "random"}
        Power-up contents of the store (module docstring).
    seed : int
        Seed of the random frames and of the store's ``$random`` contents.
    lut_style : {"auto", "bram", "logic"}
        Weight LUT storage of the generated Verilog.
    directory : path-like, optional
        Where to keep the Verilog, the testbench and the output words; a temporary
        directory (deleted afterwards) by default.

    Returns
    -------
    XStoreCheck
        ``(ok, report, words)``: ``ok`` iff the simulation finished, no output bit of the
        module was X/Z in any cycle, and every ``states`` word equals
        :func:`~dptbd.sim.scoreboard.expected_words`.

    Raises
    ------
    RuntimeError
        Icarus failed to compile the testbench.
    """
    if init not in INITS:
        raise ValueError(f"init must be one of {INITS}, got {init!r}")
    if isinstance(frames, (int, np.integer)):
        rng = np.random.default_rng(seed)
        frames = rng.integers(0, 1 << cfg.input_bits, size=(int(frames), cfg.height, cfg.width))
    frames = np.asarray(frames)
    if frames.ndim != 3 or frames.shape[1:] != (cfg.height, cfg.width):
        raise ValueError(f"frames must have shape (T, {cfg.height}, {cfg.width}), "
                         f"got {frames.shape}")
    if directory is None:
        with tempfile.TemporaryDirectory(prefix="dptbd-x-store-") as tmp:
            return _run(cfg, frames, init, seed, lut_style, pathlib.Path(tmp))
    directory = pathlib.Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    return _run(cfg, frames, init, seed, lut_style, directory)


def _run(cfg, frames, init, seed, lut_style, directory: pathlib.Path) -> XStoreCheck:
    text, info = generate_verilog(cfg, external_state_store=True, lut_style=lut_style)
    design = directory / f"{MODULE_NAME}.v"
    design.write_text(text)
    pixel_file, out_file = directory / "pixels.hex", directory / "states.hex"
    stream = [pack_pixel(cfg, int(p), index == 0)
              for frame in frames for index, p in enumerate(frame.ravel())]
    pixel_file.write_text("".join(f"{word:x}\n" for word in stream))
    tb = directory / f"{_TB_MODULE}.v"
    tb.write_text(testbench_verilog(cfg, info, pixels=len(stream), init=init, seed=seed,
                                    pixel_file=pixel_file, out_file=out_file))
    vvp = directory / f"{_TB_MODULE}.vvp"
    compiled = subprocess.run(["iverilog", "-g2012", "-s", _TB_MODULE, "-o", str(vvp),
                               str(tb), str(design)], capture_output=True, text=True)
    if compiled.returncode != 0:
        raise RuntimeError(f"iverilog failed:\n{compiled.stderr}")
    sim = subprocess.run(["vvp", "-n", str(vvp)], capture_output=True, text=True,
                         timeout=300)
    log = sim.stdout

    lines = out_file.read_text().split() if out_file.exists() else []
    expected = expected_words(cfg, frames).ravel()
    problems = [line for line in log.splitlines() if line.startswith(("X_OUTPUT", "TIMEOUT"))]
    done = re.search(r"DONE cycles=(\d+) x_cycles=(\d+) out_of_range=(\d+)", log)
    x_words = mismatches = 0
    for index, line in enumerate(lines):
        if not re.fullmatch(r"[0-9a-f]+", line):
            x_words += 1
            if x_words <= 5:
                problems.append(f"{_describe(cfg, index)}: X/Z in states__payload = {line}")
            continue
        if index < len(expected) and int(line, 16) != int(expected[index]):
            mismatches += 1
            if mismatches <= 5:
                got = unpack_state(cfg, int(line, 16))
                want = unpack_state(cfg, int(expected[index]))
                problems.append(f"{_describe(cfg, index)}: got {got}, expected {want}")
    x_cycles = int(done.group(2)) if done else -1
    ok = (done is not None and x_cycles == 0 and x_words == 0 and mismatches == 0
          and len(lines) == len(expected))
    summary = (f"{'PASS' if ok else 'FAIL'}: {cfg.width}x{cfg.height} r={cfg.radius} "
               f"K={cfg.segment_frames}, {len(frames)} frames, store init={init}"
               + (f" (seed {seed}, {done.group(3)} of {cfg.width * cfg.height} words with "
                  f"d > M={cfg.start_code})" if init == "random" and done else "")
               + f": {len(lines)}/{len(expected)} words, {x_words} with X/Z, "
               f"{mismatches} mismatching, {x_cycles if done else '?'} cycles with X/Z "
               f"on an output" + ("" if done else ", did not finish"))
    return XStoreCheck(ok, "\n".join([summary, *problems]), len(lines))
