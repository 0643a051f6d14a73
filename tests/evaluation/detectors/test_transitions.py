"""Paper 000's transition terms Q: eq (22) on velocities by hand, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.transitions import velocity_log_penalty
from dptbd.weights import move_offsets
from helpers.refusals import whole

def test_velocity_penalty_table_by_hand():
    q = velocity_log_penalty(1, alpha=1.0)
    moves = [tuple(m) for m in move_offsets(1)]
    assert q.shape == (10, 9)
    assert np.all(q[9] == 0.0)  # START: no heading, no penalty
    assert np.all(np.diag(q[:9]) == 0.0)  # keeping the velocity costs nothing
    up, right = moves.index((-1, 0)), moves.index((0, 1))
    assert math.isclose(q[up, right], -math.log10(1 + math.sqrt(2)))
    assert np.all(q <= 0)
    q0 = velocity_log_penalty(2, alpha=0.0)  # alpha = 0 penalises the move length itself
    m = [tuple(v) for v in move_offsets(2)].index((2, -2))
    assert math.isclose(q0[0, m], -math.log10(1 + math.sqrt(8)))


@pytest.mark.parametrize("call, message", [
    (lambda: velocity_log_penalty(2, alpha=1.5),
     "alpha (eq (22) coefficient) must be a finite real number in [0, 1], got 1.5"),
    (lambda: velocity_log_penalty(2, alpha=-0.1),
     "alpha (eq (22) coefficient) must be a finite real number in [0, 1], got -0.1"),
    (lambda: velocity_log_penalty(3), "radius must be an integer in [1, 2], got 3"),
])
def test_bad_input_names_the_parameter(call, message):
    with pytest.raises(DetectorError, match=whole(message)):
        call()
