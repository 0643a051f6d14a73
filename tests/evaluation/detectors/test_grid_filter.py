"""Paper 004's grid filter (``grid_filter``): kernel, transition, likelihood, entropy."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.grid_filter import (
    Transition, check_kernel, entropy_bits, estimate_alpha, gaussian_kernel, log_i0,
    rician_log_likelihood)
from helpers.refusals import whole


def test_gaussian_kernel_is_normalised_and_symmetric():
    for sr, sd, r in [(0.5, 0.5, 1), (1.0, 0.3, 2), (0.0, 0.7, 1)]:
        k = gaussian_kernel(sr, sd, r)
        assert k.shape == (2 * r + 1, 2 * r + 1)
        assert math.isclose(k.sum(), 1.0, abs_tol=1e-15)
        assert np.allclose(k, k[::-1, ::-1])
    assert np.array_equal(gaussian_kernel(0.0, 0.0, 1), np.pad([[1.0]], 1))


@pytest.mark.parametrize("kernel, message", [
    (np.full((3, 3), 0.1), "kernel must sum to 1 (eq (16), a row-stochastic transition), sums to 0.9"),
    (np.ones((2, 3)) / 6, "kernel must be 2-D with odd sides (centred), got shape (2, 3)"),
    (np.ones(9) / 9, "kernel must be 2-D with odd sides (centred), got shape (9,)"),
    (np.array([[0.5, 0.6, -0.1]]), "kernel must be finite and non-negative (transition probabilities)"),
    (np.array([[np.nan, 1.0, 0.0]]), "kernel must be finite and non-negative (transition probabilities)"),
])
def test_bad_kernel_is_refused_by_name(kernel, message):
    with pytest.raises(DetectorError, match=whole(message)):
        check_kernel(kernel)
    with pytest.raises(DetectorError, match=whole(message)):
        Transition((4, 4), kernel)


def dense_kernel_matrix(shape, kernel):
    """T from its definition: K[i - m, j - n] / (kernel mass landing inside), raster order."""
    n_i, n_j = shape
    ri, rj = kernel.shape[0] // 2, kernel.shape[1] // 2
    t = np.zeros((n_i * n_j, n_i * n_j))
    for m in range(n_i):
        for n in range(n_j):
            for a in range(-ri, ri + 1):
                for b in range(-rj, rj + 1):
                    if 0 <= m + a < n_i and 0 <= n + b < n_j:
                        t[m * n_j + n, (m + a) * n_j + n + b] = kernel[a + ri, b + rj]
            t[m * n_j + n] /= t[m * n_j + n].sum()
    return t


def test_transition_matches_its_definition_and_is_row_stochastic():
    k = gaussian_kernel(0.8, 0.4, 1)
    tr = Transition((5, 4), k)
    dense = tr.dense()
    assert np.allclose(dense, dense_kernel_matrix((5, 4), k))
    w = np.random.default_rng(0).random((5, 4))
    assert np.allclose(tr.predict(w).ravel(), dense.T @ w.ravel())  # eq (18)


def test_drift_moves_mass_by_the_doppler_range_rate():
    k = gaussian_kernel(0.0, 0.0, 1)  # no diffusion: only the drift
    tr = Transition((6, 3), k, drift=np.array([0.25, -1.5, 0.0]))
    dense = tr.dense()
    assert np.allclose(dense.sum(axis=1), 1.0)  # eq (16), also at the clamped edges
    w = np.zeros((6, 3))
    w[2] = 1.0
    out = tr.predict(w)
    assert np.allclose(out[:, 0], [0, 0, 0.75, 0.25, 0, 0])
    assert np.allclose(out[:, 1], [0.5, 0.5, 0, 0, 0, 0])
    assert np.allclose(out[:, 2], [0, 0, 1, 0, 0, 0])
    w = np.zeros((6, 3))
    w[0, 1] = 1.0  # would leave the grid: clamped to the edge, mass kept
    assert math.isclose(tr.predict(w)[0, 1], 1.0)


def test_entropy_of_uniform_and_delta_posteriors():
    assert math.isclose(float(entropy_bits(np.full((8, 16), 1 / 128))), 7.0)
    delta = np.zeros((5, 7))
    delta[2, 3] = 1.0
    assert float(entropy_bits(delta)) == 0.0
    two = np.zeros((3, 3))
    two[0, 0] = two[2, 2] = 0.5
    assert math.isclose(float(entropy_bits(two)), 1.0)


def test_log_i0_matches_numpy_and_does_not_overflow():
    x = np.linspace(0, 600, 6001)
    assert np.max(np.abs(log_i0(x) - np.log(np.i0(x)))) < 5e-7
    assert np.isfinite(log_i0(np.array([1e4, 1e6]))).all()


def test_eq21_by_hand_and_rayleigh_noise_scale():
    z, a, alpha = 2.0, 1.5, 0.8
    expect = math.exp(-a * a / (2 * alpha * alpha)) * float(np.i0(a * z / alpha ** 2))
    assert math.isclose(math.exp(float(rician_log_likelihood(z, a, alpha))), expect, rel_tol=1e-6)
    assert float(rician_log_likelihood(z, 0.0, alpha)) == 0.0  # no target: ratio 1
    rng = np.random.default_rng(0)
    z = np.abs(2.0 * (rng.standard_normal((400, 500)) + 1j * rng.standard_normal((400, 500))))
    assert abs(float(estimate_alpha(z)) - 2.0) < 0.01


@pytest.mark.parametrize("call, message", [
    (lambda: Transition((0, 4), gaussian_kernel()),
     "grid shape[0] (I) must be an integer in [1, 65535], got 0"),
    (lambda: Transition((4, 4), gaussian_kernel(), drift=np.zeros(3)),
     "drift must be a finite (4,) array (one per Doppler cell), got shape (3,)"),
    (lambda: gaussian_kernel(-1.0), "sigma_range must be a finite real number in [0, inf), got -1.0"),
])
def test_bad_grid_input_names_the_parameter(call, message):
    with pytest.raises(DetectorError, match=whole(message)):
        call()
