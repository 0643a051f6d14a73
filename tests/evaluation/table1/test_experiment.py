"""dptbd.evaluation.table1.experiment: paper 001's Table 1 by Monte Carlo, the same rows on any
number of workers."""

import numpy as np
import pytest

from dptbd.errors import DptbdError
from dptbd.evaluation.execution import ExecutionError
from dptbd.evaluation.table1.experiment import DETECTORS, SETTINGS, run_table1, table1_rows


def test_table1_one_trial_dp_beats_single_frame():
    rows = table1_rows(trials=1)
    assert len(rows) == len(SETTINGS) * len(DETECTORS)
    pd = {name: np.mean([r.counts.pd for r in rows if r.detector == name]) for name in DETECTORS}
    assert pd["direction-weighted DP"] > pd["single frame"] + 0.2
    for r in rows:
        assert r.counts.frames == 24 and r.counts.mean_false_points <= 33


def test_table1_rows_identical_on_one_worker_and_two_local_workers():
    kw = dict(trials=4, chunk=2, settings=SETTINGS[:2], size=32, seed=11)
    one = run_table1(workers=1, **kw)
    two = run_table1(workers=2, **kw)  # 4 tasks on a LocalCluster of 2 processes
    assert len(one.rows) == 2 * len(DETECTORS) and one.rows == two.rows
    # and the rows do not depend on how the trials are grouped into tasks
    assert run_table1(workers=1, **dict(kw, chunk=3)).rows == one.rows


def test_table1_refuses_bad_trials_chunk_and_workers():
    for name, kw, value in [("trials", dict(trials=0), 0), ("chunk", dict(chunk=0), 0)]:
        with pytest.raises(DptbdError, match=rf"^{name} must be an integer in \[1, inf\), got "
                                             rf"{value}$"):
            run_table1(**kw)
    with pytest.raises(ExecutionError, match=r"^workers must be an integer in \[1, 1024\], "
                                             r"got 0$"):
        run_table1(1, workers=0)
