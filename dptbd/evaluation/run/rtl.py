"""The RTL check of ``dptbd run --rtl``: the generated Verilog of the FPGA stage simulated on
the run's frames (Verilator or cocotb + Icarus) and checked bit for bit against the golden model.

Where the state lives (``--rtl-state-store``, :data:`STATE_STORES`): ``"chip"`` simulates
``dptbd_seg`` (or ``dptbd_dp``) with its state store on chip; ``"axi"`` the drop-in core
``dptbd_axi`` (or ``dptbd_dp``) built with ``--state-store axi``, its state in the Verilator
harness's AXI4 memory model (``sim/harness/axi4_memory.h``, zero latency, every channel
ready) with the store's default layout (:meth:`~dptbd.config.DPConfig.axi_store`); ``"auto"``
(the default) takes ``"axi"`` when the frame's state does not fit in the block RAM of the
largest device the flow builds for (:func:`needs_axi_store`), as at 640 x 512 and 4096 x 256,
and ``"chip"`` otherwise.
"""

from __future__ import annotations

import dataclasses
import pathlib
import time
from typing import Callable

import numpy as np

__all__ = ["RtlError", "RtlCheck", "STATE_STORES", "block_ram_bits", "needs_axi_store",
           "resolve_state_store", "rtl_tools_missing", "run_rtl", "check_rtl", "rtl_summary",
           "rtl_line"]

#: ``--rtl-state-store``: where the simulated design keeps its state (see the module doc).
STATE_STORES = ("auto", "chip", "axi")

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
    state_store : {"auto", "chip", "axi"}
        Where the state lives (:data:`STATE_STORES`, :func:`resolve_state_store`).
    """

    simulator: str = "verilator"
    frames: int = 0
    build_dir: pathlib.Path | None = None
    state_store: str = "auto"


def block_ram_bits() -> tuple[int, str]:
    """(bits, "family device") of the largest block RAM of the devices the flow builds for
    (:data:`dptbd.hw.flow.family.FAMILIES`, the vendors' data sheets)."""
    from dptbd.hw.flow.family import FAMILIES

    return max((count * bits, f"{family.name} {device}")
               for family in FAMILIES.values()
               for device, (count, bits) in family.block_rams.items())


def needs_axi_store(cfg) -> bool:
    """Whether the on-chip state store of ``cfg`` (W·H states of ``state_bits``) exceeds
    the block RAM of every device the flow builds for (:func:`block_ram_bits`)."""
    return cfg.width * cfg.height * cfg.state_bits > block_ram_bits()[0]


def resolve_state_store(cfg, state_store: str, simulator: str = "verilator") -> str:
    """``"chip"`` or ``"axi"``: ``state_store`` with ``"auto"`` resolved for ``cfg``
    (:func:`needs_axi_store`). The AXI4 store runs on Verilator only: ``ValueError`` with
    ``simulator="icarus"``, naming the way out."""
    if state_store not in STATE_STORES:
        raise ValueError(f"--rtl-state-store must be one of {', '.join(STATE_STORES)}, got "
                         f"{state_store!r}")
    chosen = state_store
    if chosen == "auto":
        chosen = "axi" if needs_axi_store(cfg) else "chip"
    if chosen == "axi" and simulator != "verilator":
        if state_store == "auto":
            bits, device = block_ram_bits()
            why = (f"the state of a {cfg.width}x{cfg.height} frame "
                   f"({cfg.width * cfg.height * cfg.state_bits} bits) exceeds the block RAM "
                   f"of the largest device ({device}: {bits} bits), so --rtl keeps it in "
                   f"external memory (AXI4), which only the Verilator harness models; use "
                   f"--rtl-simulator verilator, or --rtl-state-store chip")
        else:
            why = ("--rtl-state-store axi: only the Verilator harness models the AXI4 "
                   "memory; use --rtl-simulator verilator")
        raise ValueError(why)
    return chosen


def run_rtl(frames: np.ndarray, cfg, n_frames: int | None, build_dir: pathlib.Path | None,
            design: str = "segmenter", simulator: str = "verilator", *,
            log: Log = _silent, state_store: str = "chip") -> dict:
    """Simulate the generated Verilog on the first ``n_frames`` frames (None or 0: all);
    raise :class:`RtlError` unless bit-exact.

    ``design="segmenter"``: the whole FPGA stage (``dptbd_seg``: DP pipeline + segmenter),
    every candidate list word checked against the golden models; ``"dp"``: the DP pipeline
    (``dptbd_dp``), every (E, d) word checked. ``simulator``: ``"verilator"``
    (:mod:`dptbd.sim.rtl.check`) or ``"icarus"`` (cocotb, :mod:`dptbd.sim.icarus`).
    ``build_dir`` None: the simulator's default build root. ``log`` receives a line before
    the build and one before the simulation. ``state_store`` (:data:`STATE_STORES`):
    ``"axi"`` simulates ``dptbd_axi`` (``design="segmenter"``: the drop-in core, every
    candidate-list word, flag and counter checked, no AXI4 rule broken on its state port)
    or ``dptbd_dp`` (``"dp"``) built with the AXI4 state store, on Verilator (see the module
    doc); the record's ``state_store`` says which, ``cycles_per_pixel`` the rate.
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
    store = resolve_state_store(cfg, state_store, simulator)
    start = time.perf_counter()
    if store == "axi":
        info = _rtl_verilator_store(frames[:n], cfg, build_dir, design, log)
    elif simulator == "verilator":
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


def _rtl_verilator_store(frames: np.ndarray, cfg, build_dir, design: str, log: Log) -> dict:
    from dptbd.sim import verilator

    root = verilator.default_build_root() if build_dir is None else pathlib.Path(build_dir)
    store = cfg.axi_store()
    log(f"  RTL: building the Verilog for this configuration with the AXI4 state store "
        f"({store.data_bits}-bit, bursts of {store.burst_beats}, {store.outstanding} "
        f"outstanding) on Verilator in {root} …")
    if design == "segmenter":
        from dptbd.sim.axi.stimulus import clean_beats
        from dptbd.sim.verilator.axi import check_axi

        sim = verilator.build(cfg, "axi", root=root, state_store=store)
        log(f"  RTL: build {'from the cache' if sim.cached else 'compiled'} in "
            f"{sim.seconds:.1f} s; simulating {sim.toplevel} on {len(frames)} frames "
            f"({frames.size} pixels) …")
        beats = clean_beats(frames)
        result = check_axi(sim, beats, [{"stop": len(beats)}], memory=dict(latency=(0, 0)))
        run = result.run
        accepted = run.accept_cycles
        last = int(run.out_cycles[-1]) if len(run.out_cycles) else int(accepted[-1])
        info = {"module": sim.toplevel, "passed": result.passed,
                "report": result.board.report() if result.passed else result.report(),
                "words_in": len(beats), "words_compared": int(result.board.count),
                "cycles": last - int(accepted[0]) + 1, "latency": sim.latency,
                "simulated_cycles": int(run.cycles), "sim_seconds": round(run.sim_seconds, 4),
                "cycles_per_second": round(run.cycles_per_second),
                "build_dir": str(sim.directory), "build_seconds": round(sim.seconds, 2),
                "build_cached": sim.cached}
        design = "axi"
    else:
        from dptbd.sim.verilator import dp_axi

        t0 = time.perf_counter()
        sim = dp_axi.build(store, root=root)
        built = time.perf_counter() - t0
        log(f"  RTL: build ready in {built:.1f} s; simulating dptbd_dp on {len(frames)} "
            f"frames ({frames.size} pixels) …")
        run = dp_axi.run(sim, frames)
        r = run.result
        accepted = run.accept_cycles
        violations = int(r["violations"])
        passed = run.bit_exact and not violations and r["status"] == "done"
        if passed:
            report = "bit-exact"
        elif violations:
            report = f"{violations} AXI4 rule violations, the first: {r['first_violation']}"
        elif r["status"] != "done":
            report = f"status {r['status']} after {int(r['cycles'])} cycles"
        else:
            report = f"the first differing (E, d) word is word {run.first_mismatch}"
        seconds = float(r["seconds"])
        info = {"module": "dptbd_dp", "passed": passed, "report": report,
                "words_in": int(frames.size), "words_compared": len(run.outputs),
                "cycles": int(r["cycles"]), "latency": None,
                "simulated_cycles": int(r["cycles"]), "sim_seconds": round(seconds, 4),
                "cycles_per_second": round(r["cycles"] / seconds) if seconds > 0 else None,
                "build_dir": str(sim.directory), "build_seconds": round(built, 2)}
    info.update(simulator="verilator", design=design, state_store="axi",
                memory_latency=0, data_bits=store.data_bits, burst_beats=store.burst_beats,
                outstanding=store.outstanding,
                cycles_per_pixel=round(float(accepted[-1] - accepted[0] + 1) / len(accepted), 4))
    return info


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


_WORDS = {"segmenter": "candidate-list words", "axi": "candidate-list words",
          "dp": "(E, d) words"}


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
                  simulator=check.simulator, log=log, state_store=check.state_store)
    rtl["checked"] = True
    rtl["checked_frames"] = [0, rtl["frames"] - 1]
    rtl["summary"] = rtl_summary(rtl["frames"], frames.shape[0], _module(rtl),
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
    return (f"  RTL: {rtl['report']} — the generated Verilog ({_module(rtl)} on "
            f"{str(rtl.get('simulator', '?')).capitalize()}) matches the golden model on "
            f"{which}: {rtl.get('words_compared')} "
            f"{_WORDS.get(rtl.get('design'), 'words')} compared, {rtl.get('cycles')} "
            f"cycles{speed} ({rtl['seconds']:.1f} s in all)"
            + ("; the model's output is used for the rest" if rtl["frames"] < n_frames
               else "")
            + (f"; {rtl['cycles_per_pixel']:.3f} cycles per pixel with the AXI4 store at "
               f"latency {rtl['memory_latency']}" if rtl.get("state_store") == "axi" else ""))


def _module(rtl: dict) -> str:
    """The simulated module, with ``--state-store axi`` when its state is in AXI4 memory."""
    return rtl["module"] + (" --state-store axi" if rtl.get("state_store") == "axi" else "")
