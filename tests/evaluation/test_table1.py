"""dptbd.evaluation.table1: paper 001's Table 1 by Monte Carlo."""

import numpy as np

from dptbd.evaluation.table1 import DETECTORS, SETTINGS, table1_rows


def test_table1_one_trial_dp_beats_single_frame():
    rows = table1_rows(trials=1)
    assert len(rows) == len(SETTINGS) * len(DETECTORS)
    pd = {name: np.mean([r.counts.pd for r in rows if r.detector == name]) for name in DETECTORS}
    assert pd["direction-weighted DP"] > pd["single frame"] + 0.2
    for r in rows:
        assert r.counts.frames == 24 and r.counts.mean_false_points <= 33
