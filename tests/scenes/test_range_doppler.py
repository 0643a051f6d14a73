"""The range-Doppler scenes (paper 004): Swerling I statistics, noise/target/seeds, scenario 2 geometry, refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.scenes.range_doppler import (
    PassiveRadar, mean_power_from_snr_db, rd_scene, scenario2_track, straight_track,
    swerling1_amplitudes)
from dptbd.scenes.synthetic import SceneError
from helpers.refusals import whole


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


@pytest.mark.parametrize("kwargs, message", [
    (dict(shape=(0, 5)), "shape[0] (delay cells) must be an integer in [1, 65535], got 0"),
    (dict(shape=(8,)),
     "shape must be a pair (delay cells, Doppler cells) of integers in [1, 65535], got (8,)"),
    (dict(alpha=0.0), "alpha (noise scale) must be a finite real number in (0, inf), got 0.0"),
    (dict(frames=0), "frames must be an integer in [1, inf), got 0"),
    (dict(track=np.zeros((3, 2))), "track must be a finite (4, 2) array of cells, got shape (3, 2)"),
    (dict(snr_db=float("nan")), "snr_db must be a finite real number in (-inf, inf), got nan"),
    (dict(dtype=np.int16), "dtype must be float32 or float64, got int16"),
    (dict(seed=-1), "seed must be an integer in [0, inf), got -1"),
])
def test_rd_scene_bad_input(kwargs, message):
    args = dict(shape=(8, 8), frames=4)
    args.update(kwargs)
    with pytest.raises(SceneError, match=whole(message)):
        rd_scene(**args)
