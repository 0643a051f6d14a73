"""K-frame segments (K = 6, 8) against the recursive DP with a forgetting factor.

    python benchmarks/bench_family_detection.py                  # sweep, then report
    python benchmarks/bench_family_detection.py --alpha 0.95     # report only

1. **Sweep** alpha on the *tuning* scenes (``--tune-seed``, default 1000; ``--tune-trials``
   per Table 1 setting): the alpha with the largest first-level Pd pooled over the six
   settings is chosen (skipped when ``--alpha`` is given).
2. **Report** on *other* scenes (``--seed``, default 2003 = ``dptbd table1``'s seed;
   ``--trials`` per setting): segments K = 6 and K = 8 (stride K) and the recursive DP with
   the chosen alpha, each map keeping its n = 33 largest pixels (equal false points per map).
   Pd per map pooled with its 95 % Wilson interval (``dptbd.evaluation.stats``; maps of
   one scene are correlated, so that interval is optimistic), and the paired difference
   of per-scene Pd against each segment variant with a 95 % interval over scenes; false
   points per map; maps per scene.

Library: ``dptbd.evaluation.family.detection``. This script reports; it asserts nothing.
"""

from __future__ import annotations

import argparse

from dptbd.evaluation.family import detection as fd
from dptbd.evaluation.metrics import DetectionCounts
from dptbd.evaluation.stats import wilson_interval

ALPHAS = (0.5, 0.7, 0.8, 0.85, 0.9, 0.95, 0.97, 0.98, 0.99)


def _pooled(per_setting: dict) -> DetectionCounts:
    total = DetectionCounts(0, 0, 0, 0)
    for scenes in per_setting.values():
        for counts in scenes:
            total = total + counts
    return total


def _cell(c: DetectionCounts) -> str:
    lo, hi = wilson_interval(c.detections, c.opportunities)
    return f"{c.pd:.3f} [{lo:.3f}, {hi:.3f}]"


def sweep(tune_seed: int, tune_trials: int) -> float:
    res = fd.compare([fd.recursive(a) for a in ALPHAS], trials=tune_trials, seed=tune_seed)
    print(f"alpha sweep (seed {tune_seed}, {tune_trials} scenes per setting, pooled):")
    print("| alpha | Pd per map [95 %] | false points per map |")
    print("|---|---|---|")
    best = None
    for alpha, per in zip(ALPHAS, res.values()):
        c = _pooled(per)
        print(f"| {alpha:g} | {_cell(c)} | {c.mean_false_points:.1f} |", flush=True)
        if best is None or c.pd > best[1]:
            best = (alpha, c.pd)
    print(f"chosen alpha = {best[0]:g}\n")
    return best[0]


def report(alpha: float, seed: int, trials: int) -> None:
    variants = [fd.segments(6), fd.segments(8), fd.recursive(alpha)]
    res = fd.compare(variants, trials=trials, seed=seed)
    labels = [v.label for v in variants]
    print(f"report (seed {seed}, {trials} scenes per setting), Pd per map [95 % Wilson]:")
    print("| setting (SNR, v) | " + " | ".join(labels) + " |")
    print("|---|" + "---|" * len(variants))
    for key in res[labels[0]]:
        snr, vel = key
        cells = []
        for name in labels:
            total = DetectionCounts(0, 0, 0, 0)
            for c in res[name][key]:
                total = total + c
            cells.append(_cell(total))
        print(f"| {snr:g}, ({vel[0]:g}, {vel[1]:g}) | " + " | ".join(cells) + " |")
    pooled = {name: _pooled(res[name]) for name in labels}
    print("| **pooled** | " + " | ".join(_cell(pooled[n]) for n in labels) + " |")
    print("| false points per map | " + " | ".join(f"{pooled[n].mean_false_points:.1f}"
                                                  for n in labels) + " |")
    n_scenes = sum(len(v) for v in res[labels[0]].values())
    print("| maps per scene | " + " | ".join(f"{pooled[n].frames / n_scenes:g}" for n in labels) + " |")
    rec = [c for key in res[labels[2]] for c in res[labels[2]][key]]
    for name in labels[:2]:
        seg = [c for key in res[name] for c in res[name][key]]
        mean, lo, hi = fd.paired_pd_difference(seg, rec)
        print(f"\nPd({labels[2]}) - Pd({name}), paired over {n_scenes} scenes: "
              f"{mean:+.3f} [{lo:+.3f}, {hi:+.3f}]")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tune-seed", type=int, default=1000)
    ap.add_argument("--tune-trials", type=int, default=10)
    ap.add_argument("--seed", type=int, default=2003)
    ap.add_argument("--trials", type=int, default=20)
    ap.add_argument("--alpha", type=float, default=None, help="skip the sweep")
    args = ap.parse_args(argv)
    alpha = sweep(args.tune_seed, args.tune_trials) if args.alpha is None else args.alpha
    report(alpha, args.seed, args.trials)


if __name__ == "__main__":
    main()
