"""``dptbd sim``: simulate the generated Verilog on a scene (cocotb + Icarus), check it bit
for bit against the golden model, and report the cycle count.

The scene is a built-in scenario (:mod:`dptbd.sim.scenarios`) or a ``.npy`` of integer
frames ``(T, H, W)``. Everything is checked before the simulator starts: the parameters
(DPConfig and what the gateware implements), the scene's frame size against W x H, its
pixels against B_in, the LUT's shape. The simulation logs one line per frame as the
scoreboard confirms it; at the end the command prints the simulated cycles from the first
accepted pixel to the last output, cycles per pixel (``T*W*H + latency`` exactly when
there are no input gaps and no output back-pressure) and the verdict.
"""

from __future__ import annotations

import argparse
import pathlib
import time

import numpy as np

from dptbd.commands.verilog import add_config_arguments, config_from_args


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
    run.add_argument("--valid-pause", type=float, default=0.0, metavar="P",
                     help="probability of an idle input cycle (default 0)")
    run.add_argument("--ready-pause", type=float, default=0.0, metavar="P",
                     help="probability of output back-pressure per cycle (default 0)")
    run.add_argument("--waves", type=pathlib.Path, metavar="FILE.fst",
                     help="write an FST waveform (GTKWave, Surfer)")
    run.add_argument("--build-dir", type=pathlib.Path, default=pathlib.Path("build/sim"),
                     help="build root; one directory per parameter set (default build/sim)")


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


def main(args: argparse.Namespace) -> int:
    from dptbd.hw.schedule import check_supported
    from dptbd.sim.runner import build, simulate

    # ---- refuse bad input before anything is built or simulated -------------------
    for name in ("valid_pause", "ready_pause"):
        p = getattr(args, name)
        if not 0.0 <= p < 1.0:
            raise ValueError(f"--{name.replace('_', '-')} must be in [0, 1), got {p}")
    if args.waves is not None and args.waves.suffix != ".fst":
        raise ValueError(f"--waves {args.waves}: Icarus under cocotb writes FST; give a "
                         f"path ending in .fst")
    cfg = config_from_args(args)
    check_supported(cfg)                 # e.g. overlapping segments, frames too small
    frames, scene_text = _scene(args, cfg)

    print(f"dptbd sim: {cfg.width}x{cfg.height}, K={cfg.segment_frames}, B_in={cfg.input_bits}, "
          f"B_E={cfg.energy_bits}, F={cfg.weight_frac_bits}, r={cfg.radius}, {cfg.rounding}")
    print(f"  {scene_text}")
    start = time.perf_counter()
    sim = build(cfg, args.build_dir, waves=args.waves is not None)
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
    pixels = int(frames.size)
    cycles = s.get("cycles")
    print()
    print(f"frames simulated        {s.get('frames')} ({pixels} pixels, {s.get('outputs')} "
          f"states out)")
    if cycles is not None:
        exact = pixels + sim.latency
        note = ""
        if not pauses:
            note = (f"  (= T*W*H + latency = {pixels} + {sim.latency})" if cycles == exact
                    else f"  (!= T*W*H + latency = {exact})")
        print(f"simulated cycles        {cycles} first input to last output{note}")
        print(f"cycles per pixel        {cycles / pixels:.5f}")
    print(f"simulator speed         {s.get('sim_cycles_per_second') or 0:.0f} cycles/s while "
          f"streaming ({s.get('stream_cycles')} cycles in {s.get('stream_seconds', 0):.1f} s; "
          f"{wall:.1f} s in all with build, start-up and model)")
    if args.waves is not None:
        print(f"waveform                {args.waves.resolve()}")
    verdict = "bit-exact against dptbd.model.fixed" if result.passed else "NOT bit-exact"
    print(f"verdict                 {verdict}: {result.report}")
    return 0 if result.passed else 1
