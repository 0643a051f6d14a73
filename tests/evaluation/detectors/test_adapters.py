"""The eight detectors by name: the registry's refusals, each detector on a small scene, the
dw-dp adapter against the golden model, the detectors' parameters and their refusals."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.adapters import DETECTORS, make_detector, parse_detectors
from dptbd.evaluation.detectors.interface import SceneModel
from dptbd.model.fixed import run_fixed
from dptbd.scenes.range_doppler import rd_scene, straight_track
from helpers.refusals import whole


def test_parse_detectors():
    assert parse_detectors("info, ca-cfar,info") == ("info", "ca-cfar")
    with pytest.raises(DetectorError, match=(r"^unknown detector 'mht'; known: dw-dp, "
                                             r"dp-amplitude, dp-penalty, dp-likelihood, info, "
                                             r"grid-bayes, ca-cfar, pf-tbd$")):
        parse_detectors("info,mht")
    with pytest.raises(DetectorError, match=(r"^detectors must name at least one of dw-dp, "
                                             r"dp-amplitude, dp-penalty, dp-likelihood, info, "
                                             r"grid-bayes, ca-cfar, pf-tbd$")):
        parse_detectors("")


@pytest.mark.parametrize("name", list(DETECTORS))
def test_every_detector_runs_on_a_small_scene(name):
    model = SceneModel((20, 12), "rayleigh", 1.0, 12.0, 1, None)
    track = straight_track((8, 5), (0.2, 0.1), 10)
    frames = rd_scene((20, 12), 10, track, snr_db=25.0, seed=1, trials=2).frames
    kw = dict(segment_frames=4) if "dp" in name else {}
    dec = make_detector(name, model, **kw).decide(frames)
    assert dec.statistic.shape == (2, 10) and dec.estimate.shape == (2, 10, 2)
    scored = ~np.isnan(dec.statistic)
    assert scored[:, 3:].all()
    if "dp" in name:
        assert not scored[:, :3].any()  # a K-frame segment decides from frame K-1 on
    if name != "dp-likelihood":  # 000's bump merit is not made for a fluctuating target
        near = np.max(np.abs(dec.estimate[:, -1] - np.rint(track[-1])), axis=-1) <= 1
        assert near.all()


def test_dw_dp_adapter_is_the_golden_model():
    model = SceneModel((9, 10), "gaussian", 1.0, 10.0, 2, None)
    det = make_detector("dw-dp", model, segment_frames=3)
    frames = np.random.default_rng(0).normal(size=(2, 5, 9, 10))
    dec = det.decide(frames)
    codes = det.codes(frames)
    cfg = DPConfig(width=10, height=9, segment_frames=3, segment_stride=1, input_bits=10,
                   energy_bits=16, radius=2)
    energy = run_fixed(codes, cfg).energy
    assert np.array_equal(dec.statistic[:, 2:], energy.reshape(2, 3, -1).max(axis=-1))


@pytest.mark.parametrize("call, message", [
    (lambda m: make_detector("dw-dp", m, segment_frames=0),
     "segment_frames must be an integer in [1, 64], got 0"),
    (lambda m: make_detector("dp-penalty", m, alpha=2.0),
     "alpha (eq (22) coefficient) must be a finite real number in [0, 1], got 2.0"),
    (lambda m: make_detector("dp-likelihood", m, epsilon=1.2),
     "epsilon (printed alpha in 000 §5.2) must be a finite real number in (0, 1), got 1.2"),
    (lambda m: make_detector("dp-amplitude", m, sigma=-1.0),
     "sigma (printed delta in 000 §5.2) must be a finite real number in (0, inf), got -1.0"),
    (lambda m: make_detector("info", m, kernel=np.ones((3, 3))),
     "kernel must sum to 1 (eq (16), a row-stochastic transition), sums to 9.0"),
    (lambda m: make_detector("grid-bayes", m, birth=0.0),
     "birth must be a finite real number in (0, 1), got 0.0"),
    (lambda m: make_detector("ca-cfar", m, n_ref=64),
     "the CFAR axis has 20 cells; n_ref=64 reference and n_guard=2 guard cells need at least 67"),
    (lambda m: make_detector("nope", m),
     "unknown detector 'nope'; known: dw-dp, dp-amplitude, dp-penalty, dp-likelihood, info, grid-bayes, ca-cfar, pf-tbd"),
    (lambda m: make_detector("info", m, entropy=1.0),
     "detector 'info' has no parameter 'entropy'; it has: kernel, sigma_kernel, known_noise"),
    (lambda m: make_detector("dp-amplitude", m, alpha=1.5),
     "alpha (eq (22) coefficient) must be a finite real number in [0, 1], got 1.5"),
    (lambda m: make_detector("ca-cfar", m, axis=5),
     "axis must be -2 (range, rows) or -1 (Doppler, columns), got 5"),
    (lambda m: make_detector("ca-cfar", m, axis=0),
     "axis must be -2 (range, rows) or -1 (Doppler, columns), got 0"),
    (lambda m: make_detector("ca-cfar", m, axis=True),
     "axis must be -2 (range, rows) or -1 (Doppler, columns), got True"),
    (lambda m: make_detector("ca-cfar", m, n_guard=-2),
     "n_guard (guard cells) must be an integer in [0, inf), got -2"),
    (lambda m: make_detector("info", m, sigma_kernel=-1.0),
     "sigma_kernel (kernel standard deviation, cells) must be a finite real number in [0, inf), got -1.0"),
    (lambda m: make_detector("grid-bayes", m, sigma_kernel=float("nan")),
     "sigma_kernel (kernel standard deviation, cells) must be a finite real number in [0, inf), got nan"),
    (lambda m: make_detector("info", m, kernel=np.ones((1, 1)), sigma_kernel=0.5),
     "give kernel or sigma_kernel, not both"),
    (lambda m: make_detector("info", m, known_noise="yes"), "known_noise must be true or false, got 'yes'"),
    (lambda m: make_detector("grid-bayes", m, known_noise=1), "known_noise must be true or false, got 1"),
])
def test_bad_detector_parameters(call, message):
    with pytest.raises(DetectorError, match=whole(message)):
        call(SceneModel((20, 20)))


def test_parameters_reach_the_detectors_as_python_values():
    m = SceneModel((20, 12), scale=2.0)
    assert make_detector("info", m, known_noise=np.bool_(True)).alpha == 2.0
    assert make_detector("info", m, known_noise=False).alpha is None
    # sigma_kernel sets a Gaussian kernel of radius max_speed
    k = make_detector("grid-bayes", m, sigma_kernel=0.0).transition.kernel
    assert k.shape == (3, 3) and k[1, 1] == 1.0
    det = make_detector("ca-cfar", m, axis=np.int64(-1), n_ref=np.int64(8))
    assert (det.axis, det.n_ref) == (-1, 8) and type(det.axis) is int
