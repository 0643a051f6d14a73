"""Pd vs SNR at equal Pfa (:mod:`dptbd.evaluation.detectors.pd_vs_snr`): the comparison's
calibration and counts, the matched channel, its refusals, the same run on a Dask cluster."""

from __future__ import annotations

import math

import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.pd_vs_snr import SceneSpec, run_comparison
from helpers.refusals import whole


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


@pytest.mark.parametrize("call, message", [
    (lambda: run_comparison(["info"], snrs_db=[0.0], spec=SceneSpec(kind="rd", frames=10, crop=(120, 160, 32, 48)),
                            noise_trials=2, false_alarm_rate=0.01, jobs=1),
     "false_alarm_rate=0.01 needs at least 100 noise-only decisions, 2 noise trials give 6; raise noise_trials"),
    (lambda: SceneSpec(crop=(190, 0, 64, 128)), "crop row0 must be an integer in [0, 136], got 190"),
])
def test_comparison_refusals(call, message):
    with pytest.raises(DetectorError, match=whole(message)):
        call()


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
