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


def test_roc_levels_on_the_same_scenes_matched_channels_included():
    from dptbd.evaluation.detectors.report import roc_rows

    spec = SceneSpec(kind="rd", frames=10, crop=(120, 160, 32, 48))
    base = run_comparison(["ca-cfar", "info"], snrs_db=[10.0, 20.0], spec=spec, trials=2,
                          noise_trials=10, false_alarm_rate=0.05, jobs=1, matched=True)
    res = run_comparison(["ca-cfar", "info"], snrs_db=[10.0, 20.0], spec=spec, trials=2,
                         noise_trials=10, false_alarm_rate=0.05, jobs=1, matched=True,
                         roc_pfas=[0.1, 0.5])
    assert res.roc_pfas == (0.1, 0.5) and res.params["roc_false_alarm_rates"] == [0.1, 0.5]
    # the operating point is untouched by the ROC levels
    assert res.thresholds == base.thresholds and res.detections == base.detections
    # each ROC level is a run at that rate: the same threshold, the same counts
    for i, p in enumerate((0.1, 0.5)):
        alone = run_comparison(["ca-cfar", "info"], snrs_db=[10.0, 20.0], spec=spec, trials=2,
                               noise_trials=10, false_alarm_rate=p, jobs=1, matched=True)
        for name in ("ca-cfar", "info"):
            assert res.roc_thresholds[name][i] == alone.thresholds[name]
            assert res.roc_false_alarms[name][i] == alone.false_alarms[name]
            for s in (10.0, 20.0):
                assert res.roc_detections[(name, s)][i] == alone.detections[(name, s)]
    assert isinstance(res.roc_thresholds["info"][0], dict)  # matched: one per preset channel
    rows = roc_rows(res)
    assert [(r["detector"], r["snr_db"], r["false_alarm_rate"]) for r in rows] == [
        (n, s, p) for n in ("ca-cfar", "info") for s in (10.0, 20.0) for p in (0.05, 0.1, 0.5)]
    info20 = [r for r in rows if r["detector"] == "info" and r["snr_db"] == 20.0]
    assert [r["threshold"] for r in info20] == [res.thresholds["info"][20.0]] + [
        t[20.0] for t in res.roc_thresholds["info"]]
