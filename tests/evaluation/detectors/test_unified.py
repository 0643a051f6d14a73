"""Paper 000's unified recursion (25)-(26) in float: brute force, hand-computed cases, segments,
bad input (the integer form: test_unified_fixed.py)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.merits import amplitude_merit, likelihood_difference_merit
from dptbd.evaluation.detectors.transitions import no_penalty, velocity_log_penalty
from dptbd.evaluation.detectors.unified import (backtrack, path_value, run_unified,
                                                run_unified_segments)
from dptbd.weights import move_offsets
from helpers.refusals import whole


def brute_force(z, merit, q, radius):
    """Best path value ending at every cell: every path enumerated (eq (25) by definition)."""
    n_t, h, w = z.shape
    cells = [(i, j) for i in range(h) for j in range(w)]
    best = np.full((h, w), -np.inf)
    for path in itertools.product(cells, repeat=n_t):
        steps = zip(path[:-1], path[1:])
        if all(max(abs(b[0] - a[0]), abs(b[1] - a[1])) <= radius for a, b in steps):
            best[path[-1]] = max(best[path[-1]], path_value(z, path, merit, q, radius))
    return best


@pytest.mark.parametrize("radius,shape", [(1, (3, 3, 4)), (2, (3, 4, 4))])
@pytest.mark.parametrize("merit", [amplitude_merit(), likelihood_difference_merit(1.6, 0.85, 1.0)],
                         ids=["amplitude", "likelihood"])
def test_exact_mode_is_the_maximum_over_all_paths(radius, shape, merit):
    rng = np.random.default_rng(radius)
    z = rng.normal(size=shape)
    q = velocity_log_penalty(radius, 0.7)
    exact = run_unified(z, merit, q, radius=radius, mode="exact", history=True)
    assert np.allclose(exact.value, brute_force(z, merit, q, radius))
    dp = run_unified(z, merit, q, radius=radius, mode="datapath", history=True)
    assert np.all(dp.value <= exact.value + 1e-12)  # the datapath form is a greedy lower bound
    for cell in itertools.product(range(shape[1]), range(shape[2])):
        for res in (exact, dp):  # the backtracked path is worth exactly the value
            path = backtrack(res, cell)
            assert tuple(path[-1]) == cell
            assert math.isclose(path_value(z, path, merit, q, radius), res.value[cell], abs_tol=1e-12)


def test_datapath_is_exact_when_q_does_not_depend_on_the_predecessor():
    rng = np.random.default_rng(7)
    z = rng.normal(size=(4, 3, 3))
    q = np.tile(-rng.random(9), (10, 1))  # Q(move) only: every row the same
    dp = run_unified(z, amplitude_merit(), q, radius=1)
    assert np.allclose(dp.value, brute_force(z, amplitude_merit(), q, 1))


def test_eq15_by_hand():
    # eq (14)-(15): h_1 = z(1); h_2(x) = max over the 3 x 3 predecessors + z(2)
    z = np.zeros((2, 3, 3))
    z[0] = [[1, 0, 0], [0, 0, 0], [0, 0, 5]]
    z[1] = [[0, 1, 0], [0, 0, 0], [0, 0, 0]]
    res = run_unified(z, amplitude_merit(), no_penalty(1), radius=1)
    assert res.value.tolist() == [[1, 2, 0], [1, 5, 5], [0, 5, 5]]
    # (0, 0) takes the 1 at (0, 0) itself: the centre move m = 4; (1, 1) takes (2, 2): move (-1, -1) = 0
    assert res.direction[0, 0] == 4 and res.direction[1, 1] == 0
    assert res.direction[0, 1] == 5  # from (0, 0): moved (0, +1), m = 1 * 3 + 2


def test_tie_goes_to_lowest_move_index():
    z = np.zeros((2, 3, 3))
    res = run_unified(z, amplitude_merit(), no_penalty(1), radius=1)
    moves = move_offsets(1)
    for y in range(3):
        for x in range(3):  # lowest index whose predecessor is inside the image
            valid = [m for m, (dy, dx) in enumerate(moves) if 0 <= y - dy < 3 and 0 <= x - dx < 3]
            assert res.direction[y, x] == valid[0]


def test_segments_restart_the_recursion():
    rng = np.random.default_rng(4)
    z = rng.normal(size=(2, 7, 5, 5))
    maps, ends = run_unified_segments(z, amplitude_merit(), no_penalty(1), segment_frames=3, radius=1)
    assert maps.shape == (2, 5, 5, 5) and ends.tolist() == [2, 3, 4, 5, 6]
    for s, end in enumerate(ends):
        one = run_unified(z[:, end - 2:end + 1], amplitude_merit(), no_penalty(1), radius=1).value
        assert np.array_equal(maps[:, s], one)


@pytest.mark.parametrize("call, message", [
    (lambda: run_unified(np.zeros((2, 3, 3)), amplitude_merit(), np.zeros((9, 9)), radius=1),
     "transition must have shape (10, 9) for radius=1 ([predecessor direction 0..9, move 0..8]), got (9, 9)"),
    (lambda: run_unified(np.zeros((2, 3, 3)), amplitude_merit(), no_penalty(1), radius=1, mode="fast"),
     "mode must be one of ('datapath', 'exact'), got 'fast'"),
    (lambda: run_unified(np.zeros((3, 3)), amplitude_merit(), no_penalty(1), radius=1),
     "frames must have shape (..., T, H, W) with at least 3 axes, got shape (3, 3)"),
    (lambda: run_unified(np.full((2, 3, 3), np.nan), amplitude_merit(), no_penalty(1), radius=1),
     "frames must be finite: found NaN or inf"),
    (lambda: run_unified(np.zeros((2, 3, 3)), abs, no_penalty(1), radius=1),
     "merit must be a Merit (amplitude_merit(), ...), got <built-in function abs>"),
    (lambda: run_unified_segments(np.zeros((4, 3, 3)), amplitude_merit(), no_penalty(1), segment_frames=5,
                                  radius=1), "segment_frames must be an integer in [1, 4], got 5"),
])
def test_bad_input_names_the_parameter(call, message):
    with pytest.raises(DetectorError, match=whole(message)):
        call()
