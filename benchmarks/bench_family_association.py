"""Segments (K = 6, 8) against the recursive DP through the DSP association.

    python benchmarks/bench_family_association.py --alpha 0.97 --seeds 40
    python benchmarks/bench_family_association.py --sweep --seeds 40   # alpha from seeds 100-119
    python benchmarks/bench_family_association.py --alpha 0.97 --penalty-sweep 0 16 32 64 128

``dptbd run``'s built-in scenario (two targets, SNR 2.0) on seeds ``--first-seed`` …
``--first-seed + --seeds - 1``, ideal lists (n = 33 per map), the scenario's association.
Variants: segments K = 6 and 8 (stride K), the recursive DP with ``--alpha`` scored every
6 and every 8 frames with paths of 6 resp. 8 frames (as many lists as the segments of that
K). ``--alpha`` is meant to be chosen on *other* scenes: by ``bench_family_detection.py``
(Table 1's, seed 1000, first-level Pd), or with ``--sweep`` on this scenario's seeds
``--tune-first-seed`` … (default 100-119, disjoint from the reported seeds): the alpha with
the most *clean* runs (both targets confirmed, no false track; ties: fewer false tracks),
recursive scoring every 6 frames. ``--zero-move-penalty Q`` subtracts the penalty code Q
(``docs/arithmetic.md`` §8.2) from the zero move of the recursive variants. Per target: confirmed in how many runs
(95 % Wilson interval), frames until output (mean and median over the confirmed runs),
first-level Pd pooled over the lists; per run: false tracks (mean, runs with at least one).

Library: ``dptbd.evaluation.family.association``. This script reports; it asserts nothing.
"""

from __future__ import annotations

import argparse

import numpy as np

from dptbd.evaluation.family import detection as fd
from dptbd.evaluation.family.association import job_outcome
from dptbd.evaluation.stats import wilson_interval


def _wilson(k: int, n: int) -> str:
    lo, hi = wilson_interval(k, n)
    return f"{k}/{n} [{lo:.2f}, {hi:.2f}]"


ALPHAS = (0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95, 0.97)


def _sweep_row(key: str, variant, seeds: range) -> tuple[int, float]:
    runs = [job_outcome(variant, s) for s in seeds]
    both = [all(f is not None for f in r.frames_until_output) for r in runs]
    clean = sum(b and r.false_tracks == 0 for b, r in zip(both, runs))
    false = float(np.mean([r.false_tracks for r in runs]))
    delays = [f for r in runs for f in r.frames_until_output if f is not None]
    print(f"| {key} | {clean}/{len(runs)} | {sum(both)}/{len(runs)} | {false:.2f} | "
          f"{np.mean(delays):.1f} |", flush=True)
    return clean, false


def _sweep_header(what: str, seeds: range) -> None:
    print(f"{what} sweep (built-in scenario, seeds {seeds.start}-{seeds.stop - 1}, lists every "
          f"6 frames):\n")
    print(f"| {what} | clean runs | both confirmed | false tracks per run | "
          "frames until output (confirmed) |")
    print("|---|---|---|---|---|")


def sweep(seeds: range) -> float:
    _sweep_header("alpha", seeds)
    best = None
    for alpha in ALPHAS:
        clean, false = _sweep_row(f"{alpha:g}", fd.recursive(alpha, segment_frames=6), seeds)
        if best is None or (clean, -false) > best[1]:
            best = (alpha, (clean, -false))
    print(f"chosen alpha = {best[0]:g}\n")
    return best[0]


def penalty_sweep(alpha: float, penalties: list[int], seeds: range) -> None:
    _sweep_header(f"zero-move penalty (alpha {alpha:g})", seeds)
    for pen in penalties:
        _sweep_row(str(pen), fd.recursive(alpha, segment_frames=6, zero_move_penalty=pen), seeds)
    print()


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--alpha", type=float, default=None)
    ap.add_argument("--sweep", action="store_true", help="choose alpha on the tuning seeds")
    ap.add_argument("--tune-first-seed", type=int, default=100)
    ap.add_argument("--tune-seeds", type=int, default=20)
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--zero-move-penalty", type=int, default=0,
                    help="penalty code on the zero move of the recursive variants")
    ap.add_argument("--penalty-sweep", type=int, nargs="+", default=None,
                    help="only sweep these zero-move penalties at --alpha on the tuning seeds")
    args = ap.parse_args(argv)
    if args.sweep == (args.alpha is not None):
        ap.error("give exactly one of --alpha and --sweep")
    tune = range(args.tune_first_seed, args.tune_first_seed + args.tune_seeds)
    if args.penalty_sweep:
        penalty_sweep(args.alpha, args.penalty_sweep, tune)
        return
    if args.sweep:
        args.alpha = sweep(tune)
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    pen = args.zero_move_penalty
    variants = [fd.segments(6), fd.recursive(args.alpha, segment_frames=6, zero_move_penalty=pen),
                fd.segments(8), fd.recursive(args.alpha, segment_frames=8, zero_move_penalty=pen)]
    print(f"built-in scenario, seeds {seeds.start}-{seeds.stop - 1}, ideal lists\n")
    print("| variant | lists | target | confirmed [95 %] | frames until output: mean / median "
          "| first-level Pd | false tracks per run | runs with a false track [95 %] |")
    print("|---|---|---|---|---|---|---|---|")
    for v in variants:
        runs = [job_outcome(v, s) for s in seeds]
        name = f"{v.label}, K={v.segment_frames}" if v.forgetting is not None else v.label
        false = np.array([r.false_tracks for r in runs])
        for j in range(len(runs[0].hits)):
            conf = [r.frames_until_output[j] for r in runs if r.frames_until_output[j] is not None]
            det = sum(r.hits[j][0] for r in runs)
            opp = sum(r.hits[j][1] for r in runs)
            delay = f"{np.mean(conf):.1f} / {np.median(conf):g}" if conf else "-"
            tail = (f"{false.mean():.2f} | {_wilson(int((false > 0).sum()), len(runs))}"
                    if j == 0 else " | ")
            print(f"| {name} | {runs[0].maps} | {j + 1} | {_wilson(len(conf), len(runs))} | "
                  f"{delay} | {det / opp:.3f} ({det}/{opp}) | {tail} |", flush=True)
        both = sum(all(f is not None for f in r.frames_until_output) for r in runs)
        clean = sum(all(f is not None for f in r.frames_until_output) and r.false_tracks == 0
                    for r in runs)
        print(f"| {name} | | both | {_wilson(both, len(runs))} | | | clean runs (both, no "
              f"false track): {_wilson(clean, len(runs))} | |", flush=True)


if __name__ == "__main__":
    main()
