"""The wake a detection map keeps of a target's past positions (first level).

On paper 001's Table 1 setting (the scenes of :mod:`~dptbd.evaluation.family.detection`),
every scored map of a variant keeps its n = 33 largest pixels (``candidate_mask``). For a
map whose last frame is t and a lag L:

* an *opportunity* is a frame t − L >= 0 in which the target was visible, with the target
  also visible at t and its pixel at t − L **outside the detection gate** of its pixel at t
  (Chebyshev distance > 1): a past position that, if kept, is a false point;
* a *hit* is such a past pixel among the map's n largest: P(kept at lag L) = hits /
  opportunities.

Beside it, the map's false points (kept pixels outside the gate of the current position,
as :func:`~dptbd.evaluation.metrics.first_level_counts` counts them) and how many of them
lie within ``near`` pixels (Chebyshev) of the target's visible positions of the
``history`` frames t − history .. t − 1 (on and around its past track).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.errors import DptbdError, check_int
from dptbd.evaluation.family.detection import FRAMES, Variant, variant_scene_maps
from dptbd.evaluation.metrics import near_mask
from dptbd.evaluation.table1.experiment import FALSE_ALARM_RATE
from dptbd.model.segmentation import candidate_mask, count_for_rate

__all__ = ["WakeCounts", "check_lags", "parse_lags", "wake_counts"]


@dataclasses.dataclass(frozen=True)
class WakeCounts:
    """Wake counts of one or more scenes: ``hits[i]`` / ``opportunities[i]`` at ``lags[i]``;
    ``false_points`` and ``near_track`` (of them, near the past track) over ``maps`` maps.
    Sums with ``+`` (same lags)."""

    lags: tuple[int, ...]
    hits: tuple[int, ...]
    opportunities: tuple[int, ...]
    false_points: int
    near_track: int
    maps: int

    def __add__(self, other: "WakeCounts") -> "WakeCounts":
        if self.lags != other.lags:
            raise DptbdError(f"wake counts of lags {self.lags} and {other.lags} cannot be added")
        return WakeCounts(self.lags, tuple(a + b for a, b in zip(self.hits, other.hits)),
                          tuple(a + b for a, b in zip(self.opportunities, other.opportunities)),
                          self.false_points + other.false_points,
                          self.near_track + other.near_track, self.maps + other.maps)

    def kept(self, lo: int, hi: int) -> tuple[int, int]:
        """``(hits, opportunities)`` pooled over the lags in ``[lo, hi]``."""
        sel = [i for i, lag in enumerate(self.lags) if lo <= lag <= hi]
        return sum(self.hits[i] for i in sel), sum(self.opportunities[i] for i in sel)


def check_lags(lags) -> tuple[int, ...]:
    """``lags`` as a tuple of distinct integers in [1, 99], ascending; refused otherwise."""
    out = tuple(check_int(f"lags[{i}]", lag, 1, FRAMES - 1) for i, lag in enumerate(lags))
    if not out:
        raise DptbdError("lags must hold at least one lag in [1, 99]")
    if len(set(out)) != len(out) or list(out) != sorted(out):
        raise DptbdError(f"lags must be distinct and ascending, got {list(out)}")
    return out


def _scene_counts(mask: np.ndarray, ends: np.ndarray, pixel: np.ndarray, visible: np.ndarray,
                  lags: tuple[int, ...], near: int, history: int) -> WakeCounts:
    hits = np.zeros(len(lags), dtype=np.int64)
    opps = np.zeros(len(lags), dtype=np.int64)
    false_points = near_track = 0
    for m, t in zip(mask, ends):
        if not visible[t]:
            false_points += int(np.count_nonzero(m))
            continue
        gate = near_mask(m.shape, pixel[t][None], 1)
        false = m & ~gate
        false_points += int(np.count_nonzero(false))
        past = [u for u in range(max(t - history, 0), t) if visible[u]]
        if past:
            near_track += int(np.count_nonzero(false & near_mask(m.shape, pixel[past], near)))
        for i, lag in enumerate(lags):
            u = t - lag
            if u < 0 or not visible[u] or np.max(np.abs(pixel[u] - pixel[t])) <= 1:
                continue
            opps[i] += 1
            hits[i] += bool(m[pixel[u][0], pixel[u][1]])
    return WakeCounts(lags, tuple(int(h) for h in hits), tuple(int(o) for o in opps),
                      false_points, near_track, len(ends))


def wake_counts(variant: Variant, snr: float, velocity: tuple[float, float], *, lags,
                trials: int, seed: int, near: int = 3, history: int = 40, chunk: int = 5,
                size: int = 128) -> list[WakeCounts]:
    """:class:`WakeCounts` of one variant on one Table 1 setting, one per scene: ``trials``
    scenes from ``seed`` (those of ``detection.variant_trial_counts``), at ``lags``
    (:func:`check_lags`); ``near`` in [0, 10] pixels, ``history`` in [1, 99] frames."""
    lags = check_lags(lags)
    near = check_int("near", near, 0, 10)
    history = check_int("history", history, 1, FRAMES - 1)
    trials = check_int("trials", trials, 1)
    count = count_for_rate(FALSE_ALARM_RATE, size * size)
    out = []
    for ends, images, truth in variant_scene_maps(variant, snr, velocity, trials=trials,
                                                  seed=seed, chunk=chunk, size=size):
        for mask in candidate_mask(images, count):
            out.append(_scene_counts(mask, ends, truth.pixel, truth.visible, lags, near, history))
    return out


def parse_lags(text: str) -> tuple[int, ...]:
    """``"1-40"`` or ``"2,10,20"`` (or both, comma-separated) -> the lags (:func:`check_lags`)."""
    out = []
    for part in str(text).split(","):
        bounds = part.strip().split("-")
        try:
            lo, hi = (int(bounds[0]), int(bounds[-1])) if len(bounds) <= 2 else (None, None)
        except ValueError:
            lo = None
        if lo is None:
            raise DptbdError(f"lags must be comma-separated integers or FIRST-LAST ranges, got {text!r}")
        out.extend(range(lo, hi + 1) if hi >= lo else [lo, hi])
    return check_lags(out)
