"""K-frame segments against the recursive DP with a forgetting factor (first level).

On paper 001's Table 1 setting (``dptbd.evaluation.table1.experiment``: 128 x 128, 100 frames, the
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
from dptbd.errors import DptbdError, check_int
from dptbd.evaluation.metrics import DetectionCounts, first_level_counts
from dptbd.evaluation.table1.experiment import FALSE_ALARM_RATE, SETTINGS, table1_config
from dptbd.model.fast import run_fixed_fast
from dptbd.model.family.fast import run_family_fast
from dptbd.model.segmentation import candidate_mask, count_for_rate
from dptbd.scenes import synthetic as scenes
from dptbd.scenes.synthetic import ADC_GAIN, INPUT_BITS

__all__ = ["Variant", "segments", "recursive", "variant_config", "variant_maps", "variant_trial_counts",
           "variant_range_counts", "check_frame_ranges", "variant_counts", "compare",
           "paired_pd_difference", "parse_segment_lengths", "parse_frame_ranges", "FRAMES"]

#: Frames of a Table 1 scene.
FRAMES = 100

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
    zero_move_penalty: int = 0

    def family_fields(self, radius: int) -> dict:
        """The §8 ``DPConfig`` fields of a recursive variant (``{}`` for segments): alpha's
        code of 8 bits, E of :data:`RECURSIVE_ENERGY_BITS`, and ``zero_move_penalty``
        subtracted from the zero move of every predecessor but ``START``."""
        if self.forgetting is None:
            return {}
        out = dict(recursive=True, forgetting=self.forgetting, forgetting_bits=8,
                   energy_bits=RECURSIVE_ENERGY_BITS)
        if self.zero_move_penalty:
            m = (2 * radius + 1) ** 2
            table = np.zeros((m + 1, m), dtype=np.int64)
            table[:m, m // 2] = self.zero_move_penalty
            out["penalty_codes"] = table
        return out


def segments(k: int) -> Variant:
    """K-frame segments, stride K."""
    return Variant(f"segments K={k}", segment_frames=check_int("segment_frames", k, 1, 100))


def recursive(alpha: float, warmup: int = 7, segment_frames: int = 6,
              zero_move_penalty: int = 0) -> Variant:
    """The recursive DP with forgetting factor ``alpha`` in (0, 1] (1: no forgetting, a sum
    that never resets; the E of :data:`RECURSIVE_ENERGY_BITS` holds 256 frames of 12-bit
    pixels).

    ``warmup``: the first scored map (first level, :func:`variant_counts`);
    ``segment_frames``: the frames a candidate's path is backtracked over and the cadence
    of the lists the DSP receives (:mod:`dptbd.evaluation.family.association`);
    ``zero_move_penalty``: a penalty code (``docs/arithmetic.md`` §8.2) on the zero move
    after any predecessor but ``START``, against the recursion's wake.
    """
    # DPConfig is alpha's home: (0, 1], and a code of forgetting_bits = 8 that is not 0
    alpha = DPConfig(forgetting=alpha, forgetting_bits=8).forgetting
    pen = check_int("zero_move_penalty", zero_move_penalty, 0, 65535)
    label = f"recursive alpha={alpha:g}" + (f" zero-move penalty {pen}" if pen else "")
    return Variant(label, forgetting=alpha,
                   segment_frames=check_int("segment_frames", segment_frames, 1, 100),
                   warmup=check_int("warmup", warmup, 0, 99), zero_move_penalty=pen)


def variant_config(variant: Variant, size: int = 128) -> DPConfig:
    """The golden model's configuration of a variant (Table 1's, with 001's eq (11) LUT)."""
    base = table1_config(variant.segment_frames, variant.segment_frames, size=size)
    return base.replace(**variant.family_fields(base.radius)) if variant.forgetting else base


def variant_trial_counts(variant: Variant, snr: float, velocity: tuple[float, float], *,
                         trials: int, seed: int, chunk: int = 5, size: int = 128
                         ) -> list[DetectionCounts]:
    """First-level counts of one variant on one Table 1 setting, one per scene (trial):
    ``trials`` scenes from ``seed``, the same scenes for every variant (paired)."""
    return [scene[0] for scene in variant_range_counts(variant, snr, velocity,
                                                       ranges=((0, FRAMES - 1),), trials=trials,
                                                       seed=seed, chunk=chunk, size=size)]


def check_frame_ranges(ranges) -> tuple[tuple[int, int], ...]:
    """``ranges`` as a tuple of ``(first, last)`` frames, each ``0 <= first <= last <= 99``
    (a Table 1 scene's frames); refused otherwise."""
    out = []
    for i, rng in enumerate(ranges):
        try:
            first, last = rng
        except (TypeError, ValueError):
            raise DptbdError(f"frame range {i} must be a pair (first, last) of frames, got {rng!r}") from None
        first = check_int(f"frame range {i} first", first, 0, FRAMES - 1)
        last = check_int(f"frame range {i} last", last, first, FRAMES - 1)
        out.append((first, last))
    if not out:
        raise DptbdError("ranges must hold at least one (first, last) frame range")
    return tuple(out)


def variant_scene_maps(variant: Variant, snr: float, velocity: tuple[float, float], *,
                       trials: int, seed: int, chunk: int = 5, size: int = 128):
    """``(ends, images, truth)`` of ``variant`` on ``trials`` Table 1 scenes of the setting
    ``(snr, velocity)`` from ``seed``, ``chunk`` scenes at a time: the scored maps' last
    frames, the maps (scene, map, row, column) and the target's truth (the same scenes for
    every variant: paired)."""
    cfg = variant_config(variant, size)
    for first in range(0, trials, chunk):
        scene = scenes.table1_scenario(snr, velocity, size=size, seed=seed,
                                       trials=min(chunk, trials - first), first_trial=first,
                                       dtype=np.float32)
        ends, images = variant_maps(variant, scene.quantised(INPUT_BITS, gain=ADC_GAIN), cfg)
        yield ends, images, scene.truth[0]


def variant_range_counts(variant: Variant, snr: float, velocity: tuple[float, float], *,
                         ranges, trials: int, seed: int, chunk: int = 5, size: int = 128
                         ) -> list[list[DetectionCounts]]:
    """First-level counts of one variant on one Table 1 setting by frame range:
    ``out[scene][i]`` counts the scored maps whose last frame lies in ``ranges[i] = (first,
    last)`` (inclusive; :func:`check_frame_ranges`), ``trials`` scenes from ``seed`` (the
    same scenes for every variant: paired). A range holding no scored map of the variant
    counts nothing (``DetectionCounts(0, 0, 0, 0)``)."""
    ranges = check_frame_ranges(ranges)
    count = count_for_rate(FALSE_ALARM_RATE, size * size)
    out = []
    for ends, images, truth in variant_scene_maps(variant, snr, velocity, trials=trials,
                                                  seed=seed, chunk=chunk, size=size):
        pix, vis = truth.pixel[ends][:, None], truth.visible[ends][:, None]
        for trial_image in candidate_mask(images, count):
            per = []
            for lo, hi in ranges:
                sel = (ends >= lo) & (ends <= hi)
                per.append(first_level_counts(trial_image[sel], pix[sel], vis[sel]) if sel.any()
                           else DetectionCounts(0, 0, 0, 0))
            out.append(per)
    return out


def variant_maps(variant: Variant, frames: np.ndarray, cfg: DPConfig
                 ) -> tuple[np.ndarray, np.ndarray]:
    """``(ends, maps)``: the scored maps of ``variant`` on ADC codes ``frames (N, T, H, W)``
    (``cfg`` = :func:`variant_config`): a segment variant's maps of every segment, a
    recursive variant's maps of the frames ``warmup .. T - 1``; ``maps`` is ``(N, S, H, W)``
    and ``ends`` the last frame of each."""
    if cfg.recursive:
        ends = np.arange(variant.warmup, frames.shape[-3])
        return ends, run_family_fast(frames, cfg).energy[:, ends]
    res = run_fixed_fast(frames, cfg)
    return res.end_frames, res.energy


def variant_counts(variant: Variant, snr: float, velocity: tuple[float, float], *, trials: int,
                   seed: int, chunk: int = 5, size: int = 128) -> DetectionCounts:
    """:func:`variant_trial_counts` summed over the scenes."""
    total = DetectionCounts(0, 0, 0, 0)
    for c in variant_trial_counts(variant, snr, velocity, trials=trials, seed=seed,
                                  chunk=chunk, size=size):
        total = total + c
    return total


def compare(variants, *, trials: int, seed: int, settings=SETTINGS, size: int = 128
            ) -> dict[str, dict[tuple, list[DetectionCounts]]]:
    """``{variant label: {(snr, velocity): per-scene counts}}`` for every variant and setting."""
    return {v.label: {(snr, vel): variant_trial_counts(v, snr, vel, trials=trials, seed=seed,
                                                       size=size)
                      for snr, vel in settings} for v in variants}


def paired_pd_difference(a: list[DetectionCounts], b: list[DetectionCounts]
                         ) -> tuple[float, float, float]:
    """Mean over scenes of Pd(b) - Pd(a) with its 95 % normal interval (scenes paired).

    Each scene's Pd is its detections over its opportunities; the scene, not the map, is
    the independent unit (maps of one scene share its noise through the recursion).
    """
    if len(a) != len(b) or len(a) < 2:
        raise ValueError(f"paired_pd_difference needs two equally long lists of at least 2 "
                         f"scenes, got {len(a)} and {len(b)}")
    diff = np.array([y.pd - x.pd for x, y in zip(a, b)])
    half = 1.959963984540054 * diff.std(ddof=1) / np.sqrt(len(diff))
    return float(diff.mean()), float(diff.mean() - half), float(diff.mean() + half)


def parse_segment_lengths(text: str) -> tuple[int, ...]:
    """``"6,8,12"`` -> the segment lengths K, each an integer in [1, 100], distinct, in the
    given order; refused otherwise."""
    parts = [p.strip() for p in str(text).split(",")]
    try:
        ks = [int(p) for p in parts]
    except ValueError:
        raise DptbdError(f"k must be comma-separated integers in [1, 100], got {text!r}") from None
    ks = tuple(segments(k).segment_frames for k in ks)
    if len(set(ks)) != len(ks):
        raise DptbdError(f"k must hold distinct segment lengths, got {text!r}")
    return ks


def parse_frame_ranges(text: str) -> tuple[tuple[int, int], ...]:
    """``"7-15,64-99"`` -> ``((7, 15), (64, 99))`` (:func:`check_frame_ranges`); refused
    otherwise."""
    out = []
    for part in str(text).split(","):
        bounds = part.strip().split("-")
        try:
            first, last = (int(b) for b in bounds)
        except ValueError:
            raise DptbdError(f"frame ranges must be comma-separated FIRST-LAST pairs of frames, "
                             f"got {text!r}") from None
        out.append((first, last))
    return check_frame_ranges(out)
