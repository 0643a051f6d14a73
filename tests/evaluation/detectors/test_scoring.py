"""Equal-Pfa scoring: the threshold from noise-only decisions, detections within the gate."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.interface import Decisions
from dptbd.evaluation.detectors.scoring import calibrate, count_detections, count_false_alarms


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
