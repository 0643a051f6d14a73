"""K-frame segments (K = 6, 8) against the recursive DP with a forgetting factor.

    python benchmarks/bench_family_detection.py                  # sweep, then report
    python benchmarks/bench_family_detection.py --alpha 0.95     # report only
    python benchmarks/bench_family_detection.py --alpha 0.97 --pfa 1e-3,1e-4 --roc roc.png
    python benchmarks/bench_family_detection.py --alpha 0.97 --trials 100 --k 6,8,12,16,24,32 \
        --frame-ranges 7-15,64-99 --wake --pfa none --workers 2

1. **Sweep** alpha on the *tuning* scenes (``--tune-seed``, default 1000; ``--tune-trials``
   per Table 1 setting): the alpha with the largest first-level Pd pooled over the six
   settings is chosen (skipped when ``--alpha`` is given).
2. **Report** on *other* scenes (``--seed``, default 2003 = ``dptbd table1``'s seed;
   ``--trials`` per setting): segments of each K of ``--k`` (default 6,8; stride K) and the
   recursive DP with the chosen alpha, each map keeping its n = 33 largest pixels (equal
   list length per map: equal false points up to ties, not an equal false-alarm rate).
   Pd per map pooled with its 95 % Wilson interval (``dptbd.evaluation.stats``; maps of
   one scene are correlated, so that interval is optimistic), and the paired difference
   of per-scene Pd against each segment variant with a 95 % interval over scenes; false
   points per map; maps per scene. ``--frame-ranges 7-15,64-99``: the recursion's Pd per
   map also over the maps of those frames only, and the paired difference last - first.
   ``--wake``: for the first K and the recursion, the probability that the target's pixel
   L frames back (outside the gate of its current pixel) is among a map's 33 largest, per
   lag of ``--wake-lags`` and pooled beyond 12, and the false points within 3 px of the
   last 40 positions (``dptbd.evaluation.family.wake``).
3. **Equal Pfa per pixel** (``--pfa``, default 1e-3,1e-4; ``--pfa none`` skips it): the
   same variants and target scenes, each map thresholded at the level its own noise-only
   maps of the same index exceed on that fraction of pixels
   (``dptbd.evaluation.family.equal_pfa``; noise-only scenes ``--noise-seed`` ..
   ``--noise-seed + --noise-scenes - 1``): threshold, measured noise-only Pfa, Pd per map
   [95 % Wilson], false alarms per map on the target scenes, paired differences. ``--roc
   FILE.png`` draws Pd against Pfa at the levels ``--roc-pfa``. ``--workers`` / ``--scheduler``:
   the execution layer.

Library: ``dptbd.evaluation.family.detection``. This script reports; it asserts nothing.
"""

from __future__ import annotations

import argparse
import pathlib

from dptbd.errors import DptbdError
from dptbd.evaluation.family import detection as fd
from dptbd.evaluation.execution import Execution, map_tasks
from dptbd.evaluation.family import equal_pfa as ep
from dptbd.evaluation.family import wake
from dptbd.evaluation.metrics import DetectionCounts
from dptbd.evaluation.pfa import allowed_false_alarms, check_noise_seeds, figure_roc, parse_pfas
from dptbd.evaluation.stats import wilson_interval

ROC_PFAS = "1e-5,3e-5,1e-4,3e-4,1e-3,3e-3,1e-2"

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


def _range_task(variant, snr, vel, ranges, trials: int, seed: int) -> list:
    return fd.variant_range_counts(variant, snr, vel, ranges=ranges, trials=trials, seed=seed)


def _wake_task(variant, snr, vel, lags, trials: int, seed: int) -> list:
    return wake.wake_counts(variant, snr, vel, lags=lags, trials=trials, seed=seed)


def variants_of(ks: tuple, alpha: float) -> list:
    return [fd.segments(k) for k in ks] + [fd.recursive(alpha)]


def report(alpha: float, seed: int, trials: int, ks: tuple = (6, 8), frame_ranges: tuple = (),
           workers: int = 1, scheduler: str | None = None) -> None:
    variants = variants_of(ks, alpha)
    ranges = ((0, fd.FRAMES - 1),) + tuple(frame_ranges)
    tasks = [(v, snr, vel, ranges if v.forgetting is not None else ranges[:1], trials, seed)
             for v in variants for snr, vel in fd.SETTINGS]
    with Execution(workers=workers, scheduler=scheduler).client() as client:
        results = map_tasks(_range_task, tasks, client)
    labels = [v.label for v in variants]
    res = {name: {} for name in labels}   # {label: {setting: [per-scene [per-range counts]]}}
    for (v, snr, vel, *_), r in zip(tasks, results):
        res[v.label][(snr, tuple(vel))] = r

    def scenes_of(name, i=0):
        return [scene[i] for per in res[name].values() for scene in per]

    def pooled(name, i=0):
        total = DetectionCounts(0, 0, 0, 0)
        for c in scenes_of(name, i):
            total = total + c
        return total

    print(f"report (seed {seed}, {trials} scenes per setting), each map's n = 33 largest pixels, "
          f"Pd per map [95 % Wilson]:")
    print("| setting (SNR, v) | " + " | ".join(labels) + " |")
    print("|---|" + "---|" * len(variants))
    for key in res[labels[0]]:
        snr, vel = key
        cells = []
        for name in labels:
            total = DetectionCounts(0, 0, 0, 0)
            for scene in res[name][key]:
                total = total + scene[0]
            cells.append(_cell(total))
        print(f"| {snr:g}, ({vel[0]:g}, {vel[1]:g}) | " + " | ".join(cells) + " |")
    print("| **pooled** | " + " | ".join(_cell(pooled(n)) for n in labels) + " |")
    print("| false points per map | " + " | ".join(f"{pooled(n).mean_false_points:.1f}"
                                                  for n in labels) + " |")
    n_scenes = len(scenes_of(labels[0]))
    print("| maps per scene | " + " | ".join(f"{pooled(n).frames / n_scenes:g}" for n in labels) + " |")
    rec = scenes_of(labels[-1])
    print()
    for name in labels[:-1]:
        mean, lo, hi = fd.paired_pd_difference(scenes_of(name), rec)
        print(f"* Pd({labels[-1]}) - Pd({name}), paired over {n_scenes} scenes: "
              f"{mean:+.3f} [{lo:+.3f}, {hi:+.3f}]")
    if frame_ranges:
        print(f"\n{labels[-1]}, Pd per map by the map's frame (maps of frames first .. last, "
              f"{n_scenes} scenes):")
        print("| frames | maps | Pd per map [95 % Wilson] | false points per map |")
        print("|---|---|---|---|")
        for i, (lo, hi) in enumerate(ranges):
            c = pooled(labels[-1], i)
            if c.frames:
                print(f"| {max(lo, variants[-1].warmup)}–{hi} | {c.frames} | {_cell(c)} | "
                      f"{c.mean_false_points:.1f} |")
        if len(frame_ranges) >= 2:
            a, b = scenes_of(labels[-1], 1), scenes_of(labels[-1], len(ranges) - 1)
            mean, lo, hi = fd.paired_pd_difference(a, b)
            print(f"\n* Pd(frames {ranges[-1][0]}–{ranges[-1][1]}) - Pd(frames "
                  f"{max(ranges[1][0], variants[-1].warmup)}–{ranges[1][1]}), paired over "
                  f"{n_scenes} scenes: {mean:+.3f} [{lo:+.3f}, {hi:+.3f}]")


def report_wake(alpha: float, seed: int, trials: int, k: int, lags: tuple, workers: int = 1,
                scheduler: str | None = None) -> None:
    variants = [fd.segments(k), fd.recursive(alpha)]
    tasks = [(v, snr, vel, lags, trials, seed) for v in variants for snr, vel in fd.SETTINGS]
    with Execution(workers=workers, scheduler=scheduler).client() as client:
        results = map_tasks(_wake_task, tasks, client)
    total = {}
    for (v, *_), per in zip(tasks, results):
        for c in per:
            total[v.label] = total[v.label] + c if v.label in total else c
    n_scenes = trials * len(fd.SETTINGS)
    print(f"\nwake (seed {seed}, {n_scenes} scenes): P(the target's pixel L frames back, outside "
          f"the gate of its current pixel, is among the map's n = 33 largest):")
    labels = [v.label for v in variants]
    print("| lag L | " + " | ".join(labels) + " |")
    print("|---|" + "---|" * len(labels))
    rows = [(lag, lag) for lag in lags] + ([(13, max(lags))] if max(lags) >= 13 else [])
    for lo, hi in rows:
        cells = []
        for name in labels:
            h, o = total[name].kept(lo, hi)
            cell = f"{h / o:.3f} [{wilson_interval(h, o)[0]:.3f}, {wilson_interval(h, o)[1]:.3f}] " \
                   f"({o})" if o else "–"
            cells.append(cell)
        print(f"| {lo if lo == hi else f'{lo}–{hi}'} | " + " | ".join(cells) + " |")
    print("| false points per map | " + " | ".join(
        f"{total[n].false_points / total[n].maps:.1f}" for n in labels) + " |")
    print("| of them within 3 px of the last 40 positions | " + " | ".join(
        f"{total[n].near_track / total[n].maps:.1f}" for n in labels) + " |")


def report_equal_pfa(alpha: float, seed: int, trials: int, pfas: tuple, noise_seed: int,
                     noise_scenes: int, roc: pathlib.Path | None, roc_pfas: tuple, workers: int,
                     scheduler: str | None, ks: tuple = (6, 8)) -> None:
    variants = variants_of(ks, alpha)
    levels = tuple(sorted(set(pfas) | (set(roc_pfas) if roc else set()), reverse=True))
    noise = range(noise_seed, noise_seed + noise_scenes)
    res = ep.compare_equal_pfa(variants, levels, trials=trials, seed=seed, noise_seeds=noise,
                               workers=workers, scheduler=scheduler)
    labels = res.labels
    n_scenes = len(res.per_scene(labels[0], 0))
    for p in pfas:
        i = levels.index(p)
        print(f"\nequal Pfa {p:g} per pixel (target seed {seed}, {trials} scenes per setting; "
              f"noise-only seeds {noise_seed}..{noise_seed + noise_scenes - 1}, one threshold per "
              f"map index):")
        print("| variant | threshold (first .. last map) | noise-only Pfa | Pd per map [95 %] | "
              "false alarms per map |")
        print("|---|---|---|---|---|")
        for name in labels:
            thr = res.thresholds[name][i]
            c = res.pooled(name, i)
            print(f"| {name} | {thr[0]:g} .. {thr[-1]:g} | {res.measured[name][i]:.2e} | {_cell(c)} | "
                  f"{c.mean_false_points:.1f} |")
        rec = res.per_scene(labels[-1], i)
        for name in labels[:-1]:
            mean, lo, hi = fd.paired_pd_difference(res.per_scene(name, i), rec)
            print(f"\nPd({labels[-1]}) - Pd({name}) at Pfa {p:g}, paired over {n_scenes} scenes: "
                  f"{mean:+.3f} [{lo:+.3f}, {hi:+.3f}]")
    if roc:
        curves = {}
        for name in labels:
            pts = []
            for i, p in enumerate(levels):
                c = res.pooled(name, i)
                lo, hi = wilson_interval(c.detections, c.opportunities)
                pts.append((p, c.pd, lo, hi))
            curves[name] = pts
        figure_roc(curves, roc, title=f"Table 1 settings pooled, {n_scenes} scenes, seed {seed}")
        print(f"\nwrote {roc}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tune-seed", type=int, default=1000)
    ap.add_argument("--tune-trials", type=int, default=10)
    ap.add_argument("--seed", type=int, default=2003)
    ap.add_argument("--trials", type=int, default=20)
    ap.add_argument("--alpha", type=float, default=None, help="skip the sweep")
    ap.add_argument("--k", default="6,8",
                    help="segment lengths K next to the recursion, comma-separated (default 6,8)")
    ap.add_argument("--frame-ranges", default=None,
                    help="the recursion's Pd per map also by the map's frame, e.g. 7-15,64-99")
    ap.add_argument("--wake", action="store_true",
                    help="the wake of the first K and the recursion: P(past position kept) by lag")
    ap.add_argument("--wake-lags", default="1-40", help="lags of --wake (default 1-40)")
    ap.add_argument("--pfa", default="1e-3,1e-4",
                    help="false-alarm probabilities per pixel of the equal-Pfa report, or none")
    ap.add_argument("--noise-seed", type=int, default=ep.NOISE_SEED,
                    help=f"first noise-only scene's seed (default {ep.NOISE_SEED})")
    ap.add_argument("--noise-scenes", type=int, default=10, help="noise-only scenes (default 10)")
    ap.add_argument("--roc", type=pathlib.Path, default=None, help="write the ROC figure (PNG) here")
    ap.add_argument("--roc-pfa", default=ROC_PFAS, help=f"ROC levels (default {ROC_PFAS})")
    ap.add_argument("--workers", type=int, default=1, help="local worker processes (default 1)")
    ap.add_argument("--scheduler", default=None, help="tcp://HOST:PORT of a dask cluster")
    args = ap.parse_args(argv)
    try:  # every refusal before any run
        pfas = () if args.pfa == "none" else parse_pfas(args.pfa)
        ks = fd.parse_segment_lengths(args.k)
        frame_ranges = () if args.frame_ranges is None else fd.parse_frame_ranges(args.frame_ranges)
        lags = wake.parse_lags(args.wake_lags)
        roc_pfas = parse_pfas(args.roc_pfa)
        if args.alpha is not None:
            fd.recursive(args.alpha)
        check_noise_seeds(range(args.noise_seed, args.noise_seed + args.noise_scenes))
        for p in pfas + (roc_pfas if args.roc else ()):  # one threshold per map index
            allowed_false_alarms(p, args.noise_scenes * 128 * 128)
    except DptbdError as exc:
        ap.error(str(exc))
    if args.roc is not None and args.roc.suffix != ".png":
        ap.error(f"--roc must name a .png file, got {args.roc}")
    alpha = sweep(args.tune_seed, args.tune_trials) if args.alpha is None else args.alpha
    report(alpha, args.seed, args.trials, ks, frame_ranges, args.workers, args.scheduler)
    if args.wake:
        report_wake(alpha, args.seed, args.trials, ks[0], lags, args.workers, args.scheduler)
    if pfas or args.roc:
        report_equal_pfa(alpha, args.seed, args.trials, pfas, args.noise_seed, args.noise_scenes,
                         args.roc, roc_pfas, args.workers, args.scheduler, ks)


if __name__ == "__main__":
    main()
