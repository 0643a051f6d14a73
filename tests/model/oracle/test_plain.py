"""The DP with predecessor-independent LUTs against the brute-force path oracle
(:mod:`helpers.path_oracle`): the exact max over ALL paths.

All rows of the LUT equal (plain DP eq (8) is the all-ones case). The step
v -> round(v * c) + x, clamped, is non-decreasing in v, so by induction E_k(q) is the max
of v_k over ALL paths ending at q, and the candidate C_m = round(E_{k-1}(q_m) * c_m) is the
max over paths whose last move is m of the pre-add value round(v_{K-1} * c_m). Hence E =
best path value for every end pixel, and d = the lowest m whose best-with-last-move-m
candidate equals the maximum (the spec's local tie-break IS this global statement, because
the local candidate of move m equals the global best over paths ending in m). Holds in
float (IEEE multiply and add by a fixed non-negative number are monotone too) and in fixed
point, with or without saturation."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.config import EnergyWidthWarning
from dptbd.weights import plain_weights
from helpers.path_oracle import (SCENE_IDS, SCENES, exhaustive_oracle, make_cfg, random_frames,
                                 row_independent_lut, run_model)


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
@pytest.mark.parametrize("fixed", [False, True], ids=["float", "fixed"])
@pytest.mark.parametrize("high", [2, 15], ids=["ties", "wide"])
def test_plain_dp_is_max_over_all_paths(scene, fixed, high):
    """Plain DP (all-ones LUT): E = best path sum, d = lowest best last move."""
    height, width, k_frames, radius = scene
    cfg = make_cfg(height, width, k_frames, radius, weights=plain_weights(radius))
    rng = np.random.default_rng(1000 * k_frames + 10 * height + width + high)
    for _ in range(4):
        frames = random_frames(rng, k_frames, height, width, high)
        best, d_oracle = exhaustive_oracle(frames, cfg, fixed)
        energy, direction = run_model(frames, cfg, fixed)
        np.testing.assert_array_equal(energy, best)
        np.testing.assert_array_equal(direction, d_oracle)
        # plain DP: the path value is the plain sum of its pixels
        sums_best = exhaustive_oracle(frames, cfg, fixed=False)[0]
        np.testing.assert_array_equal(energy, sums_best)


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
def test_plain_dp_fixed_equals_float(scene):
    """Integer pixels, no saturation, all-ones LUT: fixed and float agree bit for bit."""
    height, width, k_frames, radius = scene
    for rounding in ("truncate", "half_up"):
        cfg = make_cfg(height, width, k_frames, radius, weights=plain_weights(radius),
                       rounding=rounding)
        rng = np.random.default_rng(7)
        for _ in range(3):
            frames = random_frames(rng, k_frames, height, width, 2)
            e_fix, d_fix = run_model(frames, cfg, True)
            e_flt, d_flt = run_model(frames, cfg, False)
            np.testing.assert_array_equal(e_fix, e_flt)
            np.testing.assert_array_equal(d_fix, d_flt)


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
@pytest.mark.parametrize("rounding", ["truncate", "half_up"])
@pytest.mark.parametrize("frac_bits", [0, 1, 3, 8])
def test_move_only_weights_fixed_is_max_over_all_paths(scene, rounding, frac_bits):
    """Row-independent LUT with fractional weights: the rounded, clamped step is monotone,
    so the fixed-point DP is the exact max over all paths of the fixed-point path value."""
    height, width, k_frames, radius = scene
    rng = np.random.default_rng(frac_bits * 31 + k_frames)
    for trial in range(3):
        levels = None if trial == 0 else [0.0, 0.25, 0.5, 0.75, 1.0, 0.3]
        cfg = make_cfg(height, width, k_frames, radius, rounding=rounding,
                       weight_frac_bits=frac_bits, weights=row_independent_lut(rng, radius, levels))
        frames = random_frames(rng, k_frames, height, width, 15)
        best, d_oracle = exhaustive_oracle(frames, cfg, fixed=True)
        energy, direction = run_model(frames, cfg, True)
        np.testing.assert_array_equal(energy, best)
        np.testing.assert_array_equal(direction, d_oracle)


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
def test_move_only_weights_float_is_max_over_all_paths(scene):
    """Same in float64: multiplying/adding a fixed non-negative number is monotone in IEEE
    arithmetic, so even non-dyadic weights (0.3, random) give the exact max, bit for bit."""
    height, width, k_frames, radius = scene
    rng = np.random.default_rng(99 + k_frames)
    for trial in range(4):
        levels = None if trial % 2 == 0 else [0.0, 0.3, 0.5, 0.7, 1.0]
        cfg = make_cfg(height, width, k_frames, radius,
                       weights=row_independent_lut(rng, radius, levels))
        frames = random_frames(rng, k_frames, height, width, 2 if trial < 2 else 15)
        best, d_oracle = exhaustive_oracle(frames, cfg, fixed=False)
        energy, direction = run_model(frames, cfg, False)
        np.testing.assert_array_equal(energy, best)
        np.testing.assert_array_equal(direction, d_oracle)


@pytest.mark.parametrize("rounding", ["truncate", "half_up"])
def test_max_over_paths_with_saturation(rounding):
    """Narrow E (3 bits, pixels up to 7, K = 4): clamping at every step is still monotone,
    so E = max over paths of the clamped path value; d follows the pre-add candidates
    (which tie at E_max only when they are equal, never because the sum saturates)."""
    rng = np.random.default_rng(5)
    for weights in (plain_weights(1), row_independent_lut(rng, 1, [0.5, 0.75, 1.0])):
        with pytest.warns(EnergyWidthWarning):
            cfg = make_cfg(5, 5, 4, 1, input_bits=3, energy_bits=3, weight_frac_bits=2,
                           rounding=rounding, weights=weights)
        for _ in range(4):
            frames = random_frames(rng, 4, 5, 5, 7)
            best, d_oracle = exhaustive_oracle(frames, cfg, fixed=True)
            energy, direction = run_model(frames, cfg, True)
            assert energy.max() <= 7
            np.testing.assert_array_equal(energy, best)
            np.testing.assert_array_equal(direction, d_oracle)


@pytest.mark.parametrize("fixed", [False, True], ids=["float", "fixed"])
def test_single_frame_segment_is_the_frame(fixed):
    """K = 1: E = x and d = START everywhere (§5)."""
    cfg = make_cfg(5, 5, 1, 1)
    frames = random_frames(np.random.default_rng(3), 1, 5, 5, 15)
    best, d_oracle = exhaustive_oracle(frames, cfg, fixed)
    energy, direction = run_model(frames, cfg, fixed)
    np.testing.assert_array_equal(energy, frames[0])
    np.testing.assert_array_equal(energy, best)
    np.testing.assert_array_equal(direction, np.full((5, 5), 9))
    np.testing.assert_array_equal(direction, d_oracle)
