"""Confidence intervals for detection and false-alarm probabilities."""

from __future__ import annotations

import math

__all__ = ["wilson_interval", "median_interval"]


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


def median_interval(values, confidence: float = 0.95) -> tuple[float, float]:
    """Distribution-free interval of the median: order statistics ``(x_(l), x_(n+1-l))``.

    ``l`` is the largest rank with ``P(Binomial(n, 1/2) < l) <= (1 - confidence) / 2``, so
    the interval holds the population median with probability >= ``confidence`` for any
    continuous distribution. Below 6 values no rank reaches 95 %: the interval is then the
    whole range ``(min, max)``. Returns ``(nan, nan)`` for no values.
    """
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence!r}")
    xs = sorted(float(v) for v in values)
    n = len(xs)
    if n == 0:
        return (math.nan, math.nan)
    tail = (1.0 - confidence) / 2.0

    def cdf(j: int) -> float:
        return sum(math.comb(n, i) for i in range(j + 1)) / 2 ** n

    rank = 1
    while rank + 1 <= n - rank and cdf(rank) <= tail:
        rank += 1
    return (xs[rank - 1], xs[n - rank])
