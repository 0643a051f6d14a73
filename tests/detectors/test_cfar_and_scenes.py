"""CA-CFAR against a direct loop, its false-alarm rate, and the range-Doppler scenes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.model.detectors import DetectorError
from dptbd.model.detectors.cfar import ca_cfar_detect, ca_cfar_factor, ca_cfar_ratio, reference_counts
from dptbd.model.detectors.rd_scenes import (
    PassiveRadar, mean_power_from_snr_db, rd_scene, scenario2_track, straight_track,
    swerling1_amplitudes)
from dptbd.model.stats import wilson_interval


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


@pytest.mark.parametrize("kwargs,name", [
    (dict(n_ref=15), "even"), (dict(n_guard=3), "even"), (dict(n_ref=0), "n_ref"),
    (dict(n_guard=-2), "n_guard"), (dict(axis=0), "axis"),
])
def test_ca_cfar_bad_parameters(kwargs, name):
    with pytest.raises(DetectorError, match=name):
        ca_cfar_ratio(np.ones((40, 3)), **kwargs)


def test_ca_cfar_short_axis_and_pfa():
    with pytest.raises(DetectorError, match="at least 19"):
        ca_cfar_ratio(np.ones((18, 3)))
    with pytest.raises(DetectorError, match="pfa"):
        ca_cfar_detect(np.ones((40, 3)), 1.0)
    with pytest.raises(DetectorError, match=">= 0"):
        ca_cfar_ratio(-np.ones((40, 3)))


def test_swerling1_amplitude_statistics():
    rng = np.random.default_rng(5)
    p = 3.0
    a = swerling1_amplitudes(rng, p, 200_000)
    power = np.abs(a) ** 2
    assert abs(power.mean() / p - 1) < 0.01                      # mean power P
    assert abs(power.var() / p ** 2 - 1) < 0.03                  # exponential: variance P**2
    assert abs(np.mean(power > p) - math.exp(-1)) < 0.005       # P(|A|^2 > P) = 1/e
    assert abs(np.mean(np.exp(1j * np.angle(a)))) < 0.01        # uniform phase
    assert abs(np.mean(np.abs(a)) - math.sqrt(math.pi * p) / 2) < 0.01  # Rayleigh amplitude


def test_rd_scene_noise_target_and_seeds():
    track = straight_track((5.2, 7.0), (0.5, -0.25), 6)
    sc = rd_scene((12, 20), 6, track, snr_db=20.0, alpha=2.0, seed=3, trials=4)
    noise = rd_scene((12, 20), 6, None, alpha=2.0, seed=3, trials=4)
    assert sc.frames.shape == (4, 6, 12, 20) and sc.frames.dtype == np.float32
    assert np.array_equal(sc.pixel, np.rint(track).astype(int)) and sc.visible.all()
    off = np.ones(sc.frames.shape, dtype=bool)
    off[:, np.arange(6), sc.pixel[:, 0], sc.pixel[:, 1]] = False
    assert np.array_equal(sc.frames[off], noise.frames[off])  # noise does not depend on the target
    on = sc.frames[:, np.arange(6), sc.pixel[:, 0], sc.pixel[:, 1]]
    assert on.mean() > 5 * noise.frames.mean()
    # trial k is the same whatever the batch
    one = rd_scene((12, 20), 6, track, snr_db=20.0, alpha=2.0, seed=3, first_trial=2)
    assert np.array_equal(one.frames, sc.frames[2])
    big = rd_scene((100, 100), 10, None, alpha=2.0, seed=9).frames.astype(float)
    assert abs(np.mean(big ** 2) / (2 * 4.0) - 1) < 0.01       # E|n|^2 = 2 alpha^2
    assert math.isclose(mean_power_from_snr_db(10.0, 2.0), 80.0)


def test_scenario2_geometry():
    radar = PassiveRadar()
    track = scenario2_track(radar, 50)
    assert np.allclose(track[0], [148.15, 187.87], atol=0.01)   # eqs (3)-(4), (8)-(9)
    assert np.all((track >= 0) & (track < np.array(radar.shape)))
    drift = radar.range_drift()[int(round(track[0, 1]))]
    assert abs(np.mean(np.diff(track[:, 0])) - drift) < 0.01    # range rate = Doppler-implied drift


@pytest.mark.parametrize("kwargs,name", [
    (dict(shape=(0, 5)), "delay cells"), (dict(alpha=0.0), "alpha"), (dict(frames=0), "frames"),
    (dict(track=np.zeros((3, 2))), "track"), (dict(snr_db=float("nan")), "snr_db"),
    (dict(dtype=np.int16), "dtype"), (dict(seed=-1), "seed"),
])
def test_rd_scene_bad_input(kwargs, name):
    args = dict(shape=(8, 8), frames=4)
    args.update(kwargs)
    with pytest.raises(DetectorError, match=name):
        rd_scene(**args)
