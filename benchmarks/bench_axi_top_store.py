"""Cycles per pixel of the drop-in core ``dptbd_axi`` with its state in external memory
(``dptbd verilog --top axi --state-store axi``) against the memory's latency, on Verilator.

    python benchmarks/bench_axi_top_store.py                  # 640 x 512, 3 frames
    python benchmarks/bench_axi_top_store.py --latency 0 100 500 --outstanding 4 16

The build is ``dptbd.sim.verilator.build(cfg, "axi", state_store=...)``, the AXI harness
with the C++ AXI4 memory model (``sim/harness/axi4_memory.h``): every burst answered after
a fixed latency (cycles from the address handshake to the first read beat, and from the
last write beat to the response), every channel always ready; the input offers a beat in
every cycle and ``m_axis_cand`` always takes. The frames are uniform random pixels.
Reported: cycles from the first to the last accepted pixel over the pixels (1.0 = one
pixel per clock), and whether every list word, flag and counter is the golden model's with
no AXI4 rule broken (:func:`dptbd.sim.verilator.axi.check_axi`). This script only reports.
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
    parser.add_argument("--frames", type=int, default=3)
    parser.add_argument("--latency", type=int, nargs="+", default=[0, 100, 500])
    parser.add_argument("--outstanding", type=int, nargs="+", default=[4, 16])
    parser.add_argument("--data-bits", type=int, default=64)
    parser.add_argument("--burst-beats", type=int, default=16)
    args = parser.parse_args()
    cfg = DPConfig(width=args.width, height=args.height).build_config()
    frames = np.random.default_rng(1).integers(0, 256, size=(args.frames, cfg.height, cfg.width))
    beats = clean_beats(frames)
    print(f"dptbd_axi --state-store axi, {cfg.describe()}, {args.frames} frames, AXI "
          f"{args.data_bits}-bit, bursts of {args.burst_beats} beats, Verilator")
    print("| latency (cycles) | outstanding | cycles per pixel | bit-exact |")
    print("|---|---|---|---|")
    for outstanding in args.outstanding:
        store = cfg.axi_store(data_bits=args.data_bits, burst_beats=args.burst_beats,
                              outstanding=outstanding)
        sim = V.build(cfg, "axi", state_store=store)
        for latency in args.latency:
            result = check_axi(sim, beats, [{"stop": len(beats)}],
                               memory=dict(latency=(latency, latency)))
            accepted = result.run.accept_cycles
            cpp = float(accepted[-1] - accepted[0] + 1) / len(accepted)
            print(f"| {latency} | {outstanding} | {cpp:.3f} | {result.passed} |", flush=True)


if __name__ == "__main__":
    main()
