"""What direction weighting and the segment length K buy: first level and association.

    python benchmarks/measure_weighting.py cluster               # Table 1 scenes, 50 trials
    python benchmarks/measure_weighting.py association --seeds 40
    python benchmarks/measure_weighting.py association --seeds 40 --variants weighted-K4 weighted-K6 weighted-K8

``cluster`` — on paper 001's Table 1 scenes (``dptbd.evaluation.table1.experiment``: the same
configuration, ADC, seed 2003 and candidate count as ``dptbd table1``; K = 6, stride 4),
the direction-weighted DP and plain DP (an all-ones LUT) on the same scenes: per
(accumulated frame, target) the candidates inside the 3 x 3 gate around the target's true
pixel (001's "cluster"), their mean over every accumulated frame and over the frames in
which the target was detected, and the first-level Pd. More points in the gate means the
accumulated energy *stays* around the target; fewer means it spreads away from it.

``association`` — ``dptbd run``'s built-in scenario (001's second experiment: 128 x 128,
100 frames, SNR 2.0, two targets, 0.2 %, gateware lists with headroom 2) over seeds
0 … N-1 through the FPGA stage and the DSP stage (``dptbd.evaluation.chain``, as ``dptbd run``
builds it), for each variant: weighted or plain LUT, K = 4, 6 or 8 (stride K, the
gateware's schedule). Per target: confirmed in how many runs (95 % Wilson interval,
``dptbd.evaluation.stats.wilson_interval``), frames until output (mean over the runs in
which it was confirmed); per run: false tracks (mean, and runs with at least one, with its
Wilson interval); first-level Pd pooled over seeds.

Library functions only (no command module). This script reports; it asserts nothing.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

VARIANTS = ("weighted-K6", "plain-K6", "weighted-K4", "plain-K4", "weighted-K8", "plain-K8")


def _wilson(k: int, n: int) -> str:
    from dptbd.evaluation.stats import wilson_interval
    lo, hi = wilson_interval(k, n)
    return f"{k}/{n} = {k / n:.2f} [{lo:.2f}, {hi:.2f}]"


# ---- first level: points in the 3 x 3 gate -------------------------------------------------

def cluster(trials: int, segment_frames: int, segment_stride: int, seed: int, chunk: int) -> None:
    from dptbd.weights import plain_weights
    from dptbd.evaluation.table1 import experiment as table1
    from dptbd.evaluation.metrics import near_mask
    from dptbd.model.fast import run_fixed_fast
    from dptbd.model.segmentation import candidate_mask, count_for_rate
    from dptbd.scenes import synthetic

    cfg = table1.table1_config(segment_frames, segment_stride)
    plain = cfg.replace(weights=plain_weights(cfg.radius))
    count = count_for_rate(table1.FALSE_ALARM_RATE, cfg.width * cfg.height)
    print(f"Table 1 scenes, {trials} trials per setting, seed {seed}, K = {segment_frames}, "
          f"stride {segment_stride}, n = {count} candidates per accumulated frame\n")
    print("| SNR | V | detector | Pd | points in the 3x3 gate per accumulated frame | "
          "per detection | gate holds 2+ points |")
    print("|---|---|---|---|---|---|---|")
    for snr, velocity in table1.SETTINGS:
        tally = {name: np.zeros(4, np.int64) for name in ("direction-weighted DP", "plain DP")}
        for first in range(0, trials, chunk):
            scene = synthetic.table1_scenario(snr, velocity, size=cfg.width, seed=seed,
                                              trials=min(chunk, trials - first),
                                              first_trial=first, dtype=np.float32)
            frames = scene.quantised(table1.INPUT_BITS, gain=table1.ADC_GAIN)
            ends = (cfg.segment_stride * np.arange(cfg.n_segments(scene.n_frames))
                    + cfg.segment_frames - 1)
            truth = scene.truth[0]
            for name, c in (("direction-weighted DP", cfg), ("plain DP", plain)):
                masks = candidate_mask(run_fixed_fast(frames, c).energy, count)
                for trial_masks in masks:
                    for s, t in enumerate(ends):
                        if not truth.visible[t]:
                            continue
                        gate = near_mask(trial_masks[s].shape, truth.pixel[t][None], 1)
                        inside = int(np.count_nonzero(trial_masks[s] & gate))
                        tally[name] += (1, inside > 0, inside, inside >= 2)
        for name, (frames_n, det, inside, two) in tally.items():
            print(f"| {snr} | ({velocity[0]:g}, {velocity[1]:g}) | {name} | {det / frames_n:.3f} | "
                  f"{inside / frames_n:.2f} | {inside / max(det, 1):.2f} | {two / frames_n:.3f} |",
                  flush=True)


# ---- association: confirmation and false tracks over seeds --------------------------------

def run_seed(seed: int, weighted: bool, segment_frames: int) -> dict:
    """The built-in scenario of ``dptbd run`` with one seed, LUT and K, through both stages."""
    from dptbd.weights import plain_weights
    from dptbd.evaluation.run.job import run_job
    from dptbd.evaluation.run.scenario import default_scenario

    sc = default_scenario()
    dp = {**sc.dp, "segment_frames": segment_frames}
    if not weighted:
        dp["weights"] = plain_weights(1)
    sc = sc.replace(seed=seed, dp=dp)
    sc.check()
    result = run_job(sc)                      # the main job, as dptbd run runs it
    res, ev, truths = result.pipeline, result.evaluation, result.input.truth
    hits = []
    for j, truth in enumerate(truths):
        det = opp = 0
        for s, end in enumerate(res.segments.end_frames):
            if not truth.visible[end]:
                continue
            opp += 1
            c = res.candidates[s]
            if len(c):
                d = np.maximum(np.abs(c["row"].astype(np.int64) - truth.pixel[end][0]),
                               np.abs(c["col"].astype(np.int64) - truth.pixel[end][1]))
                det += bool(np.any(d <= 1))
        hits.append((det, opp))
    return {"false_tracks": ev.false_tracks,
            "targets": [(t.frames_until_output, h) for t, h in zip(ev.targets, hits)]}


def association(seeds: int, variants: list[str]) -> None:
    print(f"dptbd run's built-in scenario, seeds 0-{seeds - 1}, gateware lists (headroom 2)\n")
    print("| LUT | K | target | confirmed [95% CI] | frames until output (confirmed runs) | "
          "first-level Pd (pooled) | false tracks per run | runs with a false track [95% CI] |")
    print("|---|---|---|---|---|---|---|---|")
    for variant in variants:
        lut, k = variant.split("-K")
        start = time.perf_counter()
        runs = [run_seed(s, lut == "weighted", int(k)) for s in range(seeds)]
        false = [r["false_tracks"] for r in runs]
        n_t = len(runs[0]["targets"])
        for j in range(n_t):
            out = [r["targets"][j][0] for r in runs]
            conf = [o for o in out if o is not None]
            det = sum(r["targets"][j][1][0] for r in runs)
            opp = sum(r["targets"][j][1][1] for r in runs)
            tail = (f"{np.mean(false):.2f} | {_wilson(sum(f > 0 for f in false), seeds)}"
                    if j == 0 else " | ")
            print(f"| {lut} | {k} | {j + 1} | {_wilson(len(conf), seeds)} | "
                  f"{np.mean(conf) if conf else float('nan'):.1f} | {det / opp:.3f} ({det}/{opp}) | "
                  f"{tail} |", flush=True)
        both = sum(all(t[0] is not None for t in r["targets"]) for r in runs)
        print(f"| {lut} | {k} | both | {_wilson(both, seeds)} | | | | |  "
              f"<!-- {time.perf_counter() - start:.0f} s -->", flush=True)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="what", required=True)
    c = sub.add_parser("cluster", help="points in the 3x3 gate on the Table 1 scenes")
    c.add_argument("--trials", type=int, default=50)
    c.add_argument("--segment-frames", type=int, default=6)
    c.add_argument("--segment-stride", type=int, default=4)
    c.add_argument("--seed", type=int, default=2003, help="default 2003, as dptbd table1")
    c.add_argument("--chunk", type=int, default=10)
    a = sub.add_parser("association", help="confirmation and false tracks over seeds")
    a.add_argument("--seeds", type=int, default=40)
    a.add_argument("--variants", nargs="+", choices=VARIANTS,
                   default=["weighted-K6", "plain-K6"])
    args = p.parse_args(argv)
    if args.what == "cluster":
        cluster(args.trials, args.segment_frames, args.segment_stride, args.seed, args.chunk)
    else:
        association(args.seeds, args.variants)
    return 0


if __name__ == "__main__":
    sys.exit(main())
