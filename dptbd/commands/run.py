"""``dptbd run``: the main job on the built-in scenario.

Paper 001's second experiment (128 x 128, 100 frames, SNR 2.0, two targets) through the
FPGA stage (the bit-accurate golden model) and histogram segmentation; prints the
first-level detection table in the form of 001's Table 1. (The DSP association stage,
figures and output folder come with the end-to-end issue.)
"""

from __future__ import annotations

import argparse

import numpy as np

from dptbd.config import DPConfig
from dptbd.model import scenes
from dptbd.model.metrics import first_level_counts
from dptbd.model.segmentation import candidate_mask, count_for_rate
from dptbd.model.table1 import ADC_GAIN, FALSE_ALARM_RATE, INPUT_BITS


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--seed", type=int, default=0, help="scene seed (default 0)")
    parser.add_argument("--snr", type=float, default=2.0, help="SNR as paper 001 defines it (default 2.0)")
    parser.add_argument("--segment-frames", type=int, default=6, metavar="K", help="frames per segment (default 6)")
    parser.add_argument("--segment-stride", type=int, default=None, metavar="S",
                        help="frames between segment starts (default K: what the gateware does)")


def main(args: argparse.Namespace) -> int:
    cfg = DPConfig(width=128, height=128, segment_frames=args.segment_frames,
                   segment_stride=args.segment_stride, input_bits=INPUT_BITS, energy_bits=16)
    scene = scenes.paper001_two_targets(snr=args.snr, seed=args.seed)
    frames = scene.quantised(INPUT_BITS, gain=ADC_GAIN)
    try:
        from dptbd.model.fast import run_fixed_fast as run
    except ImportError:  # pragma: no cover
        from dptbd.model.fixed import run_fixed as run
    out = run(frames, cfg)
    count = count_for_rate(FALSE_ALARM_RATE, cfg.width * cfg.height)
    masks = candidate_mask(out.energy, count)
    print(f"paper 001 experiment 2: 128x128, {scene.n_frames} frames, SNR {args.snr}, "
          f"K = {cfg.segment_frames}, stride {cfg.segment_stride}, {count} candidate points per "
          f"accumulated frame (0.2 %), seed {args.seed}")
    print("| target | start | V | accumulated frames | first-level detections | Pd | mean false points |")
    print("|---|---|---|---|---|---|---|")
    for i, (target, truth) in enumerate(zip(scene.targets, scene.truth)):
        pixel = truth.pixel[out.end_frames][:, None]
        others = [t for j, t in enumerate(scene.truth) if j != i]
        c = first_level_counts(masks, pixel, truth.visible[out.end_frames][:, None])
        # false points: far from every target, not only this one
        every = np.stack([t.pixel[out.end_frames] for t in [truth, *others]], axis=1)
        vis = np.stack([t.visible[out.end_frames] for t in [truth, *others]], axis=1)
        false = first_level_counts(masks, every, vis).mean_false_points
        print(f"| {i + 1} | ({target.start[0]:g}, {target.start[1]:g}) | "
              f"({target.velocity[0]:g}, {target.velocity[1]:g}) | {c.frames} | {c.detections} | "
              f"{c.pd:.2f} | {false:.1f} |")
    return 0
