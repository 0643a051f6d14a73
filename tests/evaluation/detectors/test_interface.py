"""The common detector interface, equal-Pfa calibration, the comparison and ``dptbd detectors``."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.pd_vs_snr import SceneSpec, run_comparison
from dptbd.evaluation.detectors.interface import (
    DETECTORS, Decisions, SceneModel, calibrate, count_detections, count_false_alarms,
    make_detector, parse_detectors)
from dptbd.evaluation.detectors.paper000 import crossing_snr, peak_mask, run_case, CASES
from dptbd.scenes.range_doppler import rd_scene, straight_track
from dptbd.model.fixed import run_fixed
from helpers.refusals import whole


def test_parse_detectors():
    assert parse_detectors("info, ca-cfar,info") == ("info", "ca-cfar")
    with pytest.raises(DetectorError, match=(r"^unknown detector 'mht'; known: dw-dp, "
                                             r"dp-amplitude, dp-penalty, dp-likelihood, info, "
                                             r"grid-bayes, ca-cfar$")):
        parse_detectors("info,mht")
    with pytest.raises(DetectorError, match=(r"^detectors must name at least one of dw-dp, "
                                             r"dp-amplitude, dp-penalty, dp-likelihood, info, "
                                             r"grid-bayes, ca-cfar$")):
        parse_detectors("")


def test_calibrate_keeps_at_most_the_rate_and_ignores_ties_and_nan():
    stats = np.array([[np.nan, 1, 2, 3, 4], [np.nan, 5, 6, 7, 8], [np.nan, 9, 10, 10, 10]])
    thr = calibrate(stats, 0.25)  # 12 decisions -> at most 3 above
    assert thr == 9.0
    assert count_false_alarms(Decisions(stats, np.zeros(stats.shape + (2,))), thr).hits == 3
    with pytest.raises(DetectorError, match=(r"^false_alarm_rate=0\.01 needs at least 100 "
                                             r"noise-only decisions to set a threshold, got "
                                             r"12; raise the noise trials or the rate$")):
        calibrate(stats, 0.01)
    with pytest.raises(DetectorError, match=(r"^false_alarm_rate must be a finite real number "
                                             r"in \(0, 1\), got 0\.0$")):
        calibrate(stats, 0.0)


def test_count_detections_gate_and_scored_frames():
    stat = np.array([[5.0, 5.0, 5.0, np.nan], [1.0, 5.0, 5.0, 5.0]])
    est = np.zeros((2, 4, 2), dtype=int)
    est[0, 2] = (3, 3)  # far from the truth: a declaration but no detection
    pixel = np.zeros((4, 2), dtype=int)
    c = count_detections(Decisions(stat, est), 2.0, pixel, np.ones(4, bool), first_frame=1, gate=1)
    assert (c.hits, c.total) == (4, 5)
    c = count_detections(Decisions(stat, est), 2.0, pixel, np.array([1, 1, 0, 1], bool), first_frame=0)
    assert (c.hits, c.total) == (4, 5)


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
