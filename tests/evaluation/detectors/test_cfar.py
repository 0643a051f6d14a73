"""CA-CFAR against a direct loop and its false-alarm rate."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.cfar import ca_cfar_detect, ca_cfar_factor, ca_cfar_ratio, reference_counts
from dptbd.evaluation.stats import wilson_interval
from helpers.refusals import whole


def cfar_loop(z, n_ref, n_guard):
    """Direct CA-CFAR along axis 0 with the edge rule of docs/detectors.md §2.3, cell by cell."""
    length, width = z.shape
    half, g = n_ref // 2, n_guard // 2
    out = np.zeros(z.shape)
    for col in range(width):
        for i in range(length):
            left = [k for k in range(i - g - 1, -1, -1)]        # nearest first
            right = [k for k in range(i + g + 1, length)]
            nl = min(half, len(left))
            nr = min(half, len(right))
            nl, nr = nl + (half - nr), nr + (half - nl)          # complete from the other side
            ref = left[:nl] + right[:nr]
            assert len(ref) == n_ref and all(abs(k - i) > g for k in ref)
            out[i, col] = z[i, col] ** 2 / np.mean(z[ref, col] ** 2)
    return out


@pytest.mark.parametrize("length,n_ref,n_guard", [(40, 16, 2), (19, 16, 2), (23, 8, 4), (7, 2, 0)])
def test_ca_cfar_matches_the_direct_loop(length, n_ref, n_guard):
    z = np.abs(np.random.default_rng(length).normal(size=(length, 6)))
    fast = ca_cfar_ratio(z, n_ref=n_ref, n_guard=n_guard, axis=-2)
    assert np.allclose(fast, cfar_loop(z, n_ref, n_guard))
    # the Doppler axis is the same operation on the transpose
    assert np.allclose(ca_cfar_ratio(z.T, n_ref=n_ref, n_guard=n_guard, axis=-1), fast.T)
    left, right = reference_counts(length, n_ref, n_guard)
    assert np.all(left + right == n_ref)


def test_ca_cfar_false_alarm_rate_on_rayleigh_noise():
    rng = np.random.default_rng(11)
    z = np.abs(rng.standard_normal((200, 1000)) + 1j * rng.standard_normal((200, 1000)))
    pfa = 0.01
    hits = int(ca_cfar_detect(z, pfa).sum())
    lo, hi = wilson_interval(hits, z.size, z=3.3)
    assert lo <= pfa <= hi
    assert math.isclose(ca_cfar_factor(16, 1e-5), 16 * (1e-5 ** (-1 / 16) - 1))


@pytest.mark.parametrize("kwargs, message", [
    (dict(n_ref=15), "n_ref and n_guard count both sides and must be even, got n_ref=15, n_guard=2"),
    (dict(n_guard=3), "n_ref and n_guard count both sides and must be even, got n_ref=16, n_guard=3"),
    (dict(n_ref=0), "n_ref (reference cells) must be an integer in [2, inf), got 0"),
    (dict(n_guard=-2), "n_guard (guard cells) must be an integer in [0, inf), got -2"),
    (dict(axis=0), "axis must be -2 (range, rows) or -1 (Doppler, columns), got 0"),
])
def test_ca_cfar_bad_parameters(kwargs, message):
    with pytest.raises(DetectorError, match=whole(message)):
        ca_cfar_ratio(np.ones((40, 3)), **kwargs)


def test_ca_cfar_short_axis_and_pfa():
    with pytest.raises(DetectorError, match=(r"^the CFAR axis has 18 cells; n_ref=16 reference "
                                             r"and n_guard=2 guard cells need at least 19$")):
        ca_cfar_ratio(np.ones((18, 3)))
    with pytest.raises(DetectorError, match=(r"^pfa must be a finite real number in \(0, 1\), "
                                             r"got 1\.0$")):
        ca_cfar_detect(np.ones((40, 3)), 1.0)
    with pytest.raises(DetectorError, match=r"^frames must be magnitudes >= 0, found -1$"):
        ca_cfar_ratio(-np.ones((40, 3)))
