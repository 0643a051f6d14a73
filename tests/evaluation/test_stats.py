"""Interval statistics (:mod:`dptbd.evaluation.stats`)."""

import pytest

from dptbd.evaluation.stats import wilson_interval


def test_wilson_interval_known_values():
    lo, hi = wilson_interval(19, 24)
    assert lo == pytest.approx(0.5953, abs=1e-3) and hi == pytest.approx(0.9076, abs=1e-3)
    assert wilson_interval(0, 10)[0] == pytest.approx(0.0) and wilson_interval(10, 10)[1] == pytest.approx(1.0)
    with pytest.raises(ValueError, match=r"^need 0 <= successes <= trials, got 5 of 3$"):
        wilson_interval(5, 3)
