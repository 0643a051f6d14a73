"""Interval statistics (:mod:`dptbd.evaluation.stats`)."""

import math

import pytest

from dptbd.evaluation.stats import median_interval, wilson_interval


def test_wilson_interval_known_values():
    lo, hi = wilson_interval(19, 24)
    assert lo == pytest.approx(0.5953, abs=1e-3) and hi == pytest.approx(0.9076, abs=1e-3)
    assert wilson_interval(0, 10)[0] == pytest.approx(0.0) and wilson_interval(10, 10)[1] == pytest.approx(1.0)
    with pytest.raises(ValueError, match=r"^need 0 <= successes <= trials, got 5 of 3$"):
        wilson_interval(5, 3)


@pytest.mark.parametrize("z", [1.959963984540054, 3.3])
def test_wilson_interval_holds_its_estimate_exactly_at_the_ends(z):
    """The formula's rounding put 0 of 6 at lo = 2.8e-17 > 0 and 10 of 10 at hi = 1 - 1e-16 < 1
    (a negative error bar in ``dptbd detectors``' figure)."""
    for n in range(1, 301):
        assert wilson_interval(0, n, z)[0] == 0.0 and wilson_interval(n, n, z)[1] == 1.0
        for k in range(n + 1):
            lo, hi = wilson_interval(k, n, z)
            assert 0.0 <= lo <= k / n <= hi <= 1.0
    assert all(math.isnan(b) for b in wilson_interval(0, 0))  # no trials: no interval


@pytest.mark.parametrize("n, ranks", [(40, (14, 27)), (100, (40, 61)), (6, (1, 6)), (5, (1, 5)),
                                      (1, (1, 1))])
def test_median_interval_order_statistics(n, ranks):
    """Ranks of the 95 % interval: the standard table (n = 40: 14th and 27th values)."""
    values = [10.0 * i for i in range(n, 0, -1)]          # any order
    assert median_interval(values) == (10.0 * ranks[0], 10.0 * ranks[1])


def test_median_interval_coverage_is_at_least_its_confidence():
    for n in range(6, 200):
        lo, hi = (int(v) for v in median_interval(range(1, n + 1)))
        below = sum(math.comb(n, i) for i in range(lo)) / 2 ** n
        assert 1 - 2 * below >= 0.95
        # one rank further in would fall short
        if lo + 1 <= n - lo:
            assert 1 - 2 * (below + math.comb(n, lo) / 2 ** n) < 0.95


def test_median_interval_of_nothing_and_refusal():
    assert all(math.isnan(b) for b in median_interval([]))
    with pytest.raises(ValueError, match=r"^confidence must be in \(0, 1\), got 1\.0$"):
        median_interval([1.0], confidence=1.0)
