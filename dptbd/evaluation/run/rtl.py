"""The RTL check of ``dptbd run --rtl``: the generated Verilog of the FPGA stage simulated on
the run's frames (Verilator or cocotb + Icarus) and checked bit for bit against the golden model.
"""

from __future__ import annotations

import dataclasses
import pathlib
import time
from typing import Callable

import numpy as np

__all__ = ["RtlError", "RtlCheck", "rtl_tools_missing", "run_rtl", "check_rtl", "rtl_summary",
           "rtl_line"]

#: ``log(line)``: where the check says what it builds and simulates (``print`` in the command)
Log = Callable[[str], None]


def _silent(line: str) -> None:
    pass


class RtlError(RuntimeError):
    """The RTL simulation could not run or disagreed with the model."""


def rtl_tools_missing(simulator: str) -> str | None:
    """Why ``--rtl`` cannot run here with ``simulator`` (a sentence naming the missing tool
    and the other simulator), or None."""
    from dptbd.sim.sim_job import simulator_tools_missing

    return simulator_tools_missing(simulator, "--rtl-simulator")


@dataclasses.dataclass(frozen=True)
class RtlCheck:
    """What ``--rtl`` asks for: the simulator, the frames to simulate and the build root.

    Attributes
    ----------
    simulator : {"verilator", "icarus"}
    frames : int
        The first ``frames`` frames (0: all).
    build_dir : pathlib.Path or None
        Build root (None: the simulator's default).
    """

    simulator: str = "verilator"
    frames: int = 0
    build_dir: pathlib.Path | None = None


def run_rtl(frames: np.ndarray, cfg, n_frames: int | None, build_dir: pathlib.Path | None,
            design: str = "segmenter", simulator: str = "verilator", *,
            log: Log = _silent) -> dict:
    """Simulate the generated Verilog on the first ``n_frames`` frames (None or 0: all);
    raise :class:`RtlError` unless bit-exact.

    ``design="segmenter"``: the whole FPGA stage (``dptbd_seg``: DP pipeline + segmenter),
    every candidate list word checked against the golden models; ``"dp"``: the DP pipeline
    (``dptbd_dp``), every (E, d) word checked. ``simulator``: ``"verilator"``
    (:mod:`dptbd.sim.rtl.check`) or ``"icarus"`` (cocotb, :mod:`dptbd.sim.icarus`).
    ``build_dir`` None: the simulator's default build root. ``log`` receives a line before
    the build and one before the simulation.
    """
    why = rtl_tools_missing(simulator)
    if why is not None:
        raise RtlError(why)
    from dptbd.hw.schedule import check_supported

    check_supported(cfg)                      # ConfigError for e.g. overlapping segments
    total = frames.shape[0]
    if n_frames is not None and n_frames < 0:
        raise ValueError(f"--rtl-frames must be an integer in [0, inf), got {n_frames}")
    n = total if not n_frames else min(n_frames, total)
    start = time.perf_counter()
    if simulator == "verilator":
        info = _rtl_verilator(frames[:n], cfg, build_dir, design, log)
    else:
        info = _rtl_icarus(frames[:n], cfg, build_dir, design, log)
    info.update(frames=n, of_frames=total, seconds=round(time.perf_counter() - start, 1))
    if not info["passed"]:
        raise RtlError(f"the RTL ({info['module']} on {info['simulator']}) is NOT bit-exact "
                       f"against the golden model: {info['report']}{info.pop('details', '')}")
    info.pop("details", None)
    return info


def _rtl_verilator(frames: np.ndarray, cfg, build_dir, design: str, log: Log) -> dict:
    from dptbd.sim import verilator
    from dptbd.sim.rtl.check import check_frames

    root = verilator.default_build_root() if build_dir is None else pathlib.Path(build_dir)
    log(f"  RTL: building the Verilog for this configuration on Verilator in {root} …")
    sim = verilator.build(cfg, design, root=root)
    log(f"  RTL: build {'from the cache' if sim.cached else 'compiled'} in "
        f"{sim.seconds:.1f} s; simulating {sim.toplevel} on {len(frames)} frames "
        f"({frames.size} pixels) …")
    result = check_frames(sim, frames)
    raw = result.raw
    return {"simulator": "verilator", "design": design, "module": sim.toplevel,
            "passed": result.passed, "report": result.report,
            "words_in": result.words_in, "words_compared": result.words_out,
            "cycles": result.cycles, "latency": sim.latency,
            "simulated_cycles": raw.cycles, "sim_seconds": round(raw.sim_seconds, 4),
            "cycles_per_second": round(raw.cycles_per_second),
            "build_dir": str(sim.directory), "build_seconds": round(sim.seconds, 2),
            "build_cached": sim.cached}


def _rtl_icarus(frames: np.ndarray, cfg, build_dir, design: str, log: Log) -> dict:
    from dptbd.sim.icarus import build, simulate

    root = pathlib.Path("build/sim") if build_dir is None else pathlib.Path(build_dir)
    log(f"  RTL: building the Verilog for this configuration on Icarus in {root} …")
    sim = build(cfg, root, design=design)
    log(f"  RTL: simulating {sim.toplevel} on {len(frames)} frames ({frames.size} pixels) "
        f"with cocotb + Icarus …")
    result = simulate(sim, frames, run_name="dptbd-run")
    s = result.summary
    if s.get("sim_cycles_per_second"):        # tb_dp: while streaming
        cycles, seconds = s.get("stream_cycles"), s.get("stream_seconds")
    else:                                     # tb_segmenter: the whole test
        cycles, seconds = s.get("sim_cycles_total"), s.get("wall_seconds")
    info = {"simulator": "icarus", "design": design, "module": sim.toplevel,
            "passed": result.passed, "report": result.report,
            "words_in": s.get("pixels"), "words_compared": s.get("outputs"),
            "cycles": result.cycles, "latency": sim.latency,
            "simulated_cycles": cycles,
            "sim_seconds": None if seconds is None else round(seconds, 2),
            "cycles_per_second": round(cycles / seconds) if cycles and seconds else None,
            "build_dir": str(sim.directory), "build_seconds": round(sim.seconds, 2),
            "run_dir": str(result.run_dir)}
    if not result.passed:
        info["details"] = f"\n{result.log_tail(20)}\n(run files in {result.run_dir})"
    return info


_WORDS = {"segmenter": "candidate-list words", "dp": "(E, d) words"}


def rtl_summary(checked: int, total: int, module: str, simulator: str | None = None,
                words: int | None = None, cycles: int | None = None,
                design: str = "segmenter") -> str:
    """The line saying what the RTL check covered: simulator, frames (``--rtl-frames``),
    words compared and cycles (first input to last output)."""
    on = f" on {simulator.capitalize()}" if simulator else ""
    line = f"RTL ({module}{on}) checked frames 0-{checked - 1} of {total}: bit-exact"
    if words is not None:
        line += f", {words} {_WORDS.get(design, 'words')} compared"
    if cycles is not None:
        line += f", {cycles} cycles"
    if checked < total:
        line += (f"; frames {checked}-{total - 1} come from the golden model only "
                 f"(--rtl-frames 0 checks all)")
    return line


def check_rtl(frames: np.ndarray, cfg, check: RtlCheck, design: str, *,
              log: Log = _silent) -> dict:
    """:func:`run_rtl` for a run: its record (``summary.json``'s ``rtl``) with what was
    checked (``checked``, ``checked_frames``, ``summary``: :func:`rtl_summary`); ``log``
    also receives :func:`rtl_line`."""
    rtl = run_rtl(frames, cfg, check.frames, check.build_dir, design,
                  simulator=check.simulator, log=log)
    rtl["checked"] = True
    rtl["checked_frames"] = [0, rtl["frames"] - 1]
    rtl["summary"] = rtl_summary(rtl["frames"], frames.shape[0], rtl["module"],
                                 rtl.get("simulator"), rtl.get("words_compared"),
                                 rtl.get("cycles"), rtl.get("design", "segmenter"))
    log(rtl_line(rtl, frames.shape[0]))
    return rtl


def rtl_line(rtl: dict, n_frames: int) -> str:
    """The printed line of a passed check: verdict, module, simulator, frames, words, speed."""
    which = (f"the first {rtl['frames']} of {n_frames} frames" if rtl["frames"] < n_frames
             else f"all {n_frames} frames")
    cps = rtl.get("cycles_per_second")
    speed = ("" if not cps else f", {cps / 1e6:.2f} M cycles/s" if cps >= 1e6
             else f", {cps:.0f} cycles/s")
    return (f"  RTL: {rtl['report']} — the generated Verilog ({rtl['module']} on "
            f"{str(rtl.get('simulator', '?')).capitalize()}) matches the golden model on "
            f"{which}: {rtl.get('words_compared')} "
            f"{_WORDS.get(rtl.get('design'), 'words')} compared, {rtl.get('cycles')} "
            f"cycles{speed} ({rtl['seconds']:.1f} s in all)"
            + ("; the model's output is used for the rest" if rtl["frames"] < n_frames
               else ""))
