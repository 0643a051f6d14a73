"""The common detector interface (the scene model, refusals of detector parameters), the
comparison and ``dptbd detectors`` (the registry: test_adapters.py; the scoring:
test_scoring.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.adapters import make_detector
from dptbd.evaluation.detectors.interface import SceneModel
from dptbd.evaluation.detectors.paper000 import crossing_snr, peak_mask, run_case, CASES
from dptbd.evaluation.detectors.pd_vs_snr import SceneSpec, run_comparison
from helpers.refusals import whole


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
     "unknown detector 'nope'; known: dw-dp, dp-amplitude, dp-penalty, dp-likelihood, info, grid-bayes, ca-cfar"),
    (lambda m: make_detector("info", m, entropy=1.0),
     "detector 'info' has no parameter 'entropy'; it has: kernel, sigma_kernel, known_noise"),
    (lambda m: make_detector("dp-amplitude", m, alpha=1.5),
     "alpha (eq (22) coefficient) must be a finite real number in [0, 1], got 1.5"),
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


def test_scene_model_shape_is_normalised_and_known_noise_reaches_the_filter():
    m = SceneModel([np.int64(20), 12], scale=2.0)
    assert m.shape == (20, 12) and all(type(v) is int for v in m.shape)
    assert make_detector("info", m, known_noise=np.bool_(True)).alpha == 2.0
    assert make_detector("info", m, known_noise=False).alpha is None
    # sigma_kernel sets a Gaussian kernel of radius max_speed
    k = make_detector("grid-bayes", m, sigma_kernel=0.0).transition.kernel
    assert k.shape == (3, 3) and k[1, 1] == 1.0
    det = make_detector("ca-cfar", m, axis=np.int64(-1), n_ref=np.int64(8))
    assert (det.axis, det.n_ref) == (-1, 8) and type(det.axis) is int


def test_comparison_equal_pfa_and_order():
    spec = SceneSpec(kind="rd", frames=10, crop=(120, 160, 32, 48))
    res = run_comparison(["ca-cfar", "info"], snrs_db=[20.0], spec=spec, trials=4, noise_trials=10,
                         false_alarm_rate=0.05, jobs=1, params={"info": {"known_noise": True}})
    assert res.params["first_frame"] == 7
    for name in ("ca-cfar", "info"):
        fa = res.false_alarms[name]
        assert fa.total == 30 and fa.hits <= math.floor(0.05 * 30)
        assert res.detections[(name, 20.0)].total == 12
    assert res.detections[("info", 20.0)].rate > 0.5
    matched = run_comparison(["ca-cfar", "info"], snrs_db=[10.0, 20.0], spec=spec, trials=2, noise_trials=10,
                             false_alarm_rate=0.05, jobs=1, matched=True)
    assert set(matched.thresholds["info"]) == {10.0, 20.0}  # recalibrated per preset channel
    assert isinstance(matched.thresholds["ca-cfar"], float)  # CFAR has no channel: calibrated once
    assert matched.thresholds["ca-cfar"] == res.thresholds["ca-cfar"]
    with pytest.raises(DetectorError, match=(r"^false_alarm_rate=0\.01 needs at least 100 "
                                             r"noise-only decisions, 2 noise trials give 6; "
                                             r"raise noise_trials$")):
        run_comparison(["info"], snrs_db=[0.0], spec=spec, noise_trials=2, false_alarm_rate=0.01, jobs=1)
    with pytest.raises(DetectorError, match=(r"^crop row0 must be an integer in \[0, 136\], "
                                             r"got 190$")):
        SceneSpec(crop=(190, 0, 64, 128))


def test_comparison_on_a_dask_cluster_is_the_same():
    distributed = pytest.importorskip("distributed")
    spec = SceneSpec(kind="rd", frames=10, crop=(120, 160, 32, 48))
    kw = dict(snrs_db=[10.0, 20.0], spec=spec, trials=3, noise_trials=20, false_alarm_rate=0.05)
    here = run_comparison(["ca-cfar", "info"], jobs=1, **kw)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        there = run_comparison(["ca-cfar", "info"], jobs=1, scheduler=cluster.scheduler_address, **kw)
    assert (here.thresholds, here.false_alarms, here.detections) == (
        there.thresholds, there.false_alarms, there.detections)


def test_peak_mask_and_crossing():
    v = np.array([[1, 2, 1, 0], [0, 1, 0, 3], [5, 0, 0, 3]], dtype=float)
    assert np.argwhere(peak_mask(v)).tolist() == [[0, 1], [1, 3], [2, 0], [2, 3]]
    assert crossing_snr([0, 1, 2, 3], [0.1, 0.3, 0.7, 0.9], 0.5) == 1.5
    assert math.isnan(crossing_snr([0, 1], [0.1, 0.2], 0.5))


def test_paper000_case_runs_and_finds_the_target_at_high_snr():
    res = run_case(CASES[1], [0])
    assert res.target.shape == (1,) and set(res.false_tracks) == {30.0, 32.0}
    strong = run_case(type(CASES[1])("hi", "", 15.0, "amplitude", True, (30.0,)), [0])
    assert strong.target[0] > strong.noise_max[0] and strong.on_track[0] == 1.0
