"""Statistics of a comparison (:mod:`dptbd.evaluation.compare.report`): the paired difference
of two proportions, detectors with identical counts sharing a curve."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.evaluation.compare.report import identical_curves, paired_difference


def test_paired_difference():
    # identical detectors: exactly zero, a zero-width interval
    assert paired_difference([3, 5, 2], [3, 5, 2], [10, 10, 10]) == (0.0, 0.0, 0.0)
    # by hand: delta = 2/30; residuals (a - b) - delta n = (4/3, -2/3, -2/3), sum of
    # squares 8/3, times k/(k-1) = 3/2 gives 4: se = 2/30
    d, lo, hi = paired_difference([3, 5, 2], [1, 5, 2], [10, 10, 10])
    z = 1.959963984540054
    assert d == pytest.approx(2 / 30)
    assert (lo, hi) == pytest.approx((2 / 30 - z * 2 / 30, 2 / 30 + z * 2 / 30))
    back = paired_difference([1, 5, 2], [3, 5, 2], [10, 10, 10])   # swapped: sign flips
    assert back == pytest.approx((-d, -hi, -lo))
    # the same difference in every cluster: no spread, a zero-width interval
    assert paired_difference([4, 4], [2, 2], [10, 10]) == pytest.approx((0.2, 0.2, 0.2))
    d1, lo1, hi1 = paired_difference([3], [1], [10])               # one cluster: no interval
    assert d1 == pytest.approx(0.2) and math.isnan(lo1) and math.isnan(hi1)
    assert all(math.isnan(v) for v in paired_difference([0], [0], [0]))
    # pairing: outcomes that move together cancel; the same marginal counts unpaired are wider
    rng = np.random.default_rng(1)
    base = rng.binomial(20, 0.5, 200)
    paired = paired_difference(base + (rng.random(200) < 0.1), base, np.full(200, 21))
    unpaired = paired_difference(base + (rng.random(200) < 0.1), rng.permutation(base),
                                 np.full(200, 21))
    assert paired[2] - paired[1] < 0.3 * (unpaired[2] - unpaired[1])


def test_identical_curves_groups_detectors_with_identical_counts():
    from types import SimpleNamespace
    rng = np.random.default_rng(0)
    det = rng.integers(0, 5, (4, 5, 3))      # (trials, detectors, SNR)
    exc = rng.integers(0, 9, (4, 5, 2))
    det[:, 3] = det[:, 1]                     # detector 3 == detector 1 in every count ...
    exc[:, 3] = exc[:, 1]
    det[:, 2] = det[:, 0]                     # detector 2 == the float model's counts, but a
    exc[:, 2] = exc[:, 0]                     # fixed detector never joins a float curve
    agree = rng.random((4, 5, 4))             # agreement does not split a curve
    counts = {"detections": det, "exceed": exc, "agree_frac": agree, "agree_same": agree}
    names = ["float paper", "a", "b", "c", "d"]
    out = identical_curves(SimpleNamespace(counts=counts), names)
    assert out == {"float paper": "float paper", "a": "a = c", "c": None, "b": "b", "d": "d"}
    det[2, 3, 1] += 1                         # one count differs on one trial: separate curves
    out = identical_curves(SimpleNamespace(counts=counts), names)
    assert out["a"] == "a" and out["c"] == "c"
