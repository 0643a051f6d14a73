"""Compiled RTL simulation (Verilator) against cocotb + Icarus, measured in one run.

1. **Same design, same stimulus**: ``dptbd_dp`` (``DPPipeline``) streams one scene with the
   input always valid and the output always ready on cocotb + Icarus and on the Verilator
   harness; both checked bit for bit; reported: simulated cycles per second while
   streaming and the ratio.
2. **Paper 001's scene through the whole FPGA stage** (``dptbd_seg``: DP + segmenter,
   128 x 128, 100 frames, 12-bit ADC, K = 8, B_E = 16): a build from an empty cache (the
   runtime library compiled too), a build with only the runtime cached (another parameter
   set built before), a cached build, and the run (simulation loop, and the whole run with
   process start-up and file I/O; the golden model's check is reported separately).
3. **The same scene through ``dptbd_dp``** (1 638 400 state words, every one checked).
4. **The C++ compiler** (``--compilers``, instead of 1–3): each of
   :data:`~dptbd.sim.verilator.toolchain.COMPILERS` installed, as ``$CXX``, builds
   ``dptbd_seg`` and ``dptbd_dp`` (128 x 128, as in 2.) and ``dptbd_axi`` 16 x 12 in a cache of
   its own with its runtime library compiled first; reported: each build's seconds, the
   scene's simulation loop through ``dptbd_seg`` and ``dptbd_dp`` (best of three), and the
   ratios to the first compiler's.

    python benchmarks/bench_verilator.py                 # 64 x 64, 4 frames for the ratio
    python benchmarks/bench_verilator.py --width 32 --height 24 --frames 12
    python benchmarks/bench_verilator.py --compilers
"""

from __future__ import annotations

import argparse
import os
import shutil
import pathlib
import sys
import tempfile
import time

from dptbd.config import DPConfig
from dptbd.sim import icarus, verilator
from dptbd.sim.verilator import toolchain
from dptbd.sim.rtl.check import check_frames
from dptbd.sim.scenarios import make_frames


def ratio_run(cfg: DPConfig, frames, icarus_root: pathlib.Path) -> dict:
    sim = icarus.build(cfg, icarus_root)
    ic = icarus.simulate(sim, frames, run_name="bench")
    vb = verilator.build(cfg, "dp")
    vr = check_frames(vb, frames)
    return {"icarus": ic.summary.get("sim_cycles_per_second") or 0.0,
            "icarus_ok": ic.passed, "icarus_cycles": ic.cycles,
            "verilator": vr.cycles_per_second, "verilator_ok": vr.passed,
            "verilator_cycles": vr.cycles}


def paper001(root: pathlib.Path) -> None:
    cfg = DPConfig(width=128, height=128, segment_frames=8, input_bits=12, energy_bits=16)
    frames = make_frames("two-targets", cfg, 100, seed=0)
    warm = DPConfig(width=16, height=12)
    first = verilator.build(cfg, "segmenter", root=root / "empty")
    verilator.build(warm, "dp", root=root / "warm")
    second = verilator.build(cfg, "segmenter", root=root / "warm")
    cached = verilator.build(cfg, "segmenter", root=root / "warm")
    print(f"dptbd_seg 128x128 build: {first.seconds:.2f} s from an empty cache, "
          f"{second.seconds:.2f} s with the runtime library cached, {cached.seconds:.3f} s "
          f"cached ({'from the cache' if cached.cached else 'REBUILT'})")
    for design in ("segmenter", "dp"):
        sim = verilator.build(cfg, design, root=root / "warm")
        start = time.perf_counter()
        result = check_frames(sim, frames)
        total = time.perf_counter() - start
        raw = result.raw
        print(f"paper 001 scene through {sim.toplevel}: {raw.cycles} cycles simulated, "
              f"{raw.sim_seconds:.3f} s simulation loop ({raw.cycles_per_second / 1e6:.2f} M "
              f"cycles/s), {raw.wall_seconds:.3f} s run with start-up and file I/O, "
              f"{total:.2f} s with the golden model's check; first input to last output "
              f"{result.cycles}; {result.report}")


def compilers(root: pathlib.Path) -> None:
    cfg = DPConfig(width=128, height=128, segment_frames=8, input_bits=12, energy_bits=16)
    frames = make_frames("two-targets", cfg, 100, seed=0)
    small = DPConfig(width=16, height=12)
    first = None
    saved = os.environ.get("CXX")
    try:
        seen = set()
        for name in toolchain.COMPILERS:
            path = shutil.which(name)
            if path is None or os.path.realpath(path) in seen:     # c++: g++ on Debian
                continue
            seen.add(os.path.realpath(path))
            os.environ["CXX"] = name
            toolchain.check_tools.cache_clear()
            where = root / name
            verilator.build(small, "dp", root=where)              # the runtime library
            row = {}
            for label, c, design in (("seg", cfg, "segmenter"), ("dp", cfg, "dp"),
                                     ("axi", small, "axi")):
                sim = verilator.build(c, design, root=where)
                row[f"{label} build"] = sim.seconds
                if label != "axi":
                    runs = [check_frames(sim, frames) for _ in range(3)]
                    assert all(r.passed for r in runs), runs[0].report
                    row[f"{label} M cycles/s"] = max(r.raw.cycles_per_second for r in runs) / 1e6
            first = first or row
            print(f"{name} ({toolchain.check_tools()['c++']}): " + ", ".join(
                f"{k} {v:.2f}" + ("" if row is first else f" ({v / first[k]:.2f}x)")
                for k, v in row.items()), flush=True)
    finally:
        if saved is None:
            os.environ.pop("CXX", None)
        else:
            os.environ["CXX"] = saved
        toolchain.check_tools.cache_clear()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--width", type=int, default=64)
    parser.add_argument("--height", type=int, default=64)
    parser.add_argument("--frames", type=int, default=4)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--compilers", action="store_true",
                        help="only the C++ compilers' build and simulation speeds")
    args = parser.parse_args(argv)
    if args.compilers:
        with tempfile.TemporaryDirectory() as tmp:
            compilers(pathlib.Path(tmp))
        return 0
    cfg = DPConfig(width=args.width, height=args.height, segment_frames=4)
    frames = make_frames("two-targets", cfg, args.frames, seed=3)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        for i in range(args.repeat):
            r = ratio_run(cfg, frames, tmp / "icarus")
            print(f"run {i + 1}: {args.width}x{args.height}, {args.frames} frames, "
                  f"{r['verilator_cycles']} cycles: cocotb + Icarus {r['icarus']:.0f} cycles/s "
                  f"({'bit-exact' if r['icarus_ok'] else 'FAILED'}), Verilator "
                  f"{r['verilator'] / 1e6:.2f} M cycles/s "
                  f"({'bit-exact' if r['verilator_ok'] else 'FAILED'}), ratio "
                  f"{r['verilator'] / max(r['icarus'], 1e-9):.0f}x", flush=True)
        paper001(tmp)
    return 0


if __name__ == "__main__":
    sys.exit(main())
