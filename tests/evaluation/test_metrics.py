"""First-level detection counts (:mod:`dptbd.evaluation.metrics`)."""

import math

import numpy as np
import pytest

from dptbd.evaluation.metrics import DetectionCounts, first_level_counts, near_mask


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
