"""Cycles per pixel of the drop-in core ``dptbd_axi`` at P = 1, 2 and 4 pixels per clock
(``dptbd verilog --top axi --pixels-per-clock P``, on-chip state store), on Verilator.

    python benchmarks/bench_axi_wide.py                       # 640 x 512, 4 frames, P = 1 2 4
    python benchmarks/bench_axi_wide.py --pixels-per-clock 2 --frames 8

The build is ``dptbd.sim.verilator.build(cfg, "axi")`` (the AXI harness; at P > 1 a beat
of P pixels, :func:`dptbd.sim.verilator.axi.wide_beat_words`); the input offers a beat in
every cycle and ``m_axis_cand`` always takes. The frames are uniform random pixels.
Reported: cycles from the first to the last accepted beat over the pixels (1/P = P pixels
per clock; the goal is at most 1/P + 1 %), and whether every list word, flag and counter is
the golden model's (:func:`dptbd.sim.verilator.axi.check_axi`), with the lists and records
scored. This script only reports.
"""

from __future__ import annotations

import argparse

import numpy as np

from dptbd.config import DPConfig
from dptbd.sim import verilator as V
from dptbd.sim.axi.stimulus import clean_beats
from dptbd.sim.verilator.axi import check_axi


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=512)
    parser.add_argument("--frames", type=int, default=4)
    parser.add_argument("--pixels-per-clock", type=int, nargs="+", default=[1, 2, 4])
    args = parser.parse_args()
    print(f"dptbd_axi {args.width}x{args.height}, {args.frames} frames of uniform random "
          f"pixels, Verilator")
    print("| P | cycles per pixel | goal (1/P + 1 %) | bit-exact | lists (records) |")
    print("|---|---|---|---|---|")
    for p in args.pixels_per_clock:
        cfg = DPConfig(width=args.width, height=args.height, pixels_per_clock=p).build_config()
        frames = np.random.default_rng(1).integers(0, cfg.pixel_max + 1,
                                                   size=(args.frames, cfg.height, cfg.width))
        beats = clean_beats(frames)
        sim = V.build(cfg, "axi")
        result = check_axi(sim, beats, [{"stop": len(beats)}])
        accepted = result.run.accept_cycles[::p]
        cpp = float(accepted[-1] - accepted[0] + 1) / len(beats)
        board = result.board
        print(f"| {p} | {cpp:.4f} | {1 / p * 1.01:.4f} | {result.passed} | "
              f"{len(board.lists)} ({board.records_expected}) |", flush=True)


if __name__ == "__main__":
    main()
