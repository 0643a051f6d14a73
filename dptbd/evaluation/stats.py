"""Confidence intervals for detection and false-alarm probabilities."""

from __future__ import annotations

import math

__all__ = ["wilson_interval"]


def wilson_interval(successes: int, trials: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion (default 95 %).

    The interval always holds the estimate, ``lo <= successes / trials <= hi``, with
    ``lo == 0.0`` at no successes and ``hi == 1.0`` at all successes (the formula gives
    these exactly; its rounding is kept from putting a bound a few ulp on the wrong side).
    Returns ``(nan, nan)`` for zero trials (no interval).
    """
    if trials < 0 or not 0 <= successes <= max(trials, 0):
        raise ValueError(f"need 0 <= successes <= trials, got {successes} of {trials}")
    if trials == 0:
        return (math.nan, math.nan)
    p = successes / trials
    denom = 1.0 + z * z / trials
    centre = (p + z * z / (2 * trials)) / denom
    half = z * math.sqrt(p * (1 - p) / trials + z * z / (4 * trials * trials)) / denom
    return (min(p, max(0.0, centre - half)), max(p, min(1.0, centre + half)))
