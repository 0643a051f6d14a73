"""``dptbd sim``: simulate the generated Verilog on a scene, check it bit for bit against the
golden model, and report the cycle count.

Two simulators (``--simulator``):

``verilator`` (default)
    The Verilog compiled by Verilator with the C++ harness (:mod:`dptbd.sim.verilator`):
    the whole scene streamed in one call and every output word compared with the golden
    model (:mod:`dptbd.sim.rtl.check`). 001's 128 x 128, 100-frame scene takes well under a
    second once built; builds are cached (``--build-dir``, default
    :func:`dptbd.sim.verilator.default_build_root`), and the summary says whether this one
    came from the cache. 2-state: X propagation is Icarus' job.
``icarus``
    cocotb 2.x + Icarus (:mod:`dptbd.sim.icarus`), 4-state, one log line per frame as the
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
import functools
import pathlib
import sys

from dptbd.commands.options import add_config_arguments, add_simulator_arguments, config_from_args
from dptbd.sim.sim_job import (DESIGNS, MODULES, SimSettings, run_sim, sim_config,
                                      sim_frames, simulator_tools_missing, summary_lines)


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
    add_simulator_arguments(run)
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


def main(args: argparse.Namespace) -> int:
    # ---- refuse bad input before anything is built or simulated -------------------
    settings = SimSettings(design=args.design, simulator=args.simulator,
                           valid_pause=args.valid_pause, ready_pause=args.ready_pause,
                           seed=args.seed, waves=args.waves, build_dir=args.build_dir)
    settings.check()
    cfg = sim_config(config_from_args(args), args.design, args.candidate_count)
    frames, scene_text = sim_frames(cfg, scene=args.scene, scenario=args.scenario,
                                    frames=args.frames, seed=args.seed)
    why = simulator_tools_missing(args.simulator)
    if why is not None:
        print(f"dptbd sim: error: {why}", file=sys.stderr)
        return 2

    print(f"dptbd sim: {cfg.describe()}"
          + (f", n={cfg.n_candidates}, C={cfg.record_capacity}"
             if args.design == "segmenter" else ""))
    print(f"  {scene_text}")
    print(f"  {MODULES[args.design]} on {args.simulator.capitalize()}", flush=True)
    outcome = run_sim(cfg, frames, settings, log=functools.partial(print, flush=True))
    if not outcome.finished:
        print(f"dptbd sim: the simulation did not finish (see the simulator output above; "
              f"run files in {outcome.run_dir})")
        return 1
    for line in summary_lines(cfg, frames, settings, outcome):
        print(line)
    return 0 if outcome.passed else 1
