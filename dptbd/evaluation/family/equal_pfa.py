"""K-frame segments against the recursive DP at equal false-alarm rate per pixel (first level).

Beside :mod:`~dptbd.evaluation.family.detection`'s fixed list length (each map's n = 33
largest pixels), every variant's maps are thresholded at the level that *its own*
noise-only maps exceed on a fraction ``pfa`` of their pixels
(:func:`dptbd.evaluation.pfa.calibrate_pixel_threshold`). The noise-only scenes are Table
1's noise without the target (128 x 128, 100 frames, mean 30, sigma sqrt 3, the same ADC),
one scene per seed (``noise_seeds``, disjoint from the target scenes' seed), through the
same variant. **Choice: one threshold per map index** (the s-th scored map of a scene:
segment s, or the recursion's frame ``warmup + s``), calibrated on the noise-only maps of
that index pooled over the seeds: the recursion's E is not stationary — on noise it grows
like ``(1 - alpha**(t+1)) / (1 - alpha)`` (≈ 3700 at frame 7, ≈ 16000 at frame 99 with
alpha = 0.97 on Table 1's ADC), so one threshold for all its maps would be set by the
late maps and never reached by the early ones. Segment maps are stationary; the same rule
gives them thresholds that differ only by the sampling of the noise.

On the target scenes (the same seeded scenes as :mod:`.detection`), a map *detects* the
target when a pixel within one pixel (Chebyshev) of its true pixel is strictly above the
threshold; every other pixel above it is a *false alarm*
(:func:`dptbd.evaluation.metrics.first_level_counts` of ``map > threshold``). False alarms
per map on target scenes include what the target itself leaves outside its gate (the
recursion's smear along its past track), which noise-only scenes do not have.

The tasks — one per (variant, noise seed) for the calibration, one per (variant, setting)
for the counts — run on the execution layer (:mod:`dptbd.evaluation.execution`).
"""

from __future__ import annotations

import dataclasses
from typing import Sequence

import numpy as np

from dptbd.errors import check_int
from dptbd.evaluation.execution import Execution, map_tasks
from dptbd.evaluation.family.detection import Variant, variant_config, variant_maps, variant_scene_maps
from dptbd.evaluation.metrics import DetectionCounts, first_level_counts
from dptbd.evaluation.pfa import (Calibration, PfaError, allowed_false_alarms, calibrate_pixel_threshold,
                                  check_noise_seeds, check_pfa)
from dptbd.evaluation.table1.experiment import SETTINGS
from dptbd.scenes import synthetic as scenes
from dptbd.scenes.synthetic import ADC_GAIN, INPUT_BITS

__all__ = ["NOISE_SEED", "FRAMES", "noise_maps", "scored_maps", "threshold_counts", "EqualPfaResult",
           "compare_equal_pfa"]

#: First seed of the noise-only scenes by default (the target scenes use 2003 and 1000).
NOISE_SEED = 9000
#: Frames of a Table 1 scene.
FRAMES = 100


def noise_maps(variant: Variant, seed: int, size: int = 128) -> np.ndarray:
    """The scored maps ``(S, H, W)`` of ``variant`` on the noise-only Table 1 scene ``seed``."""
    noise = scenes.make_noise((size, size), FRAMES, mu=scenes.TABLE1_MU, sigma=scenes.TABLE1_SIGMA,
                              seed=seed, trials=1, dtype=np.float32)
    codes = scenes.quantise(noise, INPUT_BITS, gain=ADC_GAIN)
    return variant_maps(variant, codes, variant_config(variant, size))[1][0]


def threshold_counts(variant: Variant, snr: float, velocity: tuple[float, float],
                     thresholds: Sequence[float], *, trials: int, seed: int, chunk: int = 5,
                     size: int = 128) -> list[list[DetectionCounts]]:
    """First-level counts of ``variant`` at each level of ``thresholds`` on the Table 1
    setting ``(snr, velocity)``: ``out[scene][level]``, ``trials`` scenes from ``seed`` (the
    scenes of :func:`~dptbd.evaluation.family.detection.variant_trial_counts`).
    ``thresholds[level]`` is a number or one threshold per scored map."""
    thresholds = [np.asarray(t, dtype=np.float64).reshape(-1, 1, 1) for t in thresholds]
    out = []
    for ends, images, truth in variant_scene_maps(variant, snr, velocity, trials=trials,
                                                  seed=seed, chunk=chunk, size=size):
        pix, vis = truth.pixel[ends][:, None], truth.visible[ends][:, None]
        for trial_images in images:
            out.append([first_level_counts(trial_images > thr, pix, vis) for thr in thresholds])
    return out


@dataclasses.dataclass(frozen=True)
class EqualPfaResult:
    """Per variant label: its thresholds, their noise-only exceedance rate and its counts.

    ``thresholds[label]``: ``(levels, maps)``, one threshold per ``pfas[i]`` and map index;
    ``measured[label][i]``: noise-only pixels above them over all noise-only pixels
    (``noise_pixels[label]``) at ``pfas[i]``; ``counts[label][(snr, velocity)][scene][i]``.
    """

    pfas: tuple[float, ...]
    labels: tuple[str, ...]
    thresholds: dict
    measured: dict
    noise_pixels: dict
    counts: dict
    params: dict

    def pooled(self, label: str, level: int) -> DetectionCounts:
        """Counts of one variant at ``pfas[level]`` summed over settings and scenes."""
        total = DetectionCounts(0, 0, 0, 0)
        for per_scene in self.counts[label].values():
            for scene in per_scene:
                total = total + scene[level]
        return total

    def per_scene(self, label: str, level: int) -> list[DetectionCounts]:
        """Counts of every scene (settings in order) at ``pfas[level]``, for paired differences."""
        return [scene[level] for per_scene in self.counts[label].values() for scene in per_scene]


def _noise_task(variant: Variant, seed: int, size: int) -> np.ndarray:
    return noise_maps(variant, seed, size)


def _count_task(variant: Variant, snr: float, velocity, thresholds, trials: int, seed: int,
                size: int) -> list:
    return threshold_counts(variant, snr, velocity, thresholds, trials=trials, seed=seed, size=size)


def compare_equal_pfa(variants: Sequence[Variant], pfas: Sequence[float], *, trials: int, seed: int,
                      noise_seeds: Sequence[int], settings=SETTINGS, size: int = 128,
                      workers: int = 1, scheduler: str | None = None) -> EqualPfaResult:
    """Every variant at every false-alarm probability per pixel of ``pfas`` (checked first).

    ``noise_seeds``: the noise-only scenes of the calibration (each variant calibrated on
    the same ones); ``trials`` target scenes per setting from ``seed``.
    """
    pfas = tuple(check_pfa(p) for p in pfas)
    if not pfas:
        raise PfaError("pfa must hold at least one false-alarm probability in (0, 1)")
    variants = tuple(variants)
    trials = check_int("trials", trials, 1, error=PfaError)
    noise_seeds = check_noise_seeds(noise_seeds)
    if not variants:
        raise PfaError("variants must hold at least one variant")
    for p in pfas:  # refuse a rate the noise-only maps of one index cannot resolve, first
        allowed_false_alarms(p, len(noise_seeds) * size * size)
    execution = Execution(workers=workers, scheduler=scheduler)
    with execution.client() as client:
        maps = map_tasks(_noise_task, [(v, s, size) for v in variants for s in noise_seeds], client)
        thresholds, measured, noise_pixels = {}, {}, {}
        for i, v in enumerate(variants):
            mine = dict(zip(noise_seeds, maps[i * len(noise_seeds):(i + 1) * len(noise_seeds)]))
            thr = np.empty((len(pfas), scored_maps(v, size)))
            above = np.zeros(len(pfas), dtype=np.int64)
            pixels = 0
            for m in range(thr.shape[1]):  # one threshold per map index (the Choice above)
                cal: Calibration = calibrate_pixel_threshold(lambda sd: mine[sd][m], noise_seeds,
                                                             pfas[0])
                for j, p in enumerate(pfas):
                    thr[j, m] = cal.threshold_for(p)
                    above[j] += cal.count_above(thr[j, m])
                pixels += cal.pixels
            thresholds[v.label] = thr
            measured[v.label] = tuple(int(a) / pixels for a in above)
            noise_pixels[v.label] = pixels
        del maps
        tasks = [(v, snr, vel, thresholds[v.label], trials, seed, size)
                 for v in variants for snr, vel in settings]
        results = map_tasks(_count_task, tasks, client)
    counts: dict = {v.label: {} for v in variants}
    for (v, snr, vel, *_), res in zip(tasks, results):
        counts[v.label][(snr, tuple(vel))] = res
    params = dict(trials=trials, seed=seed, noise_seeds=list(noise_seeds), size=size,
                  settings=[(s, list(v)) for s, v in settings])
    return EqualPfaResult(pfas, tuple(v.label for v in variants), thresholds, measured,
                          noise_pixels, counts, params)


def scored_maps(variant: Variant, size: int = 128) -> int:
    """Scored maps of ``variant`` in one Table 1 scene (no scene is run)."""
    if variant.forgetting is not None:
        return FRAMES - variant.warmup
    return variant_config(variant, size).n_segments(FRAMES)
