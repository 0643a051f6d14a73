"""``dptbd sim``: simulate the generated Verilog on a scene, check it bit for bit against the
golden model, and report the cycle count.

Two simulators (``--simulator``):

``verilator`` (default)
    The Verilog compiled by Verilator with the C++ harness (:mod:`dptbd.sim.verilator`):
    the whole scene streamed in one call and every output word compared with the golden
    model (:mod:`dptbd.sim.rtl_check`). 001's 128 x 128, 100-frame scene takes well under a
    second once built; builds are cached (``--build-dir``, default
    :func:`dptbd.sim.verilator.default_build_root`), and the summary says whether this one
    came from the cache. 2-state: X propagation is Icarus' job.
``icarus``
    cocotb 2.x + Icarus (:mod:`dptbd.sim.runner`), 4-state, one log line per frame as the
    scoreboard confirms it; minutes for the 128 x 128 scene. Build root ``build/sim``.

``--design`` picks the module: ``dp`` (``dptbd_dp``, every (E, d) word checked) or
``segmenter`` (``dptbd_seg``, the DP pipeline plus the segmenter: every candidate-list word
checked against :mod:`dptbd.model.fixed` and :mod:`dptbd.model.segmentation`).

The scene is a built-in scenario (:mod:`dptbd.sim.scenarios`) or a ``.npy`` of integer
frames ``(T, H, W)``. Everything is checked before anything is built: the parameters
(DPConfig and what the gateware implements), the pause densities, the scene's frame size
against W x H, its pixels against B_in, the LUT's shape, and that the simulator's tools are
installed (a missing Verilator or C++ compiler is named, with ``--simulator icarus`` as the
fallback; exit 2). At the end the command prints the simulated cycles from the first
accepted pixel to the last output (``T*W*H + latency`` exactly for ``dp`` when there are no
input gaps and no output back-pressure), cycles per pixel, the simulator's speed, the build
time and the verdict (exit 1 on a mismatch, with the first mismatching word).
"""

from __future__ import annotations

import argparse
import pathlib
import shutil
import sys
import time

import numpy as np

from dptbd.commands.verilog import add_config_arguments, config_from_args

SIMULATORS = ("verilator", "icarus")
DESIGNS = ("dp", "segmenter")
_MODULES = {"dp": "dptbd_dp", "segmenter": "dptbd_seg"}
_OUTPUT = {"dp": "states", "segmenter": "candidate-list words"}
_MODELS = {"dp": "dptbd.model.fixed",
           "segmenter": "dptbd.model.fixed and dptbd.model.segmentation"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from dptbd.sim.scenarios import SCENARIOS

    scene = parser.add_argument_group("scene")
    scene.add_argument("--scenario", choices=SCENARIOS, default="two-targets",
                       help="built-in scene (default two-targets: paper 001's second "
                            "experiment, scaled to W x H)")
    scene.add_argument("--scene", type=pathlib.Path, metavar="FILE.npy",
                       help="integer frames (T, H, W) to simulate instead of a scenario")
    scene.add_argument("--frames", type=int, default=None,
                       help="frames to simulate (default 2 K for a scenario, all of --scene)")
    scene.add_argument("--seed", type=int, default=0, help="scene and pause seed (default 0)")
    add_config_arguments(parser)
    run = parser.add_argument_group("simulation")
    run.add_argument("--simulator", choices=SIMULATORS, default="verilator",
                     help="verilator (default: compiled, cached builds, 128 x 128 x 100 frames "
                          "in under a second) or icarus (cocotb + Icarus, 4-state, per-frame "
                          "progress, minutes for the same scene)")
    run.add_argument("--design", choices=DESIGNS, default="dp",
                     help="dp (default: the DP pipeline dptbd_dp, every (E, d) word checked) or "
                          "segmenter (dptbd_seg: DP pipeline + segmenter, every candidate-list "
                          "word checked)")
    run.add_argument("--candidate-count", type=int, default=None, metavar="N",
                     help="segmenter: candidate points per segment n (default 0.2 %% of W x H, "
                          "which is 0 below 250 pixels: set it for small frames)")
    run.add_argument("--valid-pause", type=float, default=0.0, metavar="P",
                     help="probability of an idle input cycle (default 0)")
    run.add_argument("--ready-pause", type=float, default=0.0, metavar="P",
                     help="probability of output back-pressure per cycle (default 0)")
    run.add_argument("--waves", type=pathlib.Path, metavar="FILE.fst",
                     help="write an FST waveform (GTKWave, Surfer); a separate build with "
                          "tracing compiled in")
    run.add_argument("--build-dir", type=pathlib.Path, default=None, metavar="DIR",
                     help="build root, one directory per parameter set (default: Verilator "
                          "$DPTBD_BUILD_DIR/verilator or ~/.cache/dptbd/verilator, shared by "
                          "every checkout; Icarus build/sim)")


def _scene(args: argparse.Namespace, cfg) -> tuple[np.ndarray, str]:
    from dptbd.sim.runner import check_scene
    from dptbd.sim.scenarios import describe, make_frames

    if args.frames is not None and args.frames < 1:
        raise ValueError(f"--frames must be >= 1, got {args.frames}")
    if args.scene is not None:
        if not args.scene.exists():
            raise FileNotFoundError(f"scene file {args.scene} does not exist")
        try:
            frames = np.load(args.scene, allow_pickle=False)
        except ValueError as exc:
            raise ValueError(f"{args.scene} is not a .npy array: {exc}") from exc
        frames = check_scene(cfg, frames)
        if args.frames is not None:
            if args.frames > len(frames):
                raise ValueError(f"--frames {args.frames} but {args.scene} holds "
                                 f"{len(frames)} frames")
            frames = frames[: args.frames]
        label = f"{args.scene}"
    else:
        n = args.frames if args.frames is not None else 2 * cfg.segment_frames
        frames = check_scene(cfg, make_frames(args.scenario, cfg, n, seed=args.seed))
        label = f"scenario {args.scenario} (seed {args.seed})"
    return frames, f"{label}: {describe(frames, cfg)}"


def _config(args: argparse.Namespace):
    """The DPConfig, checked for what the chosen design implements."""
    from dptbd.config import ConfigError
    from dptbd.hw.schedule import check_supported

    cfg = config_from_args(args)
    if args.candidate_count is not None:
        if args.design != "segmenter":
            raise ValueError("--candidate-count applies to --design segmenter only")
        cfg = cfg.replace(candidate_count=args.candidate_count)
    check_supported(cfg)                 # e.g. overlapping segments, frames too small
    if args.design == "segmenter" and cfg.n_candidates == 0:
        # what generate_segmenter_verilog refuses, said here before anything is built
        why = ("" if cfg.candidate_count is not None else
               f" (0.2 % of {cfg.width}x{cfg.height} = {cfg.width * cfg.height} pixels "
               f"rounds to 0)")
        raise ConfigError(
            f"--design segmenter: n = 0 candidate points per segment{why} gives a segmenter "
            f"that emits no points; give --candidate-count 1 … {cfg.width * cfg.height}")
    return cfg


def _tools_missing(simulator: str) -> str | None:
    """Why the simulator cannot run here, or None."""
    if simulator == "verilator":
        from dptbd.sim import verilator

        try:
            verilator.check_tools()
        except verilator.ToolMissingError as exc:
            return str(exc)
        return None
    missing = [t for t in ("iverilog", "vvp") if shutil.which(t) is None]
    if missing:
        return (f"--simulator icarus needs Icarus Verilog ({' and '.join(missing)} not on the "
                f"PATH); install it (bash scripts/setup.sh setup) or use --simulator verilator")
    return None


def _cycles_note(args, cfg, frames: np.ndarray, latency: int, cycles: int) -> str:
    """The exact count expected without pauses, when the design promises one."""
    if args.valid_pause > 0 or args.ready_pause > 0:
        return ""
    pixels = int(frames.size)
    if args.design == "dp":
        exact = pixels + latency
        return (f"  (= T*W*H + latency = {pixels} + {latency})" if cycles == exact
                else f"  (!= T*W*H + latency = {exact})")
    # segmenter: whole segments only, a bubble-free stream needs the histogram scan to fit
    # in a segment (tb_segmenter's exact_cycles)
    lists = cfg.n_segments(len(frames))
    exact = lists * cfg.segment_frames * cfg.width * cfg.height + latency + 1
    return (f"  (= S*K*W*H + latency + 1 = {exact - latency - 1} + {latency} + 1)"
            if cycles == exact else f"  (!= S*K*W*H + latency + 1 = {exact})")


def main(args: argparse.Namespace) -> int:
    # ---- refuse bad input before anything is built or simulated -------------------
    for name in ("valid_pause", "ready_pause"):
        p = getattr(args, name)
        if not 0.0 <= p < 1.0:
            raise ValueError(f"--{name.replace('_', '-')} must be in [0, 1), got {p}")
    if args.waves is not None and args.waves.suffix != ".fst":
        raise ValueError(f"--waves {args.waves}: the simulation writes FST; give a path "
                         f"ending in .fst")
    cfg = _config(args)
    frames, scene_text = _scene(args, cfg)
    why = _tools_missing(args.simulator)
    if why is not None:
        print(f"dptbd sim: error: {why}", file=sys.stderr)
        return 2

    print(f"dptbd sim: {cfg.width}x{cfg.height}, K={cfg.segment_frames}, B_in={cfg.input_bits}, "
          f"B_E={cfg.energy_bits}, F={cfg.weight_frac_bits}, r={cfg.radius}, {cfg.rounding}"
          + (f", n={cfg.n_candidates}, C={cfg.record_capacity}"
             if args.design == "segmenter" else ""))
    print(f"  {scene_text}")
    print(f"  {_MODULES[args.design]} on {args.simulator.capitalize()}", flush=True)
    if args.simulator == "verilator":
        return _run_verilator(args, cfg, frames)
    return _run_icarus(args, cfg, frames)


def _print_summary(args, cfg, frames, *, outputs, cycles, latency, speed, build, passed,
                   report) -> None:
    pixels = int(frames.size)
    print()
    print(f"frames simulated        {len(frames)} ({pixels} pixels, {outputs} "
          f"{_OUTPUT[args.design]} out)")
    if cycles is not None:
        note = _cycles_note(args, cfg, frames, latency, cycles)
        print(f"simulated cycles        {cycles} first input to last output{note}")
        print(f"cycles per pixel        {cycles / pixels:.5f}")
    print(f"simulator speed         {speed}")
    print(f"build                   {build}")
    if args.waves is not None:
        print(f"waveform                {args.waves.resolve()}")
    verdict = f"bit-exact against {_MODELS[args.design]}" if passed else "NOT bit-exact"
    print(f"verdict                 {verdict}: {report}")


def _run_verilator(args, cfg, frames) -> int:
    from dptbd.sim import verilator
    from dptbd.sim.rtl_check import Stimulus, check_frames

    start = time.perf_counter()
    root = args.build_dir if args.build_dir is not None else verilator.default_build_root()
    waves = args.waves is not None
    if waves:
        print("  building with FST tracing (slower to build and to run) …", flush=True)
    sim = verilator.build(cfg, args.design, root=root, waves=waves)
    how = "from the cache" if sim.cached else "compiled"
    print(f"  build {sim.directory} {how} in {sim.seconds:.2f} s (latency {sim.latency} "
          f"cycles)", flush=True)
    stimulus = Stimulus(valid_gap=args.valid_pause, ready_pause=args.ready_pause,
                        seed=args.seed + 1)
    result = check_frames(sim, frames, stimulus,
                          trace=args.waves.resolve() if waves else None)
    wall = time.perf_counter() - start
    raw = result.raw
    _print_summary(
        args, cfg, frames, outputs=result.words_out, cycles=result.cycles,
        latency=sim.latency,
        speed=(f"{raw.cycles_per_second / 1e6:.2f} M cycles/s (Verilator: {raw.cycles} "
               f"cycles, drain included, in {raw.sim_seconds:.3g} s; {raw.wall_seconds:.3g} s "
               f"for the run, {wall:.1f} s in all with build and model)"),
        build=f"{how} in {sim.seconds:.2f} s ({sim.directory})",
        passed=result.passed, report=result.report)
    return 0 if result.passed else 1


def _run_icarus(args, cfg, frames) -> int:
    from dptbd.sim.runner import build, simulate

    start = time.perf_counter()
    root = args.build_dir if args.build_dir is not None else pathlib.Path("build/sim")
    sim = build(cfg, root, waves=args.waves is not None, design=args.design)
    print(f"  built {sim.directory} in {sim.seconds:.1f} s (latency {sim.latency} cycles)",
          flush=True)
    pauses = {}
    if args.valid_pause > 0:
        pauses["valid_pause"] = {"kind": "random", "probability": args.valid_pause,
                                 "seed": args.seed + 1}
    if args.ready_pause > 0:
        pauses["ready_pause"] = {"kind": "random", "probability": args.ready_pause,
                                 "seed": args.seed + 2}
    result = simulate(sim, frames, run_name="cli", waves=args.waves, log_to_file=False,
                      **pauses)
    wall = time.perf_counter() - start
    s = result.summary
    if not s:
        print(f"dptbd sim: the simulation did not finish (see the simulator output above; "
              f"run files in {result.run_dir})")
        return 1
    if s.get("sim_cycles_per_second"):
        speed = (f"{s['sim_cycles_per_second']:.0f} cycles/s while streaming (Icarus: "
                 f"{s.get('stream_cycles')} cycles in {s.get('stream_seconds', 0):.1f} s; "
                 f"{wall:.1f} s in all with build, start-up and model)")
    else:                                # tb_segmenter: the whole test's simulated cycles
        total, seconds = s.get("sim_cycles_total") or 0, s.get("wall_seconds") or 0
        speed = (f"{total / seconds if seconds else 0:.0f} cycles/s for the whole test "
                 f"(Icarus: {total} cycles in {seconds:.1f} s; {wall:.1f} s in all with "
                 f"build, start-up and model)")
    _print_summary(args, cfg, frames, outputs=s.get("outputs"), cycles=s.get("cycles"),
                   latency=sim.latency, speed=speed,
                   build=f"{sim.seconds:.1f} s ({sim.directory}; Icarus recompiles only "
                         f"when the Verilog changed)",
                   passed=result.passed, report=result.report)
    return 0 if result.passed else 1
