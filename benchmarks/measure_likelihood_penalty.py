"""Paper 000's likelihood-difference DP with and without the eq (22) penalty: its SNR gain.

    python benchmarks/measure_likelihood_penalty.py                 # 200 scenes per SNR
    python benchmarks/measure_likelihood_penalty.py --trials 100 --snr 4 5 6 7 8 9 10 11 12 13 14

The protocol of ``docs/detectors.md`` §1.5 (:func:`dptbd.evaluation.detectors.paper000.snr_gain`):
000's scene (64 x 64, 20 frames, v = (+2, -2), σ = 1), the same seeds (targets from 5000,
noise-only scenes from 5001), a per-cell false-alarm probability (default 10⁻³) set on
noise-only scenes, detected = a cell within one cell of the target's true last position
above the threshold; the likelihood DP uses the true amplitude with ε = 0.85 and σ = 1 and
is recalibrated at each SNR. Detectors:

* ``CA-CFAR 16/2`` — §2.3's CA-CFAR on |z| of the last frame's positive cells;
* ``likelihood DP, eq (22) penalty`` — eqs (19)–(23) with this project's reading of eq (22)
  (``transitions.velocity_log_penalty(2, alpha=1)``, ``docs/detectors.md`` §1.2): what §1.5's
  table and ``dptbd detectors``' ``dp-likelihood`` run;
* ``likelihood DP, no penalty`` — the same merit with ``transitions.no_penalty(2)``: eq (23)
  without the prior term, i.e. without the project's reading of eq (22).

Printed: Pd per SNR, the SNR at Pd 0.5 and 0.9 (``paper000.crossing_snr``) and each DP's
gain over CA-CFAR. Library functions only; this script reports, it asserts nothing.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np

DETECTORS = ("CA-CFAR 16/2", "likelihood DP, eq (22) penalty", "likelihood DP, no penalty")


def _maps(name: str, frames: np.ndarray, snr_db: float, epsilon: float) -> np.ndarray:
    from dptbd.evaluation.detectors import cfar, merits, transitions, unified
    from dptbd.evaluation.detectors.paper000 import RADIUS
    from dptbd.scenes import synthetic as scenes

    if name == "CA-CFAR 16/2":
        last = frames[:, -1].astype(np.float64)
        ratio = cfar.ca_cfar_ratio(np.abs(last), n_ref=16, n_guard=2, axis=-2)
        return np.where(last > 0, ratio, 0.0)
    merit = merits.likelihood_difference_merit(scenes.amplitude_from_snr_db(snr_db, 1.0),
                                                epsilon, 1.0)
    q = (transitions.velocity_log_penalty(RADIUS, 1.0) if "penalty" in name and "no" not in name
         else transitions.no_penalty(RADIUS))
    return unified.run_unified(frames, merit, q, radius=RADIUS).value


def measure(snrs, trials: int, noise_trials: int, pfa: float, epsilon: float, seed: int,
            chunk: int) -> dict:
    from dptbd.scenes import synthetic as scenes

    def batches(snr, n, base):
        for lo in range(0, n, chunk):
            m = min(chunk, n - lo)
            if snr is None:
                yield scenes.make_noise((64, 64), 20, seed=base, trials=m, first_trial=lo)
            else:
                yield scenes.paper000_scenario(snr, seed=base, trials=m, first_trial=lo).frames

    y, x = scenes.paper000_scenario(0.0, noise=False).truth[0].pixel[-1]
    thresholds: dict = {}

    def threshold(name, snr):
        key = (name, snr) if name != "CA-CFAR 16/2" else (name, None)
        if key not in thresholds:
            vals = np.concatenate([_maps(name, f, snr, epsilon).ravel()
                                   for f in batches(None, noise_trials, seed + 1)])
            k = int(math.floor(pfa * vals.size))
            thresholds[key] = float(np.partition(vals, vals.size - k - 1)[vals.size - k - 1])
        return thresholds[key]

    pd = {n: [] for n in DETECTORS}
    for snr in snrs:
        frames_list = list(batches(snr, trials, seed))
        for n in DETECTORS:
            thr = threshold(n, snr)
            hits = sum(int(np.count_nonzero(np.any(
                _maps(n, f, snr, epsilon)[:, max(y - 1, 0):y + 2, max(x - 1, 0):x + 2] > thr,
                axis=(1, 2)))) for f in frames_list)
            pd[n].append(hits / trials)
        print(f"SNR {snr:g} dB: " + ", ".join(f"{n} {pd[n][-1]:.3f}" for n in DETECTORS),
              flush=True)
    return pd


def main(argv: list[str] | None = None) -> int:
    from dptbd.evaluation.detectors.paper000 import crossing_snr

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--snr", type=float, nargs="+", default=list(range(-2, 13)) + [13, 14, 15],
                   help="SNRs in dB, eq (8) (default -2 … 15)")
    p.add_argument("--trials", type=int, default=200)
    p.add_argument("--noise-trials", type=int, default=200)
    p.add_argument("--pfa", type=float, default=1e-3)
    p.add_argument("--epsilon", type=float, default=0.85)
    p.add_argument("--seed", type=int, default=5000)
    p.add_argument("--chunk", type=int, default=50)
    args = p.parse_args(argv)
    start = time.perf_counter()
    pd = measure(args.snr, args.trials, args.noise_trials, args.pfa, args.epsilon, args.seed,
                 args.chunk)
    print(f"\n{args.trials} scenes per SNR, {args.noise_trials} noise-only scenes, per-cell "
          f"Pfa {args.pfa:g}, ε = {args.epsilon}, seed {args.seed} "
          f"({time.perf_counter() - start:.0f} s)\n")
    print("| detector | SNR at Pd 0.5 (dB) | SNR at Pd 0.9 (dB) | gain over CA-CFAR at Pd 0.5 / 0.9 (dB) |")
    print("|---|---|---|---|")
    ref = [crossing_snr(args.snr, pd["CA-CFAR 16/2"], lv) for lv in (0.5, 0.9)]
    for n in DETECTORS:
        c = [crossing_snr(args.snr, pd[n], lv) for lv in (0.5, 0.9)]
        print(f"| {n} | {c[0]:.1f} | {c[1]:.1f} | {ref[0] - c[0]:.1f} / {ref[1] - c[1]:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
