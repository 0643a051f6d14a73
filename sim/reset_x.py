"""4-state (Icarus) check of each top level around reset: ``ready`` 0, no X, no deadlock.

``docs/gateware.md`` promises that ``pixels.ready`` (``s_axis_video_tready`` on
``dptbd_axi``) is low during reset and in the first cycle after it, that no output carries
X for any legal stimulus, a pixel offered in the first cycle after reset included, and the
AXI top level works from power-up with no register written. A 2-state simulator cannot see
any of it. :func:`run_reset_x_check` generates the Verilog of a top level (``"dp"``:
``dptbd_dp``, ``"seg"``: ``dptbd_seg``, ``"axi"``: ``dptbd_axi``), wraps it in a plain
Verilog testbench (:func:`testbench_verilog`) and runs it with ``iverilog -g2012``:

* every input is a ``reg`` set by its declaration (no event at time 0, as in a user's
  bench), changed only at falling clock edges; the reset is active in cycles
  ``reset_at`` … ``reset_at + reset_cycles - 1`` (cycle c ends with rising edge c; from its
  declaration when ``reset_at`` = 0: a reset from power-up; otherwise the design runs
  from power-up without reset first, and takes pixels, until the reset);
* the input stream offers a pixel in every cycle, in reset too, until the frames are all
  taken (AXI: ``tuser`` on each frame's first pixel, ``tlast`` on each line's last); the
  pixel index restarts at 0 with the reset, so the frames are streamed whole after it;
  the output stream is always ready, the LUT port and AXI4-Lite idle (valids low,
  ``bready``/``rready`` high), the run-time settings at the build values;
* in every cycle no output bit is X or Z, but for the output payload while its ``valid`` is
  low; the input ``ready`` and the output ``valid`` are 0 (not X) in every cycle that
  follows a reset cycle (the reset cycles but the first, and the first cycle after the
  reset) and, for a reset from power-up, in cycle 0;
* the output words after the reset are compared with the golden model: ``states`` words
  with :func:`dptbd.sim.scoreboard.expected_words`, candidate lists with
  :class:`~dptbd.sim.candidate_scoreboard.CandidateScoreboard` (AXI: ``tlast`` exactly on
  the trailers); every frame must be taken and every word out before the run ends
  (a deadlock is a timeout).

``core_options`` builds the DP core with implementation options, e.g. the ECP5 family's
(:meth:`~dptbd.hw.flow.family.Family.options_for`), whose ``DP16KD`` block RAMs are
compiled with the 4-state model of :mod:`dptbd.sim.cell_models` (every word X until written,
every output register X until loaded). ``tests/sim/test_reset_x.py`` runs it for the three
top levels and the ECP5 builds, ``tests/sim/test_reset_x_wide.py`` at P = 2 and 4.
"""

from __future__ import annotations

import pathlib
import re
import subprocess
import tempfile
from typing import Mapping, NamedTuple, Sequence

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import unpack_candidate
from dptbd.hw.layouts import pack_pixel, unpack_state
from dptbd.sim.candidate_scoreboard import CandidateScoreboard, expected_lists, list_words
from dptbd.sim.cell_models import model_sources
from dptbd.sim.scoreboard import expected_words

__all__ = ["TOPS", "ResetXCheck", "top_verilog", "testbench_verilog", "run_reset_x_check"]

#: The top levels: Verilog module, reset port (active level), input and output streams.
TOPS = {
    "dp": dict(module="dptbd_dp", reset="rst", active=1, valid="pixels__valid",
               ready="pixels__ready", out_valid="states__valid",
               out_payload=("states__payload",)),
    "seg": dict(module="dptbd_seg", reset="rst", active=1, valid="pixels__valid",
                ready="pixels__ready", out_valid="candidates__valid",
                out_payload=("candidates__payload",)),
    "axi": dict(module="dptbd_axi", reset="aresetn", active=0, valid="s_axis_video_tvalid",
                ready="s_axis_video_tready", out_valid="m_axis_cand_tvalid",
                out_payload=("m_axis_cand_tdata", "m_axis_cand_tuser", "m_axis_cand_tlast")),
}

_TB_MODULE = "tb_reset_x"


class ResetXCheck(NamedTuple):
    """Result of :func:`run_reset_x_check` (a tuple ``(ok, report, words)``)."""

    ok: bool
    """Every check of the module doc passed."""
    report: str
    """One line of counts, then the first few problems (if any)."""
    words: int
    """Output words received after the reset."""


def top_verilog(cfg: DPConfig, top: str, core_options=None) -> tuple[str, dict]:
    """The Verilog text and manifest of top level ``top`` (a key of :data:`TOPS`), its DP
    core built with ``core_options`` (``None``: DPCore's defaults)."""
    if top == "dp":
        from dptbd.hw.flow.verilog import generate_verilog
        return generate_verilog(cfg, core_options=core_options)
    if top == "seg":
        from dptbd.hw.flow.segmenter_verilog import generate_segmenter_verilog
        return generate_segmenter_verilog(cfg, core_options=core_options)
    if top == "axi":
        from dptbd.hw.flow.axi_package import generate_axi_verilog
        return generate_axi_verilog(cfg, core_options=core_options)
    raise ValueError(f"top must be one of {tuple(TOPS)}, got {top!r}")


def _input_values(cfg: DPConfig, top: str) -> dict[str, int]:
    """Constant inputs other than 0: readies high, run-time settings at the build values."""
    if top == "axi":
        return {"m_axis_cand_tready": 1, "s_axil_bready": 1, "s_axil_rready": 1}
    values = {"segment_frames": cfg.segment_frames}
    if top == "dp":
        return {**values, "states__ready": 1}
    return {**values, "candidates__ready": 1, "candidate_count": cfg.n_candidates,
            "histogram_shift": cfg.bin_shift}


def testbench_verilog(cfg: DPConfig, top: str, info: dict, *, pixels: int, power_up: bool,
                      pixel_file: str | pathlib.Path) -> str:
    """The Verilog testbench (module doc) around top level ``top`` with manifest ``info``.

    ``power_up``: the reset input is active from its declaration (run with
    ``+reset_at=0``), else idle until cycle ``reset_at``. The reset cycles are the plusargs
    ``+reset_at=A +reset_end=E`` (cycles A … E - 1); ``pixel_file`` holds one packed
    ``pixels`` payload (``"axi"``: a pixel) a line, in hex; ``+out=FILE`` gets the output
    words after the reset (hex, then ``tlast`` for ``"axi"``)."""
    spec = TOPS[top]
    ports = {p["name"]: p for p in info["ports"]}
    values = _input_values(cfg, top)
    reset, active = spec["reset"], spec["active"]
    idle = 1 - active
    lines = []
    for name, port in ports.items():
        width = port["width"]
        if port["direction"] == "input":
            init = {"aclk": 0, "clk": 0, reset: active if power_up else idle}.get(
                name, values.get(name, 0))
            lines.append(f"  reg [{width - 1}:0] {name} = {width}'d{init};")
        else:
            lines.append(f"  wire [{width - 1}:0] {name};")
    clock = "aclk" if top == "axi" else "clk"
    stream_width = ports["s_axis_video_tdata" if top == "axi" else "pixels__payload"]["width"]
    connections = ",\n    ".join(f".{name}({name})" for name in ports)
    payload = set(spec["out_payload"])
    checked = [name for name, p in ports.items()
               if p["direction"] == "output" and name not in payload]
    if top == "axi":
        feed = ("    s_axis_video_tdata <= stream[fed];\n"
                "    s_axis_video_tuser <= fed % FRAME == 0;\n"
                "    s_axis_video_tlast <= fed % WIDTH == WIDTH - 1;\n")
        record = '$fdisplay(out, "%h %b", m_axis_cand_tdata, m_axis_cand_tlast);'
    else:
        feed = "    pixels__payload <= stream[fed];\n"
        record = f'$fdisplay(out, "%h", {spec["out_payload"][0]});'
    payload_bits = " ^ ".join(f"(^{name})" for name in spec["out_payload"])
    return f"""\
`timescale 1ns/1ps
// {spec['module']} around reset: every input a reg set by its declaration (no event at time
// 0), changed at falling edges. Written by dptbd.sim.reset_x; do not edit.
module {_TB_MODULE};
  localparam integer PIXELS = {pixels}, FRAME = {cfg.frame_beats}, WIDTH = {cfg.row_beats};
  integer RESET_AT = 0, RESET_END = 4;   // +reset_at=A +reset_end=E
  reg [8*256-1:0] out_name;
  localparam integer TIMEOUT = {4 * pixels + 4000};
{chr(10).join(lines)}
  reg [{stream_width - 1}:0] stream [0:PIXELS-1];
  integer cycle = 0, fed = 0, words = 0, x_cycles = 0, ready_faults = 0, out, idle_cycles = 0;
  reg after_reset = 0;   // the previous cycle was a reset cycle (or this is cycle 0)
  wire in_reset = {reset} === 1'b{active};

  {spec['module']} dut (
    {connections});

  always #5 {clock} = ~{clock};

  // Inputs of cycle c + 1, set at the falling edge after rising edge c.
  always @(negedge {clock}) begin
    {reset} <= (cycle >= RESET_AT && cycle < RESET_END) ? 1'b{active} : 1'b{idle};
    {spec['valid']} <= fed < PIXELS;
    if (fed < PIXELS) begin
{feed}    end
  end

  // Rising edge c: the end of cycle c.
  always @(posedge {clock}) begin
    if (^{{{", ".join(checked)}}} === 1'bx
        || ({spec['out_valid']} === 1'b1 && ({payload_bits}) === 1'bx)) begin
      x_cycles = x_cycles + 1;
      if (x_cycles <= 5) $display("X_OUTPUT cycle=%0d rst=%b ready=%b valid=%b", cycle,
                                  {reset}, {spec['ready']}, {spec['out_valid']});
    end
    if ((cycle == 0 && RESET_AT == 0) || after_reset) begin
      if ({spec['ready']} !== 1'b0 || {spec['out_valid']} !== 1'b0) begin
        ready_faults = ready_faults + 1;
        if (ready_faults <= 5) $display("READY_FAULT cycle=%0d rst=%b ready=%b valid=%b",
                                        cycle, {reset}, {spec['ready']}, {spec['out_valid']});
      end
    end
    after_reset = in_reset;
    if (in_reset) fed = 0;
    else if ({spec['valid']} === 1'b1 && {spec['ready']} === 1'b1) fed = fed + 1;
    if (cycle >= RESET_END && {spec['out_valid']} === 1'b1) begin
      {record}
      words = words + 1;
    end
    idle_cycles = (cycle >= RESET_END && fed == PIXELS && {spec['out_valid']} !== 1'b1)
                  ? idle_cycles + 1 : 0;
    cycle = cycle + 1;
    if (idle_cycles > {(1 << cfg.histogram_bits) + 200 if top != 'dp' else 200}
        || cycle > TIMEOUT) begin
      $fclose(out);
      $display("END cycles=%0d fed=%0d words=%0d x_cycles=%0d ready_faults=%0d", cycle, fed,
               words, x_cycles, ready_faults);
      $finish;
    end
  end

  initial begin
    if ($value$plusargs("reset_at=%d", RESET_AT)) ;
    if ($value$plusargs("reset_end=%d", RESET_END)) ;
    $readmemh("{pathlib.Path(pixel_file).as_posix()}", stream);
    if (!$value$plusargs("out=%s", out_name)) out_name = "words.txt";
    out = $fopen(out_name, "w");
  end
endmodule
"""


def run_reset_x_check(cfg: DPConfig, frames, *, top: str,
                      resets: Sequence[tuple[int, int]] = ((0, 4),), seed: int = 1,
                      core_options: Mapping[str, str] | None = None,
                      directory: str | pathlib.Path | None = None) -> list[ResetXCheck]:
    """Simulate top level ``top`` around a reset in Icarus and score it (module doc), once
    per ``(reset_at, reset_cycles)`` of ``resets``.

    Parameters
    ----------
    cfg : DPConfig
        The configuration (refused if the gateware does not implement it).
    frames : int or array_like
        ``(T, H, W)`` integer frames, or a number T of frames of random pixels (``seed``).
    top : {"dp", "seg", "axi"}
        The top level (:data:`TOPS`).
    resets : sequence of (int, int)
        First reset cycle (>= 0; 0 is a reset from power-up) and number of reset cycles
        (>= 1) of each run.
    core_options : Mapping[str, str], optional
        The DP core's implementation options (:data:`~dptbd.hw.dp_core.CORE_OPTIONS`;
        ``None``: DPCore's defaults), e.g. a family's
        (:meth:`~dptbd.hw.flow.family.Family.options_for`). A build that instantiates vendor
        cells (ECP5 ``DP16KD``) is simulated with their 4-state models
        (:func:`dptbd.sim.cell_models.model_sources`: X until written or loaded).
    directory : path-like, optional
        Where to keep the Verilog, the bench and the words; a temporary directory by default.

    Returns
    -------
    list of ResetXCheck
        One per run: ``ok`` iff the run took every pixel after the reset, no output bit was
        X/Z, ``ready`` and the output ``valid`` were 0 where promised and every word after
        the reset equals the golden model.

    Raises
    ------
    RuntimeError
        Icarus failed to compile the bench.
    """
    if top not in TOPS:
        raise ValueError(f"top must be one of {tuple(TOPS)}, got {top!r}")
    for reset_at, reset_cycles in resets:
        if reset_at < 0 or reset_cycles < 1:
            raise ValueError(f"reset_at must be >= 0 and reset_cycles >= 1, got {reset_at} "
                             f"and {reset_cycles}")
    if isinstance(frames, (int, np.integer)):
        rng = np.random.default_rng(seed)
        frames = rng.integers(0, 1 << cfg.input_bits, size=(int(frames), cfg.height, cfg.width))
    frames = np.asarray(frames)
    if directory is None:
        with tempfile.TemporaryDirectory(prefix="dptbd-reset-x-") as tmp:
            return _run(cfg, frames, top, resets, core_options, pathlib.Path(tmp))
    directory = pathlib.Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    return _run(cfg, frames, top, resets, core_options, directory)


def _run(cfg, frames, top, resets, core_options, directory: pathlib.Path) -> list[ResetXCheck]:
    text, info = top_verilog(cfg, top, core_options)
    design = directory / f"{TOPS[top]['module']}.v"
    design.write_text(text)
    pixel_file = directory / "pixels.hex"
    if top == "axi" and cfg.pixels_per_clock > 1:   # P byte lanes, pixel 0 low
        from dptbd.hw.wide.axis_video import lane_bits
        p, lane = cfg.pixels_per_clock, lane_bits(cfg)
        flat = frames.ravel()
        stream = [sum(int(v) << (lane * k) for k, v in enumerate(flat[i:i + p]))
                  for i in range(0, flat.size, p)]
    elif top == "axi":
        stream = [int(p) for p in frames.ravel()]
    elif cfg.pixels_per_clock > 1:     # beats of P pixels (docs/gateware.md, "P pixels per clock")
        from dptbd.hw.wide import pack_beat
        p = cfg.pixels_per_clock
        stream = [pack_beat(cfg, frame.ravel()[i:i + p], i == 0)
                  for frame in frames for i in range(0, frame.size, p)]
    else:
        stream = [pack_pixel(cfg, int(p), index == 0)
                  for frame in frames for index, p in enumerate(frame.ravel())]
    pixel_file.write_text("".join(f"{word:x}\n" for word in stream))
    results = []
    for reset_at, reset_cycles in resets:
        vvp = directory / f"{_TB_MODULE}_{'power_up' if reset_at == 0 else 'late'}.vvp"
        if not vvp.exists():
            tb = vvp.with_suffix(".v")
            tb.write_text(testbench_verilog(cfg, top, info, pixels=len(stream),
                                            power_up=reset_at == 0, pixel_file=pixel_file))
            compiled = subprocess.run(["iverilog", "-g2012", "-s", _TB_MODULE, "-o", str(vvp),
                                       str(tb), str(design), *map(str, model_sources(text))],
                                      capture_output=True, text=True)
            if compiled.returncode != 0:
                raise RuntimeError(f"iverilog failed:\n{compiled.stderr}")
        out_file = directory / f"words_{reset_at}_{reset_cycles}.txt"
        log = subprocess.run(["vvp", "-n", str(vvp), f"+reset_at={reset_at}",
                              f"+reset_end={reset_at + reset_cycles}", f"+out={out_file}"],
                             capture_output=True, text=True, timeout=600).stdout
        results.append(_score(cfg, frames, top, reset_at, reset_cycles, len(stream), log,
                              out_file))
    return results


def _score(cfg, frames, top, reset_at, reset_cycles, pixels, log, out_file) -> ResetXCheck:
    end = re.search(r"END cycles=(\d+) fed=(\d+) words=(\d+) x_cycles=(\d+) "
                    r"ready_faults=(\d+)", log)
    problems = [line for line in log.splitlines()
                if line.startswith(("X_OUTPUT", "READY_FAULT"))]
    rows = ([line.split() for line in out_file.read_text().splitlines()]
            if out_file.exists() else [])
    x_words = [i for i, row in enumerate(rows)
               if not all(re.fullmatch(r"[0-9a-f]+", field) for field in row)]
    problems += [f"word {i}: X/Z in {' '.join(rows[i])}" for i in x_words[:5]]
    if not x_words:
        problems += _compare(cfg, frames, top, [int(row[0], 16) for row in rows],
                             [row[1:] for row in rows])
    if end is None:
        problems.append("the simulation did not finish")
    elif int(end.group(2)) != pixels:
        problems.append(f"deadlock: {end.group(2)} of {pixels} pixels taken after the "
                        f"reset in {end.group(1)} cycles")
    ok = (end is not None and not problems and int(end.group(4)) == 0
          and int(end.group(5)) == 0)
    summary = (f"{'PASS' if ok else 'FAIL'}: {TOPS[top]['module']} {cfg.width}x{cfg.height} "
               f"K={cfg.segment_frames}, {len(frames)} frames, reset in cycles {reset_at} … "
               f"{reset_at + reset_cycles - 1}: "
               + (f"{end.group(2)}/{pixels} pixels taken, {end.group(3)} words, "
                  f"{end.group(4)} cycles with X/Z on an output, {end.group(5)} cycles with "
                  f"ready or valid not 0 after a reset edge" if end else "did not finish"))
    return ResetXCheck(ok, "\n".join([summary, *problems]), len(rows))


def _compare(cfg, frames, top, words: list[int], flags: list[list[str]]) -> list[str]:
    """The words after the reset against the golden model (problems, empty if exact)."""
    if top == "dp" and cfg.pixels_per_clock > 1:
        return _compare_beats(cfg, frames, words)
    if top == "dp":
        expected = [int(w) for w in expected_words(cfg, frames).ravel()]
        problems = [f"{len(words)} states words, the model gives {len(expected)}"] \
            if len(words) != len(expected) else []
        for index, (got, want) in enumerate(zip(words, expected)):
            if got != want:
                problems.append(f"word {index}: got {unpack_state(cfg, got)}, expected "
                                f"{unpack_state(cfg, want)}")
                break
        return problems
    lists = expected_lists(cfg, frames)
    board = CandidateScoreboard(cfg, lists)
    board.receive_array(np.array(words, dtype=np.uint64))
    problems = [] if board.done else [board.report()]
    if top == "axi":
        want = [unpack_candidate(cfg, w)[0] == "trailer"
                for ws in list_words(cfg, lists) for w in ws]
        got = [row == ["1"] for row in flags]
        if got != want:
            problems.append(f"tlast on words {[i for i, g in enumerate(got) if g]}, the model's "
                            f"trailers are words {[i for i, w in enumerate(want) if w]}")
    return problems


def _compare_beats(cfg, frames, words: list[int]) -> list[str]:
    """:func:`_compare` of ``dptbd_dp`` at P > 1: each output beat's P states against the
    model's states of its P pixels."""
    from dptbd.hw.wide import unpack_beat_states
    p = cfg.pixels_per_clock
    expected = [unpack_state(cfg, int(w)) for w in expected_words(cfg, frames).ravel()]
    problems = [f"{len(words)} states beats, the model gives {len(expected) // p}"] \
        if len(words) * p != len(expected) else []
    for index, word in enumerate(words):
        got, want = unpack_beat_states(cfg, word), expected[index * p:(index + 1) * p]
        if got != want:
            problems.append(f"beat {index}: got {got}, expected {want}")
            break
    return problems
