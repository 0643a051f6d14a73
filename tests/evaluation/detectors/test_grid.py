"""Paper 004's grid detectors (``grid``): information accumulation and the grid Bayes filter,
both recursions against a dense brute-force implementation on tiny grids; the names
``grid`` re-exports from ``grid_filter``."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError, grid, grid_filter
from dptbd.evaluation.detectors.grid import (
    GridBayes, InfoAccumulation, Transition, gaussian_kernel, rician_log_likelihood)
from helpers.refusals import whole


def info_dense(frames, tr, snr_db):
    """Table 1 written out with the dense T and eq (21)'s product over every cell (eq (22))."""
    dense = tr.dense()
    n_cells = dense.shape[0]
    w = np.full(n_cells, 1.0 / n_cells)
    hs = []
    for z in frames:
        alpha = math.sqrt(np.mean(z ** 2) / 2)
        amp = alpha * math.sqrt(2 * 10 ** (snr_db / 10))
        pred = dense.T @ w                                               # (18)
        like = np.empty(n_cells)
        for c in range(n_cells):                                         # (22): product over cells;
            a_map = np.zeros(n_cells)                                    # only cell c has A != 0
            a_map[c] = amp
            terms = np.exp(-a_map ** 2 / (2 * alpha ** 2)) * np.i0(a_map * z.ravel() / alpha ** 2)
            like[c] = np.prod(terms)
        w = pred * like / np.sum(pred * like)                            # (25)
        hs.append(-np.sum(w[w > 0] * np.log2(w[w > 0])))                 # (26)
    return w.reshape(frames.shape[1:]), np.array(hs)


def tiny_scene(seed=0, shape=(4, 5), n_t=5, target=True):
    rng = np.random.default_rng(seed)
    n = rng.standard_normal((n_t,) + shape) + 1j * rng.standard_normal((n_t,) + shape)
    if target:
        n[:, 1, 2] += 3.0
    return np.abs(n)


def test_info_accumulation_against_dense_brute_force():
    tr = Transition((4, 5), gaussian_kernel(0.6, 0.6, 1), drift=np.array([0.3, 0, -0.2, 0, 0.1]))
    z = tiny_scene()
    run = InfoAccumulation(tr, snr_db=5.0).run(z)
    w_ref, h_ref = info_dense(z, tr, 5.0)
    # the filter's I0 is A&S 9.8.1-2 (relative error < 2e-7), the oracle's numpy.i0
    assert np.allclose(run.posterior, w_ref, rtol=2e-6, atol=1e-15)
    assert np.allclose(run.entropy, h_ref, rtol=2e-6)
    assert np.array_equal(run.statistic, -run.entropy)
    assert tuple(run.estimate[-1]) == np.unravel_index(np.argmax(w_ref), (4, 5)) == (1, 2)
    h0 = math.log2(20)
    found, est = InfoAccumulation(tr, snr_db=5.0, entropy_threshold=h0 / 2).detect(z)
    assert np.array_equal(found, run.entropy < h0 / 2)


def test_grid_bayes_against_dense_brute_force():
    tr = Transition((4, 5), gaussian_kernel(0.6, 0.6, 1))
    z = tiny_scene(seed=3)
    birth, death, snr_db = 0.9, 0.1, 5.0
    filt = GridBayes(tr, snr_db=snr_db, birth=birth, death=death)
    run = filt.run(z)
    # augmented chain: state 0 = no target, 1.. = cells
    dense = tr.dense()
    n = dense.shape[0]
    big = np.zeros((n + 1, n + 1))
    big[0, 0], big[0, 1:] = 1 - birth, birth / n
    big[1:, 0], big[1:, 1:] = death, (1 - death) * dense
    p = np.concatenate([[0.5], np.full(n, 0.5 / n)])
    for t, frame in enumerate(z):
        alpha = math.sqrt(np.mean(frame ** 2) / 2)
        amp = alpha * math.sqrt(2 * 10 ** (snr_db / 10))
        like = np.concatenate([[1.0], np.exp(rician_log_likelihood(frame.ravel(), amp, alpha))])
        p = big.T @ p * like
        p /= p.sum()
        assert math.isclose(run.statistic[t], math.log(p[1:].sum() / p[0]), rel_tol=1e-9)
    assert np.allclose(run.posterior.ravel(), p[1:] / p[1:].sum())


def test_noise_and_target_separate_on_a_small_grid():
    tr = Transition((16, 16), gaussian_kernel(0.5, 0.5, 1))
    info = InfoAccumulation(tr, snr_db=10.0)
    with_target = info.run(tiny_scene(1, (16, 16), 12, True)).entropy[-1]
    noise = info.run(tiny_scene(1, (16, 16), 12, False)).entropy[-1]
    assert with_target < 0.5 < noise


@pytest.mark.parametrize("call, message", [
    (lambda tr: GridBayes(tr, birth=1.0), "birth must be a finite real number in (0, 1), got 1.0"),
    (lambda tr: GridBayes(tr, death=0.0), "death must be a finite real number in (0, 1), got 0.0"),
    (lambda tr: GridBayes(tr, initial_existence=1.5),
     "initial_existence must be a finite real number in (0, 1), got 1.5"),
    (lambda tr: InfoAccumulation(tr, entropy_threshold=0.0),
     "entropy_threshold (H_thr) must be a finite real number in (0, 4], got 0.0"),
    (lambda tr: InfoAccumulation(tr, entropy_threshold=math.log2(16) + 0.1),
     "entropy_threshold (H_thr) must be a finite real number in (0, 4], got 4.1"),
    (lambda tr: InfoAccumulation(tr, snr_db=float("inf")),
     "snr_db (preset SNR channel) must be a finite real number in [-30, 60], got inf"),
    (lambda tr: InfoAccumulation(tr, alpha=0.0),
     "alpha (noise scale) must be a finite real number in (0, inf), got 0.0"),
    (lambda tr: InfoAccumulation(tr, likelihood="poisson"),
     "likelihood must be one of ('rician', 'gaussian'), got 'poisson'"),
    (lambda tr: InfoAccumulation("T"), "transition must be a Transition, got 'T'"),
    (lambda tr: InfoAccumulation(tr).run(np.ones((3, 4, 5))),
     "frames must be one sequence (T, 4, 4), got shape (3, 4, 5)"),
    (lambda tr: InfoAccumulation(tr).run(-np.ones((3, 4, 4))),
     "frames must be magnitudes >= 0 for the Rician likelihood"),
    (lambda tr: InfoAccumulation(tr).detect(np.ones((3, 4, 4))),
     "entropy_threshold (H_thr) must be set to detect"),
])
def test_bad_input_names_the_parameter(call, message):
    tr = Transition((4, 4), gaussian_kernel())
    with pytest.raises(DetectorError, match=whole(message)):
        call(tr)


def test_scenario1_pfa_is_the_fraction_of_frames_below_the_threshold():
    from dptbd.evaluation.detectors.paper004 import scenario1
    res = scenario1(2, 6, preset_snr_db=10.0, shape=(20, 30))
    h0 = math.log2(20 * 30)
    assert res.entropy.shape == (2, 6) and np.all(res.entropy < h0) and np.all(res.entropy >= 0)
    thr = np.sort(res.entropy.ravel())
    pfa = res.pfa([0.0, thr[3], thr[3] + 1e-9, h0])
    assert pfa.tolist() == [0.0, 3 / 12, 4 / 12, 1.0]  # strictly below H_thr
    # the same runs again: seeded
    assert np.array_equal(scenario1(2, 6, preset_snr_db=10.0, shape=(20, 30)).entropy, res.entropy)


def test_grid_filter_names_are_re_exported():
    for name in grid_filter.__all__:
        assert name in grid.__all__ and getattr(grid, name) is getattr(grid_filter, name), name
