"""Paper 000's reproductions (:mod:`dptbd.evaluation.detectors.paper000`) on small runs: the
SNR gain, the §5 cases and their refusals, the track ends and the crossings."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.paper000 import CASES, Case, crossing_snr, peak_mask, run_case, snr_gain
from helpers.refusals import whole

GAIN = ("CA-CFAR 16/2", "DP eq (24)", "DP eqs (19)-(23)")


def test_snr_gain_dp_beats_cfar_and_the_result_is_consistent():
    snrs = (3.0, 9.0)
    res = snr_gain(snrs, trials=20, noise_trials=10, pfa=1e-2, detectors=GAIN, chunk=10)
    assert res.snrs_db == snrs and res.trials == 20 and res.pfa == 1e-2
    assert set(res.pd) == set(res.detections) == set(GAIN)
    for name in GAIN:
        assert res.detections[name].shape == (2,)
        assert np.array_equal(res.pd[name], res.detections[name] / 20)
        assert np.all((res.pd[name] >= 0) & (res.pd[name] <= 1))
    # CFAR and the amplitude DP are calibrated once, the matched likelihood DP per SNR
    assert set(res.thresholds) == {"CA-CFAR 16/2@None", "DP eq (24)@None",
                                   "DP eqs (19)-(23)@3.0", "DP eqs (19)-(23)@9.0"}
    assert all(math.isfinite(v) for v in res.thresholds.values())
    dp, cf = res.pd["DP eq (24)"], res.pd["CA-CFAR 16/2"]
    # at 9 dB on 000's scene the 20-frame DP finds (nearly) every target; one frame does not
    assert dp[1] >= 0.9 and dp[1] >= cf[1] + 0.25 and dp[1] >= dp[0]
    # so the DP reaches Pd 0.5 at a lower SNR: a positive gain over CFAR
    dp_50, cf_50 = crossing_snr(snrs, dp, 0.5), crossing_snr(snrs, cf, 0.5)
    assert snrs[0] <= dp_50 <= snrs[1]
    assert math.isnan(cf_50) or cf_50 > dp_50
    with pytest.raises(DetectorError, match=(r"^unknown detector 'MHT'; known: \('single frame "
                                             r"\(known noise\)', 'CA-CFAR 16/2', 'DP eq "
                                             r"\(15\)', 'DP eq \(24\)', 'DP eqs "
                                             r"\(19\)-\(23\)'\)$")):
        snr_gain([3.0], trials=1, noise_trials=1, detectors=("MHT",))


def test_run_case_at_low_snr_matches_the_model_bounds():
    # §5.2 at 3 dB: S(z) <= 1 per frame and Q <= 0, so no path of 20 frames exceeds 20
    # and 000's V_T = 178 leaves nothing; the exact form is the maximum over all paths
    low = CASES[3]
    assert low.snr_db == 3.0 and low.thresholds == (178.0,)
    dp = run_case(low, [0, 1])
    ex = run_case(low, [0, 1], mode="exact")
    for r in (dp, ex):
        assert r.target.shape == r.noise_max.shape == r.on_track.shape == (2,)
        assert np.all(r.target <= 20.0) and np.all(r.noise_max <= 20.0)
        assert np.array_equal(r.false_cells[178.0], [0, 0]) and np.array_equal(r.false_tracks[178.0], [0, 0])
        assert np.all(r.two_track_level <= r.noise_max)
        # a noise cell at or above the target exactly when the noise maximum is
        assert np.array_equal(r.target_rank > 0, r.noise_max >= r.target)
        assert np.all((r.on_track >= 0) & (r.on_track <= 1))
    assert np.all(ex.target >= dp.target - 1e-12) and np.all(ex.noise_max >= dp.noise_max - 1e-12)


def test_run_case_eq15_datapath_is_exact_and_v_t_30_is_below_the_noise():
    # §5.1 eq (15) at 4.08 dB: Q = 0, so the datapath form equals the exact one, and the
    # best noise path of 20 frames (radius 2) is far above 000's V_T = 30 and 32
    dp, ex = run_case(CASES[0], [0]), run_case(CASES[0], [0], mode="exact")
    assert np.array_equal(dp.target, ex.target) and np.array_equal(dp.noise_max, ex.noise_max)
    assert dp.noise_max[0] > 40.0
    assert dp.false_cells[30.0][0] >= dp.false_cells[32.0][0] > 4000
    assert dp.false_tracks[30.0][0] >= dp.false_tracks[32.0][0] > 2


@pytest.mark.parametrize("kwargs, message", [
    (dict(thresholds=(float("nan"),)),
     "thresholds (V_T) must be a finite real number in (-inf, inf), got nan"),
    (dict(thresholds=(30.0, float("inf"))),
     "thresholds (V_T) must be a finite real number in (-inf, inf), got inf"),
    (dict(thresholds=()), "thresholds (V_T) must hold at least one threshold"),
    (dict(thresholds=30.0), "thresholds (V_T) must be a sequence of finite reals, got 30.0"),
    (dict(thresholds=("30",)), "thresholds (V_T) must be a finite real number in (-inf, inf), got '30'"),
    (dict(merit="bump"), "merit must be one of ('amplitude', 'likelihood'), got 'bump'"),
    (dict(snr_db=float("nan")), "snr_db must be a finite real number in [-30, 60], got nan"),
])
def test_case_refuses_bad_thresholds(kwargs, message):
    args = dict(label="x", section="", snr_db=4.0, merit="amplitude", penalty=False, thresholds=(30.0,))
    with pytest.raises(DetectorError, match=whole(message)):
        Case(**{**args, **kwargs})


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
