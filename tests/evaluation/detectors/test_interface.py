"""The common detector interface (:mod:`dptbd.evaluation.detectors.interface`): the scene
model, its refusals, the base class's checks (the eight detectors behind it:
test_adapters.py; the scoring: test_scoring.py)."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.adapters import make_detector
from dptbd.evaluation.detectors.interface import Detector, SceneModel
from helpers.refusals import whole


@pytest.mark.parametrize("call, message", [
    (lambda m: make_detector("info", m).decide(np.zeros((1, 4, 5, 5))),
     "frames must be (N, T, 20, 20), got shape (1, 4, 5, 5)"),
    (lambda m: SceneModel((20, 20), "poisson"),
     "noise must be one of ('rayleigh', 'gaussian'), got 'poisson'"),
    (lambda m: SceneModel((20, 20), max_speed=3), "max_speed must be an integer in [1, 2], got 3"),
    (lambda m: SceneModel((0, 20)), "shape[0] (H) must be an integer in [1, 65535], got 0"),
    (lambda m: SceneModel((20, -4)), "shape[1] (W) must be an integer in [1, 65535], got -4"),
    (lambda m: SceneModel((20.5, 20)), "shape[0] (H) must be an integer in [1, 65535], got 20.5"),
    (lambda m: SceneModel((20, 20, 3)),
     "shape must be a pair (H, W) of integers in [1, 65535], got (20, 20, 3)"),
    (lambda m: SceneModel(20), "shape must be a pair (H, W) of integers in [1, 65535], got 20"),
    (lambda m: Detector((20, 20)), "model must be a SceneModel, got (20, 20)"),
    (lambda m: SceneModel((20, 20), scale=0.0),
     "scale (noise) must be a finite real number in (0, inf), got 0.0"),
    (lambda m: SceneModel((20, 20), snr_db=61.0),
     "snr_db (preset SNR channel) must be a finite real number in [-30, 60], got 61.0"),
])
def test_bad_scene_model_and_frames(call, message):
    with pytest.raises(DetectorError, match=whole(message)):
        call(SceneModel((20, 20)))


def test_scene_model_shape_is_normalised():
    m = SceneModel([np.int64(20), 12], scale=2.0)
    assert m.shape == (20, 12) and all(type(v) is int for v in m.shape)
    # the preset channel's amplitude: sqrt(2 SNR) alpha (Rayleigh), sqrt(SNR) sigma (Gaussian)
    assert SceneModel((4, 4), "rayleigh", 2.0, 10.0).amplitude == pytest.approx(2.0 * 20 ** 0.5)
    assert SceneModel((4, 4), "gaussian", 2.0, 20.0).amplitude == pytest.approx(20.0)
