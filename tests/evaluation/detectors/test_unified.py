"""Paper 000's unified recursion (25)-(26): brute force, hand-computed cases, fixed point."""

from __future__ import annotations

import itertools
import math
import re

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.weights import move_offsets, plain_weights
from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.unified import (
    amplitude_merit, backtrack, likelihood_difference_merit, no_penalty, path_value,
    quantise_unified, run_unified, run_unified_fixed, run_unified_segments, velocity_log_penalty)
from dptbd.model.fixed import run_fixed


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


def test_likelihood_difference_by_hand():
    s = likelihood_difference_merit(amplitude=2.0, epsilon=0.85, sigma=1.0)
    z = np.array([0.0, 1.7, 3.0])
    expect = np.exp(-(z - 1.7) ** 2 / 2) - np.exp(-z ** 2 / 2) / math.sqrt(2 * math.pi)
    assert np.allclose(s(z), expect)
    assert math.isclose(float(s(np.array(1.7))), 1 - math.exp(-1.7 ** 2 / 2) / math.sqrt(2 * math.pi))
    # noise_sigma rescales the measurements
    s2 = likelihood_difference_merit(amplitude=4.0, epsilon=0.85, sigma=1.0, noise_sigma=2.0)
    assert np.allclose(s2(2 * z), expect)


def test_fixed_point_with_plain_lut_is_paper001_plain_dp():
    rng = np.random.default_rng(1)
    x = rng.integers(0, 256, size=(2, 6, 9, 11)).astype(np.uint16)
    cfg = DPConfig(width=11, height=9, segment_frames=6, radius=2, weights=plain_weights(2))
    golden = run_fixed(x, cfg)
    luts = quantise_unified(amplitude_merit(), no_penalty(2), radius=2, input_bits=8)
    e, d = run_unified_fixed(x, luts)
    assert np.array_equal(e, golden.energy[:, 0]) and np.array_equal(d, golden.direction[:, 0])


def test_fixed_point_equals_float_plus_bias_for_integer_luts():
    rng = np.random.default_rng(2)
    x = rng.integers(0, 256, size=(3, 5, 7, 8)).astype(np.uint16)
    q = -rng.integers(0, 4, size=(26, 25)).astype(float)
    luts = quantise_unified(amplitude_merit(), q, radius=2, input_bits=8, energy_bits=16)
    assert luts.merit_codes.min() >= luts.penalty_codes.max()  # candidates never negative
    e, d = run_unified_fixed(x, luts)
    ref = run_unified(x.astype(float), amplitude_merit(), q, radius=2)
    assert np.array_equal(luts.to_float(e, 5), ref.value)
    assert np.array_equal(d, ref.direction)
    v_t = float(np.median(ref.value))
    assert np.array_equal(e > luts.threshold_code(v_t, 5), ref.value > v_t)


def test_fixed_point_likelihood_lut_tracks_the_float_recursion():
    rng = np.random.default_rng(3)
    z = rng.normal(size=(8, 10, 10))
    z[:, 5, 5] += 2.0
    merit, q = likelihood_difference_merit(2.0, 0.85, 1.0), velocity_log_penalty(2, 1.0)
    gain, offset = 16.0, 128.0
    codes = np.clip(np.rint(z * gain + offset), 0, 255).astype(np.uint16)
    luts = quantise_unified(merit, q, radius=2, input_bits=8, gain=gain, offset=offset, scale=256.0)
    e, _ = run_unified_fixed(codes, luts)
    ref = run_unified((codes - offset) / gain, merit, q, radius=2).value
    # 8 frames of merit and penalty rounding, 1/512 each at most
    assert np.max(np.abs(luts.to_float(e, 8) - ref)) <= 16 / 512 + 1e-9


def test_segments_restart_the_recursion():
    rng = np.random.default_rng(4)
    z = rng.normal(size=(2, 7, 5, 5))
    maps, ends = run_unified_segments(z, amplitude_merit(), no_penalty(1), segment_frames=3, radius=1)
    assert maps.shape == (2, 5, 5, 5) and ends.tolist() == [2, 3, 4, 5, 6]
    for s, end in enumerate(ends):
        one = run_unified(z[:, end - 2:end + 1], amplitude_merit(), no_penalty(1), radius=1).value
        assert np.array_equal(maps[:, s], one)


@pytest.mark.parametrize("call, message", [
    (lambda: velocity_log_penalty(2, alpha=1.5),
     "alpha (eq (22) coefficient) must be a finite real number in [0, 1], got 1.5"),
    (lambda: velocity_log_penalty(2, alpha=-0.1),
     "alpha (eq (22) coefficient) must be a finite real number in [0, 1], got -0.1"),
    (lambda: velocity_log_penalty(3), "radius must be an integer in [1, 2], got 3"),
    (lambda: likelihood_difference_merit(2.0, epsilon=1.0, sigma=1.0),
     "epsilon (printed alpha in 000 §5.2) must be a finite real number in (0, 1), got 1.0"),
    (lambda: likelihood_difference_merit(2.0, epsilon=0.0, sigma=1.0),
     "epsilon (printed alpha in 000 §5.2) must be a finite real number in (0, 1), got 0.0"),
    (lambda: likelihood_difference_merit(2.0, epsilon=0.5, sigma=0.0),
     "sigma (printed delta in 000 §5.2) must be a finite real number in (0, inf), got 0.0"),
    (lambda: likelihood_difference_merit(0.0, epsilon=0.5, sigma=1.0),
     "amplitude (a) must be a finite real number in (0, inf), got 0.0"),
    (lambda: likelihood_difference_merit(2.0, 0.5, 1.0, noise_sigma=float("nan")),
     "noise_sigma must be a finite real number in (0, inf), got nan"),
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
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2), input_bits=17),
     "input_bits must be an integer in [1, 16], got 17"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2), gain=0.0),
     "gain must be a finite real number in (0, inf), got 0.0"),
    (lambda: run_unified_fixed(np.full((2, 3, 3), 256), quantise_unified(amplitude_merit(), no_penalty(2))),
     "codes must be in [0, 255] for input_bits=8, found [256, 256]"),
    (lambda: run_unified_segments(np.zeros((4, 3, 3)), amplitude_merit(), no_penalty(1), segment_frames=5,
                                  radius=1), "segment_frames must be an integer in [1, 4], got 5"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2)).threshold_code(float("nan"), 5),
     "v_t (threshold V_T) must be a finite real number in (-inf, inf), got nan"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2)).threshold_code(float("inf"), 5),
     "v_t (threshold V_T) must be a finite real number in (-inf, inf), got inf"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2)).threshold_code("30", 5),
     "v_t (threshold V_T) must be a finite real number in (-inf, inf), got '30'"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2)).threshold_code(30.0, 0),
     "n_frames must be an integer in [1, inf), got 0"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2)).to_float(np.zeros(3), 0),
     "n_frames must be an integer in [1, inf), got 0"),
])
def test_bad_input_names_the_parameter(call, message):
    with pytest.raises(DetectorError, match="^" + re.escape(message) + "$"):
        call()
