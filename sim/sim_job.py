"""The job of ``dptbd sim``: the generated Verilog simulated on a scene (Verilator, or cocotb +
Icarus), checked bit for bit against the golden model, with its cycle count.

:func:`sim_config` and :func:`sim_frames` check the parameters and the scene before anything
is built; :func:`run_sim` builds, simulates and returns a :class:`SimOutcome`;
:func:`summary_lines` are the lines ``dptbd sim`` prints at the end.
"""

from __future__ import annotations

import dataclasses
import pathlib
import shutil
import time
from typing import Callable

import numpy as np

from dptbd.config import DPConfig
from dptbd.errors import ConfigError

__all__ = ["SIMULATORS", "DESIGNS", "MODULES", "SimSettings", "SimOutcome",
           "simulator_tools_missing", "sim_config", "sim_frames", "run_sim", "summary_lines"]

SIMULATORS = ("verilator", "icarus")
DESIGNS = ("dp", "segmenter")
#: design -> top-level module
MODULES = {"dp": "dptbd_dp", "segmenter": "dptbd_seg"}
_OUTPUT = {"dp": "states", "segmenter": "candidate-list words"}
_MODELS = {"dp": "dptbd.model.fixed",
           "segmenter": "dptbd.model.fixed and dptbd.model.segmentation"}


def _silent(line: str) -> None:
    pass


@dataclasses.dataclass(frozen=True)
class SimSettings:
    """How to simulate: design, simulator, stimulus pauses, waveform and build root.

    Attributes
    ----------
    design : {"dp", "segmenter"}
    simulator : {"verilator", "icarus"}
    valid_pause, ready_pause : float
        Probability of an idle input cycle / of output back-pressure per cycle, in [0, 1).
    seed : int
        The pauses' seeds derive from it.
    waves : pathlib.Path or None
        An FST waveform to write.
    build_dir : pathlib.Path or None
        Build root (None: the simulator's default).
    """

    design: str = "dp"
    simulator: str = "verilator"
    valid_pause: float = 0.0
    ready_pause: float = 0.0
    seed: int = 0
    waves: pathlib.Path | None = None
    build_dir: pathlib.Path | None = None

    def check(self) -> None:
        """Refuse pauses outside [0, 1) and a waveform path that is not ``.fst``."""
        for name in ("valid_pause", "ready_pause"):
            p = getattr(self, name)
            if not 0.0 <= p < 1.0:
                raise ValueError(f"--{name.replace('_', '-')} must be in [0, 1), got {p}")
        if self.waves is not None and self.waves.suffix != ".fst":
            raise ValueError(f"--waves {self.waves}: the simulation writes FST; give a path "
                             f"ending in .fst")


@dataclasses.dataclass
class SimOutcome:
    """What a simulation gave: words out, cycles, speed and build lines, verdict.

    ``finished`` is False when the Icarus run ended without a summary (``run_dir`` holds
    its files).
    """

    finished: bool
    passed: bool
    report: str
    outputs: int | None = None
    cycles: int | None = None
    latency: int = 0
    speed: str = ""
    build: str = ""
    run_dir: pathlib.Path | None = None


def simulator_tools_missing(simulator: str, option: str = "--simulator") -> str | None:
    """Why ``simulator`` cannot run here (a sentence naming the missing tool and the other
    simulator, as ``option`` chooses it), or None."""
    if simulator == "verilator":
        from dptbd.sim import verilator

        try:
            verilator.check_tools()
        except verilator.ToolMissingError as exc:
            if option == "--simulator":      # check_tools names `dptbd sim`'s own fallback
                return str(exc)
            return (f"--rtl: {exc}".replace("(dptbd sim --simulator icarus)",
                                             f"({option} icarus)"))
        return None
    missing = [t for t in ("iverilog", "vvp") if shutil.which(t) is None]
    if missing:
        return (f"{option} icarus needs Icarus Verilog ({' and '.join(missing)} not on the "
                f"PATH); install it (bash scripts/setup.sh setup) or use {option} verilator")
    return None


def sim_config(cfg: DPConfig, design: str, candidate_count: int | None = None) -> DPConfig:
    """``cfg`` checked for what ``design`` implements (and ``candidate_count`` set)."""
    from dptbd.hw.schedule import check_supported

    if candidate_count is not None:
        if design != "segmenter":
            raise ValueError("--candidate-count applies to --design segmenter only")
        cfg = cfg.replace(candidate_count=candidate_count)
    check_supported(cfg)                 # e.g. overlapping segments, frames too small
    if design == "segmenter" and cfg.n_candidates == 0:
        # what generate_segmenter_verilog refuses, said here before anything is built
        why = ("" if cfg.candidate_count is not None else
               f" (0.2 % of {cfg.width}x{cfg.height} = {cfg.width * cfg.height} pixels "
               f"rounds to 0)")
        raise ConfigError(
            f"--design segmenter: n = 0 candidate points per segment{why} gives a segmenter "
            f"that emits no points; give --candidate-count 1 … {cfg.width * cfg.height}")
    return cfg


def sim_frames(cfg: DPConfig, *, scene: pathlib.Path | None = None,
               scenario: str = "two-targets", frames: int | None = None,
               seed: int = 0) -> tuple[np.ndarray, str]:
    """The checked frames to simulate and a line describing them: a ``.npy`` scene (its first
    ``frames``) or a built-in scenario (``frames`` of it, default 2 K)."""
    from dptbd.sim.icarus import check_scene
    from dptbd.sim.scenarios import describe, make_frames

    if frames is not None and frames < 1:
        raise ValueError(f"--frames must be an integer in [1, inf), got {frames}")
    if scene is not None:
        if not scene.exists():
            raise FileNotFoundError(f"scene file {scene} does not exist")
        try:
            data = np.load(scene, allow_pickle=False)
        except ValueError as exc:
            raise ValueError(f"{scene} is not a .npy array: {exc}") from exc
        data = check_scene(cfg, data)
        if frames is not None:
            if frames > len(data):
                raise ValueError(f"--frames {frames} but {scene} holds {len(data)} frames")
            data = data[:frames]
        label = f"{scene}"
    else:
        n = frames if frames is not None else 2 * cfg.segment_frames
        data = check_scene(cfg, make_frames(scenario, cfg, n, seed=seed))
        label = f"scenario {scenario} (seed {seed})"
    return data, f"{label}: {describe(data, cfg)}"


def run_sim(cfg: DPConfig, frames: np.ndarray, settings: SimSettings, *,
            log: Callable[[str], None] = _silent) -> SimOutcome:
    """Build ``settings.design`` for ``cfg`` and simulate it on ``frames``; ``log`` receives
    the build lines."""
    if settings.simulator == "verilator":
        return _run_verilator(cfg, frames, settings, log)
    return _run_icarus(cfg, frames, settings, log)


def _run_verilator(cfg, frames, settings: SimSettings, log) -> SimOutcome:
    from dptbd.sim import verilator
    from dptbd.sim.rtl.check import Stimulus, check_frames

    start = time.perf_counter()
    root = (settings.build_dir if settings.build_dir is not None
            else verilator.default_build_root())
    waves = settings.waves is not None
    if waves:
        log("  building with FST tracing (slower to build and to run) …")
    sim = verilator.build(cfg, settings.design, root=root, waves=waves)
    how = "from the cache" if sim.cached else "compiled"
    log(f"  build {sim.directory} {how} in {sim.seconds:.2f} s (latency {sim.latency} cycles)")
    stimulus = Stimulus(valid_gap=settings.valid_pause, ready_pause=settings.ready_pause,
                        seed=settings.seed + 1)
    result = check_frames(sim, frames, stimulus,
                          trace=settings.waves.resolve() if waves else None)
    wall = time.perf_counter() - start
    raw = result.raw
    return SimOutcome(
        finished=True, passed=result.passed, report=result.report, outputs=result.words_out,
        cycles=result.cycles, latency=sim.latency,
        speed=(f"{raw.cycles_per_second / 1e6:.2f} M cycles/s (Verilator: {raw.cycles} "
               f"cycles, drain included, in {raw.sim_seconds:.3g} s; {raw.wall_seconds:.3g} s "
               f"for the run, {wall:.1f} s in all with build and model)"),
        build=f"{how} in {sim.seconds:.2f} s ({sim.directory})")


def _run_icarus(cfg, frames, settings: SimSettings, log) -> SimOutcome:
    from dptbd.sim.icarus import build, simulate

    start = time.perf_counter()
    root = settings.build_dir if settings.build_dir is not None else pathlib.Path("build/sim")
    sim = build(cfg, root, waves=settings.waves is not None, design=settings.design)
    log(f"  built {sim.directory} in {sim.seconds:.1f} s (latency {sim.latency} cycles)")
    pauses = {}
    if settings.valid_pause > 0:
        pauses["valid_pause"] = {"kind": "random", "probability": settings.valid_pause,
                                 "seed": settings.seed + 1}
    if settings.ready_pause > 0:
        pauses["ready_pause"] = {"kind": "random", "probability": settings.ready_pause,
                                 "seed": settings.seed + 2}
    result = simulate(sim, frames, run_name="cli", waves=settings.waves, log_to_file=False,
                      **pauses)
    wall = time.perf_counter() - start
    s = result.summary
    if not s:
        return SimOutcome(finished=False, passed=False, report=result.report,
                          run_dir=result.run_dir)
    if s.get("sim_cycles_per_second"):
        speed = (f"{s['sim_cycles_per_second']:.0f} cycles/s while streaming (Icarus: "
                 f"{s.get('stream_cycles')} cycles in {s.get('stream_seconds', 0):.1f} s; "
                 f"{wall:.1f} s in all with build, start-up and model)")
    else:                                # tb_segmenter: the whole test's simulated cycles
        total, seconds = s.get("sim_cycles_total") or 0, s.get("wall_seconds") or 0
        speed = (f"{total / seconds if seconds else 0:.0f} cycles/s for the whole test "
                 f"(Icarus: {total} cycles in {seconds:.1f} s; {wall:.1f} s in all with "
                 f"build, start-up and model)")
    return SimOutcome(
        finished=True, passed=result.passed, report=result.report, outputs=s.get("outputs"),
        cycles=s.get("cycles"), latency=sim.latency, speed=speed,
        build=(f"{sim.seconds:.1f} s ({sim.directory}; Icarus recompiles only when the "
               f"Verilog changed)"))


def _cycles_note(cfg, frames: np.ndarray, settings: SimSettings, latency: int,
                 cycles: int) -> str:
    """The exact count expected without pauses, when the design promises one."""
    if settings.valid_pause > 0 or settings.ready_pause > 0:
        return ""
    pixels = int(frames.size)
    if settings.design == "dp":
        exact = pixels + latency
        return (f"  (= T*W*H + latency = {pixels} + {latency})" if cycles == exact
                else f"  (!= T*W*H + latency = {exact})")
    # segmenter: whole segments only, a bubble-free stream needs the histogram scan to fit
    # in a segment (tb_segmenter's exact_cycles)
    lists = cfg.n_segments(len(frames))
    exact = lists * cfg.segment_frames * cfg.width * cfg.height + latency + 1
    return (f"  (= S*K*W*H + latency + 1 = {exact - latency - 1} + {latency} + 1)"
            if cycles == exact else f"  (!= S*K*W*H + latency + 1 = {exact})")


def summary_lines(cfg, frames: np.ndarray, settings: SimSettings,
                  outcome: SimOutcome) -> list[str]:
    """The summary ``dptbd sim`` prints: frames, cycles, cycles per pixel, speed, build,
    waveform and verdict."""
    pixels = int(frames.size)
    lines = ["", f"frames simulated        {len(frames)} ({pixels} pixels, {outcome.outputs} "
                 f"{_OUTPUT[settings.design]} out)"]
    if outcome.cycles is not None:
        note = _cycles_note(cfg, frames, settings, outcome.latency, outcome.cycles)
        lines.append(f"simulated cycles        {outcome.cycles} first input to last output{note}")
        lines.append(f"cycles per pixel        {outcome.cycles / pixels:.5f}")
    lines.append(f"simulator speed         {outcome.speed}")
    lines.append(f"build                   {outcome.build}")
    if settings.waves is not None:
        lines.append(f"waveform                {settings.waves.resolve()}")
    verdict = (f"bit-exact against {_MODELS[settings.design]}" if outcome.passed
               else "NOT bit-exact")
    lines.append(f"verdict                 {verdict}: {outcome.report}")
    return lines
