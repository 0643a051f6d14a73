"""The SNR-loss arithmetic of ``dptbd compare`` (:mod:`dptbd.evaluation.snr_loss`): the
crossing of a Pd level, the paired bootstrap of the loss, clustered Wilson intervals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.errors import DptbdError
from dptbd.evaluation import sweep
from dptbd.evaluation.snr_loss import (
    bootstrap_losses, clustered_wilson, crossing, isotonic, snr_db)
from dptbd.evaluation.stats import wilson_interval


def test_crossing_interpolates_linearly_between_grid_points():
    x = [0.0, 1.0, 2.0, 3.0]
    assert crossing(x, [0.2, 0.4, 0.6, 0.8], 0.5) == pytest.approx(1.5)
    assert crossing(x, [0.2, 0.4, 0.6, 0.9], 0.8) == pytest.approx(2.0 + 0.2 / 0.3)
    assert crossing(x, [0.2, 0.5, 0.6, 0.9], 0.5) == pytest.approx(1.0)  # exactly on a point
    assert crossing(x, [0.6, 0.7, 0.8, 0.9], 0.5) == -math.inf             # below the grid
    assert crossing(x, [0.1, 0.2, 0.3, 0.4], 0.5) == math.inf              # never reached


def test_crossing_makes_the_curve_monotone_first():
    # a dip (0.6 then 0.4) is pooled to 0.5, 0.5: one crossing, at the first pooled point
    assert np.allclose(isotonic([0.1, 0.6, 0.4, 0.7]), [0.1, 0.5, 0.5, 0.7])
    assert np.allclose(isotonic([0.1, 0.6, 0.4, 0.7], [1, 1, 3, 1]), [0.1, 0.45, 0.45, 0.7])
    assert crossing([0, 1, 2, 3], [0.1, 0.6, 0.4, 0.7], 0.5) == pytest.approx(1.0)


def test_bad_input_is_refused_naming_it():
    with pytest.raises(DptbdError, match=r"^the SNR grid must be at least 2 finite, strictly "
                                         r"increasing values, got \[0\. 2\. 1\.\]$"):
        crossing([0, 2, 1], [0.1, 0.5, 0.9], 0.5)
    with pytest.raises(DptbdError, match=r"^pd and weights must match the grid's shape \(3,\)$"):
        crossing([0, 1, 2], [0.1, 0.5], 0.5)
    with pytest.raises(DptbdError, match=r"^level must be a finite real number in \(0, 1\), "
                                         r"got 1\.0$"):
        crossing([0, 1, 2], [0.1, 0.5, 0.9], 1.0)
    with pytest.raises(DptbdError, match=r"^y and w must be equal-length non-empty vectors, "
                                         r"got \(0,\), \(0,\)$"):
        isotonic([])
    with pytest.raises(DptbdError, match=r"^weights must be > 0$"):
        isotonic([0.1, 0.2], [1.0, 0.0])
    with pytest.raises(DptbdError, match=r"^detections must be \(D, 3, N\) and opportunities "
                                         r"\(3, N\), got \(1, 2, 4\) and \(2, 4\)$"):
        bootstrap_losses([0, 1, 2], np.zeros((1, 2, 4)), np.ones((2, 4)), [(0, 0)], (0.5,))


def _curves(n_trials: int, pd_ref, pd_det, opp: int = 20, seed: int = 0):
    """Per-trial detections drawn from given Pd curves."""
    rng = np.random.default_rng(seed)
    det = np.stack([rng.binomial(opp, np.broadcast_to(np.asarray(p)[:, None], (len(p), n_trials)))
                    for p in (pd_ref, pd_det)])
    return det, np.full((len(pd_ref), n_trials), opp)


def test_loss_of_an_identical_detector_is_exactly_zero():
    x = snr_db([1.5, 2.0, 2.5, 3.0])
    det, opp = _curves(50, [0.2, 0.5, 0.8, 0.95], [0.2, 0.5, 0.8, 0.95])
    det[1] = det[0]
    (est,) = bootstrap_losses(x, det, opp, [(1, 0)], (0.5, 0.8), n_boot=200, seed=1)
    for e in est:
        assert e.loss == 0.0 and e.lo == 0.0 and e.hi == 0.0
        assert e.within(0.1) and not e.differs()


def test_loss_of_a_shifted_curve_is_the_shift_and_its_interval_covers_it():
    # the detector's Pd at grid point j is the reference's at j - 1: it needs one grid
    # step (1 dB) more SNR wherever both curves are linear in between
    x = np.arange(0.0, 8.0)
    ref = np.array([0.05, 0.15, 0.3, 0.45, 0.6, 0.75, 0.88, 0.97])
    det_pd = np.concatenate([[0.01], ref[:-1]])
    det, opp = _curves(400, ref, det_pd, opp=50, seed=2)
    est = bootstrap_losses(x, det, opp, [(1, 0), (0, 1)], (0.5, 0.8), n_boot=400, seed=3)
    for e, back in zip(est[0], est[1]):
        assert e.lo < 1.0 < e.hi and e.hi - e.lo < 0.5
        assert e.loss == pytest.approx(1.0, abs=0.2)
        assert back.loss == pytest.approx(-e.loss)  # swapping the pair flips the sign
        assert e.beyond(0.1) and e.differs()


def test_loss_interval_is_unbounded_when_the_level_is_not_reached():
    x = snr_db([1.5, 2.0, 2.5])
    det, opp = _curves(40, [0.3, 0.6, 0.9], [0.0, 0.05, 0.1])
    (est,) = bootstrap_losses(x, det, opp, [(1, 0)], (0.5,), n_boot=100, seed=0)
    assert est[0].loss == math.inf and est[0].hi == math.inf and est[0].beyond(0.1)
    assert sweep.verdict(est, 0.1) == "beyond"
    (est0,) = bootstrap_losses(x, det, opp, [(1, 0)], (0.5,), n_boot=0)
    assert math.isnan(est0[0].lo) and sweep.verdict(est0, 0.1) == "undecided"


def test_clustered_wilson():
    # one cluster, or clusters with no extra spread: exactly Wilson
    p, lo, hi, deff = clustered_wilson([30], [100])
    assert (p, (lo, hi), deff) == (0.3, wilson_interval(30, 100), 1.0)
    p, lo, hi, deff = clustered_wilson([30, 30, 30], [100, 100, 100])
    assert deff == 1.0 and (lo, hi) == pytest.approx(wilson_interval(90, 300))
    # all-or-nothing clusters: the interval widens by the design effect (here ~ n_i)
    p, lo, hi, deff = clustered_wilson([100, 0, 100, 0], [100] * 4)
    assert p == 0.5 and deff > 50 and hi - lo > 0.5
    assert all(math.isnan(v) for v in clustered_wilson([0], [0]))
