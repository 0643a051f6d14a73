"""Segments (K = 6, 8) against the recursive DP through the DSP association (issue 15).

    python benchmarks/bench_family_association.py --alpha 0.8 --seeds 40

``dptbd run``'s built-in scenario (two targets, SNR 2.0) on seeds ``--first-seed`` …
``--first-seed + --seeds - 1``, ideal lists (n = 33 per map), the scenario's association.
Variants: segments K = 6 and 8 (stride K), the recursive DP with ``--alpha`` scored every
6 and every 8 frames with paths of 6 resp. 8 frames (as many lists as the segments of that
K). ``--alpha`` is meant to be the one chosen by ``bench_family_detection.py`` on *other*
scenes (Table 1's, seed 1000), not tuned here. Per target: confirmed in how many runs
(95 % Wilson interval), frames until output (mean and median over the confirmed runs),
first-level Pd pooled over the lists; per run: false tracks (mean, runs with at least one).

Library: ``dptbd.evaluation.family_association``. This script reports; it asserts nothing.
"""

from __future__ import annotations

import argparse

import numpy as np

from dptbd.evaluation import family_detection as fd
from dptbd.evaluation.family_association import job_outcome
from dptbd.evaluation.stats import wilson_interval


def _wilson(k: int, n: int) -> str:
    lo, hi = wilson_interval(k, n)
    return f"{k}/{n} [{lo:.2f}, {hi:.2f}]"


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--alpha", type=float, required=True)
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--first-seed", type=int, default=0)
    args = ap.parse_args(argv)
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    variants = [fd.segments(6), fd.recursive(args.alpha, segment_frames=6),
                fd.segments(8), fd.recursive(args.alpha, segment_frames=8)]
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
        print(f"| {name} | | both | {_wilson(both, len(runs))} | | | | |", flush=True)


if __name__ == "__main__":
    main()
