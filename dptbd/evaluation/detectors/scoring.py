"""Scoring the detectors of :mod:`~dptbd.evaluation.detectors.interface` at equal Pfa: the
threshold set on noise-only decisions (:func:`calibrate`) and the counts of detections and
false alarms against it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from dptbd.evaluation.detectors._checks import DetectorError, check_int, check_prob
from dptbd.evaluation.detectors.interface import Decisions

__all__ = ["calibrate", "Counts", "count_detections", "count_false_alarms"]


def calibrate(statistics: np.ndarray, false_alarm_rate: float) -> float:
    """The threshold with at most ``false_alarm_rate`` of the noise-only decisions above it.

    Like ``docs/arithmetic.md`` §6: with n = floor(rate * decisions), the threshold is the
    (n+1)-th largest statistic, and a decision is a false alarm when ``statistic >
    threshold`` (ties never count). NaN entries (no decision) are ignored.
    """
    rate = check_prob("false_alarm_rate", false_alarm_rate)
    s = np.asarray(statistics, dtype=np.float64)
    s = s[~np.isnan(s)]
    n = int(math.floor(rate * s.size))
    if n < 1:
        raise DetectorError(
            f"false_alarm_rate={rate:g} needs at least {math.ceil(1 / rate)} noise-only decisions "
            f"to set a threshold, got {s.size}; raise the noise trials or the rate")
    return float(np.partition(s, s.size - n - 1)[s.size - n - 1])


@dataclasses.dataclass(frozen=True)
class Counts:
    """Successes out of trials (detections of opportunities, or false alarms of decisions)."""

    hits: int
    total: int

    @property
    def rate(self) -> float:
        return self.hits / self.total if self.total else float("nan")


def count_detections(dec: Decisions, threshold: float, pixel: np.ndarray, visible: np.ndarray,
                     *, first_frame: int = 0, gate: int = 1) -> Counts:
    """Decisions above threshold whose estimate is within ``gate`` of the true cell.

    Opportunities: every (trial, frame >= first_frame) with a decision and a visible target.
    """
    gate = check_int("gate", gate, 0)
    stat, est = dec.statistic, dec.estimate
    n_t = stat.shape[1]
    frames = np.arange(n_t)
    use = (frames >= first_frame) & np.asarray(visible, dtype=bool)
    ok = ~np.isnan(stat) & use[None, :]
    near = np.max(np.abs(est - np.asarray(pixel)[None, :, :]), axis=-1) <= gate
    with np.errstate(invalid="ignore"):
        hit = ok & near & (stat > threshold)
    return Counts(int(hit.sum()), int(ok.sum()))


def count_false_alarms(dec: Decisions, threshold: float, *, first_frame: int = 0) -> Counts:
    """Noise-only decisions above threshold, of all decisions from ``first_frame`` on."""
    stat = dec.statistic[:, first_frame:]
    ok = ~np.isnan(stat)
    with np.errstate(invalid="ignore"):
        return Counts(int((ok & (stat > threshold)).sum()), int(ok.sum()))
