"""Throughput of the fixed-point model: the plain numpy reference against the fused kernel.

    python benchmarks/bench_model.py                    # 640 x 512, K = 4, r = 1, paper LUT
    python benchmarks/bench_model.py --radius 2 --json out.json
    python benchmarks/bench_model.py --lut random       # a LUT the binary kernel cannot take

Reported, all measured in the same run:

* the **reference pass**: ``np.add(E, np.uint32(1), out=E)`` on the ``uint32`` H x W state
  array, i.e. one numpy pass that reads and writes every state word once; its median over
  many repeats, sampled between the model runs so both see the same machine load;
* **pixel updates per second** of ``dptbd.model.fixed.run_fixed`` (plain numpy) and
  ``dptbd.model.fast.run_fixed_fast`` (numba; with the default thread count and with one
  thread). A *frame update* is one frame of one whole segment: S * K per trial (the K - 1
  DP steps of a segment and its start frame, E = x); a pixel update is a frame update of
  one pixel. ``per DP step`` counts only the S * (K - 1) steps;
* **passes per frame update**: the median time of one frame update over the reference pass;
* **batched vs single**: the time per trial of one call on a batch of B trials
  ``(B, T, H, W)`` against B calls on single trials ``(T, H, W)`` (ratio <= 1: batching
  costs nothing per trial).

Times are medians of ``--repeats`` runs after a warm-up call (which also absorbs numba's
JIT compilation). The target is <= 12 passes per frame update and a batched
per-trial time no larger than the single one; this script only reports, it asserts nothing.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # no BLAS spin-threads beside the timing

import argparse  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numba  # noqa: E402
import numpy as np  # noqa: E402

from dptbd.config import DPConfig
from dptbd.weights import plain_weights  # noqa: E402
from dptbd.model.fast import kernel_path, run_fixed_fast  # noqa: E402
from dptbd.model.fixed import run_fixed  # noqa: E402


class RefPass:
    """The reference pass, sampled in blocks between the measurements of the models."""

    def __init__(self, height: int, width: int, block: int):
        self.state = np.zeros((height, width), dtype=np.uint32)
        self.one = np.uint32(1)
        self.block = block
        self.samples: list[float] = []      # wall seconds
        self.cpu_samples: list[float] = []  # CPU seconds of this thread

    def sample(self) -> None:
        state, one = self.state, self.one
        for _ in range(self.block):
            c0, t0 = time.thread_time(), time.perf_counter()
            np.add(state, one, out=state)
            t1, c1 = time.perf_counter(), time.thread_time()
            self.samples.append(t1 - t0)
            self.cpu_samples.append(c1 - c0)

    @property
    def median(self) -> float:
        return float(np.median(self.samples))

    @property
    def cpu_median(self) -> float:
        return float(np.median(self.cpu_samples))


def timed(fn, repeats: int, ref: RefPass) -> tuple[list[float], list[float]]:
    """Wall and calling-thread CPU times of ``repeats`` calls of ``fn`` after one warm-up.

    The reference pass is sampled between the calls.
    """
    fn()
    times, cpu = [], []
    for _ in range(repeats):
        ref.sample()
        c0, t0 = time.thread_time(), time.perf_counter()
        fn()
        t1, c1 = time.perf_counter(), time.thread_time()
        times.append(t1 - t0)
        cpu.append(c1 - c0)
    ref.sample()
    return times, cpu


def make_config(args) -> DPConfig:
    n_moves = (2 * args.radius + 1) ** 2
    weights = {"paper": None, "plain": plain_weights(args.radius),
               "random": np.random.default_rng(1).random((n_moves + 1, n_moves))}[args.lut]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a narrow --energy-bits saturates by design
        return DPConfig(width=args.width, height=args.height, segment_frames=args.segment_frames,
                        input_bits=args.input_bits, energy_bits=args.energy_bits,
                        weight_frac_bits=args.frac_bits, radius=args.radius,
                        rounding=args.rounding, weights=weights)


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=512)
    ap.add_argument("--frames", type=int, default=32, help="T of the fast runs (default 32)")
    ap.add_argument("--plain-frames", type=int, default=8,
                    help="T of the (slow) plain numpy runs (default 8)")
    ap.add_argument("--segment-frames", type=int, default=4, help="K (default 4)")
    ap.add_argument("--radius", type=int, default=1, choices=(1, 2))
    ap.add_argument("--lut", default="paper", choices=("paper", "plain", "random"))
    ap.add_argument("--input-bits", type=int, default=8)
    ap.add_argument("--energy-bits", type=int, default=16)
    ap.add_argument("--frac-bits", type=int, default=8)
    ap.add_argument("--rounding", default="truncate", choices=("truncate", "half_up"))
    ap.add_argument("--batch", type=int, default=4, help="B of the batched runs (default 4)")
    ap.add_argument("--repeats", type=int, default=7, help="timed runs per measurement")
    ap.add_argument("--plain-repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=None,
                    help="threads of the fast kernel (default: numba.get_num_threads())")
    ap.add_argument("--json", metavar="PATH", help="also write the figures as JSON ('-': stdout)")
    args = ap.parse_args(argv)

    cfg = make_config(args)
    threads = numba.get_num_threads() if args.threads is None else args.threads
    h, w, k = cfg.height, cfg.width, cfg.segment_frames
    rng = np.random.default_rng(0)
    top = cfg.pixel_max + 1
    frames = rng.integers(0, top, (args.frames, h, w)).astype(np.uint16)
    batch = rng.integers(0, top, (args.batch, args.frames, h, w)).astype(np.uint16)
    load_before = os.getloadavg()
    ref = RefPass(h, w, block=50)

    def per_frame(measured: tuple[list[float], list[float]], n_frames: int,
                  trials: int = 1) -> dict:
        times, cpu = measured
        n_seg = cfg.n_segments(n_frames)
        med = float(np.median(times))
        frame_updates = trials * n_seg * k
        return {"median_s": med, "min_s": float(np.min(times)), "frame_updates": frame_updates,
                "s_per_frame_update": med / frame_updates,
                "s_per_dp_step": med / (trials * n_seg * (k - 1)) if k > 1 else None,
                "pixel_updates_per_s": frame_updates * h * w / med,
                "cpu_s_per_frame_update": float(np.median(cpu)) / frame_updates}

    # plain numpy reference model
    plain_frames = frames[:args.plain_frames]
    plain = per_frame(timed(lambda: run_fixed(plain_frames, cfg), args.plain_repeats, ref),
                      args.plain_frames)
    # fast kernel: default threads and one thread
    fast = per_frame(timed(lambda: run_fixed_fast(frames, cfg, threads=threads), args.repeats,
                           ref), args.frames)
    fast1 = per_frame(timed(lambda: run_fixed_fast(frames, cfg, threads=1), args.repeats, ref),
                      args.frames)
    # batched vs single trials (fast kernel, default threads)
    batched = per_frame(timed(lambda: run_fixed_fast(batch, cfg, threads=threads),
                              args.repeats, ref), args.frames, args.batch)

    def singles():
        for b in range(args.batch):
            run_fixed_fast(batch[b], cfg, threads=threads)
    single = per_frame(timed(singles, args.repeats, ref), args.frames, args.batch)

    t_ref = ref.median
    for entry in (plain, fast, fast1, batched, single):
        entry["passes_per_frame_update"] = entry["s_per_frame_update"] / t_ref
        entry["passes_per_dp_step"] = (entry["s_per_dp_step"] / t_ref
                                       if entry["s_per_dp_step"] else None)
    # single-threaded runs only: CPU time of the calling thread, immune to time slicing
    for entry in (plain, fast1):
        entry["cpu_passes_per_frame_update"] = entry["cpu_s_per_frame_update"] / ref.cpu_median
    result = {
        "config": {"width": w, "height": h, "segment_frames": k, "segment_stride":
                   cfg.segment_stride, "radius": cfg.radius, "lut": args.lut,
                   "input_bits": cfg.input_bits, "energy_bits": cfg.energy_bits,
                   "weight_frac_bits": cfg.weight_frac_bits, "rounding": cfg.rounding,
                   "frames": args.frames, "plain_frames": args.plain_frames,
                   "batch": args.batch, "repeats": args.repeats},
        "kernel_path": kernel_path(cfg),
        "machine": {"cpus": os.cpu_count(), "numba_threads": threads,
                    "numba": numba.__version__, "numpy": np.__version__,
                    "python": platform.python_version(), "processor": platform.processor(),
                    "loadavg_before": load_before, "loadavg_after": os.getloadavg()},
        "reference_pass": {"what": "np.add(E, np.uint32(1), out=E), E uint32 (H, W)",
                           "median_s": t_ref, "min_s": float(np.min(ref.samples)),
                           "cpu_median_s": ref.cpu_median, "samples": len(ref.samples)},
        "plain_numpy": plain,
        "fast": fast,
        "fast_1_thread": fast1,
        "fast_batched": batched,
        "fast_singles": single,
        "batched_over_single_per_trial": batched["median_s"] / single["median_s"],
        "speedup_fast_over_plain": plain["s_per_frame_update"] / fast["s_per_frame_update"],
    }
    report(result)
    if args.json:
        text = json.dumps(result, indent=2)
        if args.json == "-":
            print(text)
        else:
            with open(args.json, "w") as fh:
                fh.write(text + "\n")
    return result


def report(res: dict) -> None:
    c, m = res["config"], res["machine"]
    print(f"dptbd model throughput: {c['width']}x{c['height']}, K={c['segment_frames']} "
          f"(stride {c['segment_stride']}), r={c['radius']}, {c['lut']} LUT, "
          f"B_in={c['input_bits']}, B_E={c['energy_bits']}, F={c['weight_frac_bits']}, "
          f"{c['rounding']}; fast kernel: {res['kernel_path']}")
    print(f"machine: {m['cpus']} CPUs, numba {m['numba']} with {m['numba_threads']} threads, "
          f"load average {m['loadavg_before'][0]:.2f} -> {m['loadavg_after'][0]:.2f}")
    r = res["reference_pass"]
    print(f"reference pass {r['what']}: {r['median_s'] * 1e6:.1f} us "
          f"(median of {r['samples']}, min {r['min_s'] * 1e6:.1f} us)")
    print(f"{'':34s}{'per frame update':>18s}{'pixel updates/s':>17s}"
          f"{'passes/frame upd.':>19s}{'passes/DP step':>16s}")
    rows = [("plain numpy (run_fixed)", res["plain_numpy"]),
            (f"fast, {m['numba_threads']} thread(s)", res["fast"]),
            ("fast, 1 thread", res["fast_1_thread"]),
            (f"fast, batch of {c['batch']}", res["fast_batched"]),
            (f"fast, {c['batch']} single trials", res["fast_singles"])]
    for name, e in rows:
        step = f"{e['passes_per_dp_step']:16.1f}" if e["passes_per_dp_step"] else f"{'-':>16s}"
        print(f"{name:34s}{e['s_per_frame_update'] * 1e3:15.3f} ms{e['pixel_updates_per_s']:17.3g}"
              f"{e['passes_per_frame_update']:19.1f}{step}")
    b, s = res["fast_batched"], res["fast_singles"]
    print(f"per trial: batch of {c['batch']} {b['median_s'] / c['batch'] * 1e3:.1f} ms, "
          f"single {s['median_s'] / c['batch'] * 1e3:.1f} ms "
          f"-> batched/single = {res['batched_over_single_per_trial']:.3f}")
    print(f"fast over plain: {res['speedup_fast_over_plain']:.0f}x per frame update")
    print(f"thread CPU time (insensitive to other load), passes per frame update: plain "
          f"{res['plain_numpy']['cpu_passes_per_frame_update']:.1f}, fast 1 thread "
          f"{res['fast_1_thread']['cpu_passes_per_frame_update']:.1f} "
          f"(reference pass {r['cpu_median_s'] * 1e6:.1f} us CPU)")
    print("frame update = one frame of one whole segment (S*K per trial); times are medians "
          f"of {c['repeats']} runs after a warm-up")


if __name__ == "__main__":
    main(sys.argv[1:])
