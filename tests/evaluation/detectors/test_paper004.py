"""Paper 004's simulation helpers (:mod:`dptbd.evaluation.detectors.paper004`): the
per-frame timing of every detector and its refusals."""

from __future__ import annotations

import math

import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.paper004 import time_one_frame
from helpers.refusals import whole


def test_time_one_frame_smoke_on_a_small_grid():
    t = time_one_frame(repeats=1, frames=3, shape=(40, 60))
    assert {"info", "grid-bayes", "ca-cfar", "dw-dp golden", "dp-000 datapath", "dp-000 exact"} <= set(t)
    assert set(t) <= {"info", "grid-bayes", "ca-cfar", "dw-dp", "dw-dp golden", "dp-000 datapath",
                      "dp-000 exact"}
    assert all(isinstance(v, float) and math.isfinite(v) and v > 0 for v in t.values())


@pytest.mark.parametrize("kwargs, message", [
    (dict(repeats=0), "repeats must be an integer in [1, inf), got 0"),
    (dict(frames=2), "frames must be an integer in [3, inf), got 2"),
    (dict(shape=(10, 60)), "shape must be at least 19 x 19 cells (CA-CFAR 16/2), got (10, 60)"),
    (dict(shape=(40,)), "shape must be a pair (H, W) of integers in [1, 65535], got (40,)"),
])
def test_time_one_frame_bad_input(kwargs, message):
    with pytest.raises(DetectorError, match=whole(message)):
        time_one_frame(**kwargs)
