"""First-level detection counts and confidence intervals."""

import math

import numpy as np
import pytest

from dptbd.evaluation.metrics import DetectionCounts, first_level_counts, near_mask
from dptbd.evaluation.stats import wilson_interval


def test_detection_within_one_pixel_chebyshev():
    masks = np.zeros((3, 10, 10), bool)
    masks[0, 5, 6] = True          # diagonal neighbour of (4, 5): detected
    masks[1, 6, 5] = True          # two rows away: missed, and a false point
    masks[2, 0, 0] = True          # far: false point; target invisible in this frame
    truth = np.array([[[4, 5]], [[4, 5]], [[4, 5]]])
    visible = np.array([[True], [True], [False]])
    c = first_level_counts(masks, truth, visible)
    assert (c.detections, c.opportunities, c.false_points, c.frames) == (1, 2, 2, 3)
    assert c.pd == 0.5 and c.mean_false_points == pytest.approx(2 / 3)


def test_counts_add_up():
    a = DetectionCounts(1, 2, 3, 4)
    assert a + a == DetectionCounts(2, 4, 6, 8)
    assert math.isnan(DetectionCounts(0, 0, 0, 0).pd)


def test_near_mask_clips_at_edges():
    m = near_mask((4, 4), np.array([[0, 0]]))
    assert m.sum() == 4 and m[:2, :2].all()


def test_wilson_interval_known_values():
    lo, hi = wilson_interval(19, 24)
    assert lo == pytest.approx(0.5953, abs=1e-3) and hi == pytest.approx(0.9076, abs=1e-3)
    assert wilson_interval(0, 10)[0] == pytest.approx(0.0) and wilson_interval(10, 10)[1] == pytest.approx(1.0)
    with pytest.raises(ValueError, match=r"^need 0 <= successes <= trials, got 5 of 3$"):
        wilson_interval(5, 3)
