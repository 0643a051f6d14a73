"""K-frame segments against the recursive DP with a forgetting factor (issue 15, first level).

On paper 001's Table 1 setting (``dptbd.evaluation.table1``: 128 x 128, 100 frames, the
same ADC, scenes and candidate count n = 33 = 0.2 % per detection map), the golden model
of ``docs/arithmetic.md`` runs the direction-weighted DP (001's eq (11) LUT) either

* in K-frame segments, stride K (the gateware's schedule): one map per K frames, or
* recursively (§8.6), E_k = x + alpha * max(...), never reset: one map per frame; maps of
  frames t >= ``warmup`` are scored (the recursion has seen at least ``warmup + 1`` frames).

Every map keeps its n largest pixels (``candidate_mask``, the ideal §6 rule), so the false
points per map are equal up to ties; first-level Pd per map and false points per map are
counted by :func:`dptbd.evaluation.metrics.first_level_counts`. The DSP association
(confirmation delay, false tracks) is not run here.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.config import DPConfig
from dptbd.errors import check_int, check_real
from dptbd.evaluation.metrics import DetectionCounts, first_level_counts
from dptbd.evaluation.table1 import FALSE_ALARM_RATE, SETTINGS, table1_config
from dptbd.model.fast import run_fixed_fast
from dptbd.model.fast_family import run_family_fast
from dptbd.model.segmentation import candidate_mask, count_for_rate
from dptbd.scenes import synthetic as scenes
from dptbd.scenes.synthetic import ADC_GAIN, INPUT_BITS

__all__ = ["Variant", "segments", "recursive", "variant_config", "variant_counts", "compare"]

#: E width of the recursive variants: 12-bit pixels / (1 - alpha) stays below 2**20 for
#: alpha <= 0.99 (§8.6), so nothing saturates.
RECURSIVE_ENERGY_BITS = 20


@dataclasses.dataclass(frozen=True)
class Variant:
    """A schedule: ``segment_frames`` K (segments, stride K) or ``forgetting`` alpha (recursive;
    then ``segment_frames`` is the DSP's path length and list cadence)."""

    label: str
    segment_frames: int = 6
    forgetting: float | None = None
    warmup: int = 7


def segments(k: int) -> Variant:
    """K-frame segments, stride K."""
    return Variant(f"segments K={k}", segment_frames=check_int("segment_frames", k, 1, 100))


def recursive(alpha: float, warmup: int = 7, segment_frames: int = 6) -> Variant:
    """The recursive DP with forgetting factor ``alpha`` in (0, 1).

    ``warmup``: the first scored map (first level, :func:`variant_counts`);
    ``segment_frames``: the frames a candidate's path is backtracked over and the cadence
    of the lists the DSP receives (:mod:`dptbd.evaluation.family_association`).
    """
    alpha = check_real("forgetting", alpha, 0.0, 1.0, lo_open=True, hi_open=True)
    return Variant(f"recursive alpha={alpha:g}", forgetting=alpha,
                   segment_frames=check_int("segment_frames", segment_frames, 1, 100),
                   warmup=check_int("warmup", warmup, 0, 99))


def variant_config(variant: Variant, size: int = 128) -> DPConfig:
    """The golden model's configuration of a variant (Table 1's, with 001's eq (11) LUT)."""
    base = table1_config(variant.segment_frames, variant.segment_frames, size=size)
    if variant.forgetting is None:
        return base
    return base.replace(energy_bits=RECURSIVE_ENERGY_BITS, forgetting=variant.forgetting,
                        forgetting_bits=8, recursive=True)


def variant_counts(variant: Variant, snr: float, velocity: tuple[float, float], *, trials: int,
                   seed: int, chunk: int = 5, size: int = 128) -> DetectionCounts:
    """First-level counts of one variant on one Table 1 setting, ``trials`` scenes from ``seed``."""
    cfg = variant_config(variant, size)
    count = count_for_rate(FALSE_ALARM_RATE, size * size)
    total = DetectionCounts(0, 0, 0, 0)
    for first in range(0, trials, chunk):
        scene = scenes.table1_scenario(snr, velocity, size=size, seed=seed,
                                       trials=min(chunk, trials - first), first_trial=first,
                                       dtype=np.float32)
        frames = scene.quantised(INPUT_BITS, gain=ADC_GAIN)
        if cfg.recursive:
            ends = np.arange(variant.warmup, scene.n_frames)
            images = run_family_fast(frames, cfg).energy[:, ends]
        else:
            out = run_fixed_fast(frames, cfg)
            ends, images = out.end_frames, out.energy
        truth = scene.truth[0]
        for trial_image in candidate_mask(images, count):
            total = total + first_level_counts(trial_image, truth.pixel[ends][:, None],
                                               truth.visible[ends][:, None])
    return total


def compare(variants, *, trials: int, seed: int, settings=SETTINGS, size: int = 128
            ) -> dict[str, dict[tuple, DetectionCounts]]:
    """``{variant label: {(snr, velocity): counts}}`` for every variant and setting."""
    return {v.label: {(snr, vel): variant_counts(v, snr, vel, trials=trials, seed=seed, size=size)
                      for snr, vel in settings} for v in variants}
