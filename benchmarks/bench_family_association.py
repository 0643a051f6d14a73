"""Segments (K = 6, 8) against the recursive DP through the DSP association.

    python benchmarks/bench_family_association.py --alpha 0.97 --seeds 40
    python benchmarks/bench_family_association.py --sweep --seeds 40   # alpha from seeds 100-119
    python benchmarks/bench_family_association.py --alpha 0.97 --penalty-sweep 0 16 32 64 128
    python benchmarks/bench_family_association.py --alpha 0.7 --false-tracks
    python benchmarks/bench_family_association.py --alpha 0.7 --list-swaps --workers 2

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

``--false-tracks`` (``dptbd.evaluation.family.false_tracks``) asks what makes the false
tracks, recursive scoring every 6 frames: (1) on the reported seeds, every false track of
segments K = 6, of the recursion, and of the recursion with *independent* lists (list s
from a recursion over its own noise: the lists' correlation removed) classified as on
target, wake or elsewhere, with its hits in consecutive lists chained by one DP path; (2)
on the same seeds without the targets (every confirmed track false), false tracks per run
against the distinct candidates per list (those left by the association's cluster
suppression) at the list lengths ``--seg-counts`` and ``--rec-counts``; (3) on the first
``--descent-seeds`` of them, how often a list's candidate descends (its DP path, one move
after the earlier list) from a candidate ``--descent-lags`` frames earlier.

``--list-swaps`` (``dptbd.evaluation.family.list_swaps``) asks which property of a list
makes the false tracks at equal distinct-candidate density: on the same seeds without the
targets, segments K = 6 at ``--seg-counts`` and the recursion at ``--rec-counts`` (the
lengths that cross their distinct candidates), each replayed through the association with
one property replaced (the lists' positions made uniform or translated, headings zeroed,
random or taken from the other variant, energies replaced by ranks, every other recursive
list from another seed): false tracks, how far the tracks got
(hits reached), and the lists' geometry (pairs of distinct candidates by Chebyshev distance,
the image within the seed gate of one); seeds on Dask (``--workers``, ``--scheduler``).

Library: ``dptbd.evaluation.family.association``. This script reports; it asserts nothing.
"""

from __future__ import annotations

import argparse

import numpy as np

from dptbd.errors import DptbdError, check_int
from dptbd.evaluation.family import detection as fd
from dptbd.evaluation.family import false_tracks as ft
from dptbd.evaluation.family import list_swaps as lsw
from dptbd.evaluation.family.association import job_outcome, job_run
from dptbd.evaluation.family.list_swaps import PAIR_TOP, SWAPS
from dptbd.evaluation.family.wake import parse_lags
from dptbd.evaluation.execution import Execution, map_tasks
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


def _counts(name: str, text: str) -> list[int]:
    """``"33,43"`` -> list lengths, each an integer in [1, 128] (the DSP's input buffer)."""
    try:
        out = [int(v) for v in text.split(",")]
    except ValueError:
        raise DptbdError(f"{name} must be comma-separated integers in [1, 128], got {text!r}") from None
    return [check_int(f"{name}[{i}]", n, 1, 128) for i, n in enumerate(out)]


def false_track_report(alpha: float, seeds: range, seg_counts: list[int], rec_counts: list[int],
                       descent_seeds: int, lags: tuple[int, ...]) -> None:
    rec = fd.recursive(alpha, segment_frames=6)
    variants = [("segments K=6", fd.segments(6), "recursion"),
                (f"recursive alpha={alpha:g}, lists every 6", rec, "recursion"),
                (f"recursive alpha={alpha:g}, independent lists", rec, "independent")]
    print(f"False tracks by kind (built-in scenario, seeds {seeds.start}-{seeds.stop - 1}, ideal "
          "lists of n = 33):\n")
    print("| variant | false tracks (per run) | runs with one [95 %] | on target | wake | elsewhere "
          "| chained pairs / pairs | one DP path (every pair chained) / tracks with a pair | "
          "median step (px per list) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, v, lists in variants:
        per_run = [ft.false_tracks(job_run(v, s, lists=lists)) for s in seeds]
        tracks = [t for r in per_run for t in r]
        kinds = [sum(t.kind == k for t in tracks) for k in ft.KINDS]
        paired = [t for t in tracks if t.pairs]
        one_path = sum(t.chained == t.pairs for t in paired)
        step = np.median([t.step for t in tracks]) if tracks else float("nan")
        print(f"| {name} | {len(tracks)} ({len(tracks) / len(per_run):.2f}) | "
              f"{_wilson(sum(bool(r) for r in per_run), len(per_run))} | {kinds[0]} | {kinds[1]} | "
              f"{kinds[2]} | {sum(t.chained for t in tracks)}/{sum(t.pairs for t in tracks)} | "
              f"{one_path}/{len(paired)} | {step:g} |", flush=True)
    print("\nNoise only (the same seeds without the targets: every confirmed track is false):\n")
    print("| variant | list length n | distinct candidates per list | tracks started per list | "
          "false tracks (per run) | runs with one [95 %] |")
    print("|---|---|---|---|---|---|")
    rows = [("segments K=6", fd.segments(6), "recursion", n) for n in seg_counts]
    rows += [(f"recursive alpha={alpha:g}", rec, "recursion", n) for n in rec_counts]
    rows += [(f"recursive alpha={alpha:g}, independent lists", rec, "independent", 33)]
    totals = []
    for name, v, lists, n in rows:
        runs = [job_run(v, s, noise_only=True, lists=lists, count=n) for s in seeds]
        st = [r.result.stats for r in runs]
        lists_ = sum(x["segments"] for x in st)
        distinct = sum(x["candidates"] - x["suppressed"] for x in st) / lists_
        started = sum(x["started"] for x in st) / lists_
        false = [r.evaluation.false_tracks for r in runs]
        totals.append((f"{name}, n = {n} ({distinct:.1f} distinct)", sum(false)))
        print(f"| {name} | {n} | {distinct:.1f} | {started:.1f} | {sum(false)} "
              f"({np.mean(false):.2f}) | {_wilson(sum(f > 0 for f in false), len(runs))} |",
              flush=True)
    print("\nRatios of false tracks (95 % interval: the split of their sum, Wilson):\n")
    for i, (a_name, a) in enumerate(totals):
        for b_name, b in totals[:i]:
            if a + b:
                r, lo, hi = ft.rate_ratio(a, b)
                print(f"* {a_name} / {b_name}: {r:.2f} [{lo:.2f}, {hi:.2f}]")
    if not descent_seeds:
        return
    print(f"\nDescent on noise only (seeds {seeds.start}-{seeds.start + descent_seeds - 1}; a "
          "candidate descends when its DP path, one frame after the earlier map, lies within one "
          "move of one of the earlier map's n = 33 candidates; 95 % Wilson over candidates, "
          "optimistic: candidates of one scene are correlated):\n")
    print("| variant | lag (frames) | candidates descended [95 %] | chance: image within one move "
          "| all pixels' paths descended |")
    print("|---|---|---|---|---|")
    total = {}
    for s in seeds[:descent_seeds]:
        sc_run = ft.noise_scene(s)
        for key, cfg, lg in (("rec", ft.recursive_config(rec, sc_run.cfg), lags),
                             ("seg", sc_run.cfg, (6,))):
            d = ft.descent_counts(sc_run.frames, cfg, sc_run.count, lags=lg)
            total[key] = d if key not in total else total[key] + d
    for key, name in (("seg", "segments K=6"), ("rec", f"recursive alpha={alpha:g}")):
        d = total[key]
        for i, lag in enumerate(d.lags):
            lo, hi = wilson_interval(d.descended[i], d.candidates[i])
            print(f"| {name} | {lag} | {d.descended[i] / d.candidates[i]:.4f} [{lo:.4f}, {hi:.4f}] "
                  f"({d.candidates[i]}) | {d.coverage[i] / d.pairs[i]:.4f} | "
                  f"{d.background[i] / d.pairs[i]:.4f} |", flush=True)


def list_swap_report(alpha: float, seeds: range, seg_counts: list[int], rec_counts: list[int],
                     workers: int, scheduler: str | None) -> None:
    tasks = [(alpha, s, tuple(seg_counts), tuple(rec_counts)) for s in seeds]
    with Execution(workers=workers, scheduler=scheduler).client() as client:
        per_seed = map_tasks(lsw.seed_swaps, tasks, client)
    keys = list(per_seed[0])
    name = {"seg": "segments K=6", "rec": f"recursive alpha={alpha:g}"}
    tot = {k: {how: sum((r[k][0][how] for r in per_seed[1:]), per_seed[0][k][0][how])
               for how in SWAPS if how in per_seed[0][k][0]} for k in keys}
    print(f"List swaps on noise only (built-in scenario without targets, seeds {seeds.start}-"
          f"{seeds.stop - 1}, lists every 6 frames; every confirmed track is false):\n")
    print("| variant | n | distinct per list | " + " | ".join(SWAPS) + " |")
    print("|---|---|---|" + "---|" * len(SWAPS))
    for k in keys:
        d = sum(r[k][1][0][0] for r in per_seed) / sum(r[k][1][0][1] for r in per_seed)
        print(f"| {name[k[0]]} | {k[1]} | {d:.1f} | "
              + " | ".join(str(tot[k][how].false_tracks) if how in tot[k] else "-"
                           for how in SWAPS) + " |")
    print("\nRatios recursion / segments at about equal distinct density (pooled over the "
          "crossed pairs: the shortest recursive lists against the shortest segment lists, and so "
          "on), 95 % interval of the split (Wilson):\n")
    pairs = list(zip(sorted(k for k in keys if k[0] == "rec"), sorted(k for k in keys if k[0] == "seg")))
    for how in SWAPS:
        if any(how not in tot[k] for k in keys):
            continue
        parts = []
        for rk, sk in pairs + [(None, None)]:
            if rk is None:
                a = sum(tot[r][how].false_tracks for r, _ in pairs)
                b = sum(tot[s][how].false_tracks for _, s in pairs)
                label = "pooled"
            else:
                a, b = tot[rk][how].false_tracks, tot[sk][how].false_tracks
                label = f"rec n={rk[1]} / seg n={sk[1]}"
            if a + b:
                r, lo, hi = ft.rate_ratio(a, b)
                parts.append(f"{label} {a}/{b} = {r:.2f} [{lo:.2f}, {hi:.2f}]")
        print(f"* {how}: " + "; ".join(parts))
    print("\nEach variant against its own lists as made:\n")
    for k in keys:
        for how in SWAPS[1:]:
            if how not in tot[k] or how == "energy-ranks":
                continue
            a, b = tot[k][how].false_tracks, tot[k]["none"].false_tracks
            if a + b:
                r, lo, hi = ft.rate_ratio(a, b)
                print(f"* {name[k[0]]}, n = {k[1]}: {how} / lists {a}/{b} = {r:.2f} "
                      f"[{lo:.2f}, {hi:.2f}]")
    for kind in ("seg", "rec"):
        mine = [k for k in keys if k[0] == kind]
        for how in SWAPS[1:]:
            if how == "energy-ranks" or any(how not in tot[k] for k in mine):
                continue
            a = sum(tot[k][how].false_tracks for k in mine)
            b = sum(tot[k]["none"].false_tracks for k in mine)
            if a + b:
                r, lo, hi = ft.rate_ratio(a, b)
                print(f"* {name[kind]}, pooled over n: {how} / lists {a}/{b} = {r:.2f} "
                      f"[{lo:.2f}, {hi:.2f}]")
    print("\nHow far the tracks got (the lists as made; 'uniform' in parentheses): tracks "
          "reaching h hits, and the fraction of those with h - 1 that got the h-th:\n")
    levels = len(tot[keys[0]]["none"].reached)
    print("| variant | n | " + " | ".join(f"{h} hits" for h in range(1, levels + 1)) + " |")
    print("|---|---|" + "---|" * levels)
    for k in keys:
        cells = []
        for h in range(levels):
            a, u = tot[k]["none"].reached, tot[k]["uniform"].reached
            frac = (f" ({a[h] / a[h - 1]:.3f}; {u[h] / u[h - 1]:.3f})" if h and a[h - 1] and u[h - 1]
                    else "")
            cells.append(f"{a[h]} ({u[h]}){frac}")
        print(f"| {name[k[0]]} | {k[1]} | " + " | ".join(cells) + " |")
    print(f"\nGeometry of the distinct candidates (per list): pairs at Chebyshev distance 2 .. "
          f"{PAIR_TOP - 1}, {PAIR_TOP}+; fraction of the image within the seed gate of one "
          "(lists / uniform positions):\n")
    print("| variant | n | " + " | ".join(f"d = {d}" for d in range(2, PAIR_TOP)) +
          f" | d >= {PAIR_TOP} | seed-gate coverage |")
    print("|---|---|" + "---|" * (PAIR_TOP - 1) + "---|")
    for k in keys:
        cells = []
        geo = [[r[k][1][i] for r in per_seed] for i in (0, 1)]
        n_lists = sum(g[1] for g in geo[0])
        pc = [sum(g[2] for g in geo[i]) / n_lists for i in (0, 1)]
        cov = [sum(g[3] for g in geo[i]) / n_lists for i in (0, 1)]
        cells = [f"{pc[0][d]:.2f} / {pc[1][d]:.2f}" for d in range(2, PAIR_TOP + 1)]
        print(f"| {name[k[0]]} | {k[1]} | " + " | ".join(cells) +
              f" | {cov[0]:.4f} / {cov[1]:.4f} |", flush=True)


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
    ap.add_argument("--false-tracks", action="store_true",
                    help="only classify the false tracks at --alpha (and the noise-only controls)")
    ap.add_argument("--seg-counts", default="33,43",
                    help="list lengths of segments K=6 on noise only (--false-tracks)")
    ap.add_argument("--rec-counts", default="33,26",
                    help="list lengths of the recursion on noise only (--false-tracks)")
    ap.add_argument("--descent-seeds", type=int, default=5,
                    help="noise-only seeds of the descent measurement (--false-tracks; 0: none)")
    ap.add_argument("--descent-lags", default="1-6,12,18",
                    help="lags (frames) of the recursion's descent (--false-tracks)")
    ap.add_argument("--list-swaps", action="store_true",
                    help="only replay the noise-only lists at --alpha with one property swapped")
    ap.add_argument("--workers", type=int, default=1, help="dask workers (--list-swaps)")
    ap.add_argument("--scheduler", default=None, help="dask scheduler address (--list-swaps)")
    args = ap.parse_args(argv)
    if args.list_swaps:
        if args.alpha is None:
            ap.error("--list-swaps needs --alpha")
        try:
            fd.recursive(args.alpha)
            check_int("seeds", args.seeds, 1)
            seg_counts = _counts("seg_counts", args.seg_counts)
            rec_counts = _counts("rec_counts", args.rec_counts)
        except DptbdError as exc:
            ap.error(str(exc))
        if len(seg_counts) != len(rec_counts):
            ap.error(f"--list-swaps crosses --seg-counts with --rec-counts: give as many of each, "
                     f"got {len(seg_counts)} and {len(rec_counts)}")
        list_swap_report(args.alpha, range(args.first_seed, args.first_seed + args.seeds),
                         seg_counts, rec_counts, args.workers, args.scheduler)
        return
    if args.false_tracks:
        if args.alpha is None:
            ap.error("--false-tracks needs --alpha")
        try:
            fd.recursive(args.alpha)
            check_int("seeds", args.seeds, 1)
            check_int("descent_seeds", args.descent_seeds, 0, args.seeds, hi_name="seeds=")
            parsed = (_counts("seg_counts", args.seg_counts), _counts("rec_counts", args.rec_counts),
                      parse_lags(args.descent_lags))
        except DptbdError as exc:
            ap.error(str(exc))
        false_track_report(args.alpha, range(args.first_seed, args.first_seed + args.seeds),
                           parsed[0], parsed[1], args.descent_seeds, parsed[2])
        return
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
