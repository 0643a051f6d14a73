"""Simulation speed of the DP pipeline: cocotb + Icarus against the Amaranth simulator.

Both simulators run the same scene through the same design (``DPPipeline``; Icarus runs the
Verilog that ``dptbd.hw.flow.verilog`` generates from it) with the input always valid and the
output always ready, and both results are checked bit for bit against the golden model.
Reported: simulated clock cycles per wall-clock second while streaming, and the wall time
in all (Icarus: Verilog generation + compilation + simulator start-up + run).

    python benchmarks/bench_sim.py                      # 32x24, K=4, 12 frames, both
    python benchmarks/bench_sim.py --width 64 --height 64 --frames 4
    python benchmarks/bench_sim.py --paper001 --frames 3   # 001's scene on the RTL only
    python benchmarks/bench_sim.py --paper001              # all 100 frames (about 6 min)

``--paper001`` streams paper 001's second experiment (128 x 128, two targets, SNR 2.0,
12-bit ADC, K = 8, B_E = 16) through the RTL and reports the cycle count and wall time.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
import time

import numpy as np

from dptbd.config import DPConfig
from dptbd.sim.icarus import build, simulate
from dptbd.sim.scenarios import make_frames
from dptbd.sim.scoreboard import expected_words


def amaranth_run(cfg: DPConfig, frames: np.ndarray) -> dict:
    """Stream ``frames`` through ``DPPipeline`` in ``amaranth.sim``; time it, check it."""
    from amaranth.sim import Simulator

    from dptbd.hw.dp_pipeline import DPPipeline
    from dptbd.hw.layouts import pack_pixel

    dut = DPPipeline(cfg)
    words = [pack_pixel(cfg, int(p), i % (cfg.width * cfg.height) == 0)
             for i, p in enumerate(frames.ravel())]
    outputs: list[int] = []
    state = {"cycles": 0}
    payload_in = dut.pixels.payload.as_value()
    payload_out = dut.states.payload.as_value()

    async def bench(ctx):
        accepted, cycle = 0, 0
        ctx.set(dut.states.ready, 1)
        ctx.set(dut.pixels.valid, 1)
        ctx.set(payload_in, words[0])
        limit = len(words) * 2 + 1000
        while len(outputs) < len(words) and cycle < limit:
            taken = accepted < len(words) and ctx.get(dut.pixels.ready)
            if ctx.get(dut.states.valid):
                outputs.append(ctx.get(payload_out))
            await ctx.tick()                   # the transfers happen at this edge
            cycle += 1
            if taken:
                accepted += 1
                if accepted < len(words):
                    ctx.set(payload_in, words[accepted])
                else:
                    ctx.set(dut.pixels.valid, 0)
        state["cycles"] = cycle

    sim = Simulator(dut)
    sim.add_clock(1e-8)
    sim.add_testbench(bench)
    start = time.perf_counter()
    sim.run()
    seconds = time.perf_counter() - start
    expected = [int(w) for w in expected_words(cfg, frames).ravel()]
    return {"cycles": state["cycles"], "seconds": seconds,
            "cycles_per_second": state["cycles"] / seconds,
            "bit_exact": [int(o) for o in outputs] == expected}


def icarus_run(cfg: DPConfig, frames: np.ndarray, root: pathlib.Path, name: str,
               log_to_file: bool = True) -> dict:
    start = time.perf_counter()
    sim = build(cfg, root)
    result = simulate(sim, frames, run_name=name, log_to_file=log_to_file)
    total = time.perf_counter() - start
    s = result.summary
    return {"cycles": s.get("cycles"), "stream_cycles": s.get("stream_cycles"),
            "seconds": s.get("stream_seconds"), "cycles_per_second": s.get("sim_cycles_per_second"),
            "build_seconds": sim.seconds, "total_seconds": total, "latency": sim.latency,
            "bit_exact": result.passed, "report": result.report}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--width", type=int, default=32)
    parser.add_argument("--height", type=int, default=24)
    parser.add_argument("--segment-frames", type=int, default=4)
    parser.add_argument("--frames", type=int, default=None,
                        help="frames (default 12; with --paper001: 100)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--paper001", action="store_true",
                        help="paper 001's 128x128 two-target scene through the RTL only")
    parser.add_argument("--skip-amaranth", action="store_true")
    parser.add_argument("--build-dir", type=pathlib.Path, default=pathlib.Path("build/sim"))
    parser.add_argument("--json", type=pathlib.Path, help="also write the figures here")
    args = parser.parse_args(argv)

    if args.paper001:
        from dptbd.evaluation.table1.experiment import INPUT_BITS

        cfg = DPConfig(width=128, height=128, segment_frames=8, input_bits=INPUT_BITS,
                       energy_bits=16)
        n = 100 if args.frames is None else args.frames
        frames = make_frames("two-targets", cfg, n, seed=args.seed)
        print(f"paper 001 scene: 128x128, {n} frames, K=8, B_in={INPUT_BITS}, B_E=16 "
              f"({frames.size} pixels) through cocotb + Icarus", flush=True)
        r = icarus_run(cfg, frames, args.build_dir, f"paper001-{n}", log_to_file=False)
        print(f"cycles first input to last output  {r['cycles']} "
              f"(T*W*H + latency = {frames.size} + {r['latency']} = {frames.size + r['latency']})")
        print(f"wall time                          {r['total_seconds']:.1f} s in all, "
              f"{r['seconds']:.1f} s streaming ({r['seconds'] / n:.2f} s per frame, "
              f"{r['cycles_per_second']:.0f} cycles/s)")
        print(f"verdict                            "
              f"{'bit-exact' if r['bit_exact'] else 'NOT bit-exact'}: {r['report']}")
        figures = {"paper001": r, "frames": n}
    else:
        cfg = DPConfig(width=args.width, height=args.height, segment_frames=args.segment_frames)
        n = 12 if args.frames is None else args.frames
        frames = make_frames("mixed", cfg, n, seed=args.seed)
        print(f"scene: {cfg.width}x{cfg.height}, K={cfg.segment_frames}, {n} frames "
              f"({frames.size} pixels), input always valid, output always ready", flush=True)
        icarus = icarus_run(cfg, frames, args.build_dir, "bench")
        figures = {"icarus": icarus}
        rows = [("cocotb + Icarus", icarus)]
        if not args.skip_amaranth:
            figures["amaranth"] = amaranth_run(cfg, frames)
            rows.append(("amaranth.sim", figures["amaranth"]))
        print(f"{'simulator':<18} {'cycles':>8} {'cycles/s':>10} {'run s':>8} {'all s':>8}  check")
        for label, r in rows:
            print(f"{label:<18} {r.get('stream_cycles', r['cycles']):>8} "
                  f"{r['cycles_per_second']:>10.0f} {r['seconds']:>8.2f} "
                  f"{r.get('total_seconds', r['seconds']):>8.2f}  "
                  f"{'bit-exact' if r['bit_exact'] else 'MISMATCH'}")
        if "amaranth" in figures:
            ratio = icarus["cycles_per_second"] / figures["amaranth"]["cycles_per_second"]
            print(f"Icarus/Amaranth speed ratio: {ratio:.2f}")
    if args.json is not None:
        args.json.write_text(json.dumps(figures, indent=2) + "\n")
    ok = all(v.get("bit_exact", True) for v in figures.values() if isinstance(v, dict))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
