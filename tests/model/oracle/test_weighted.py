"""The DP with predecessor-dependent LUTs (paper eq (11)) against the brute-force path oracle
(:mod:`helpers.path_oracle`): the exact statements that hold.

The weight of a step depends on the direction d stored at the predecessor, which is ONE
local argmax; the DP keeps one (E, d) per pixel and is a greedy approximation of the best
weighted path. What holds:

a. every pixel's state is the value of a real path: backtracking along the stored d from
   any pixel gives an admissible path that starts at frame 1 with d = START and whose
   oracle value equals E exactly;
b. a path-form restatement: keep per pixel and frame the ONE chosen path; at frame k
   extend the chosen paths of all valid predecessors by one move, evaluate each extended
   path from scratch, keep the one with the largest candidate (lowest move on ties). Its
   value and last move equal (E, d) at every frame;
c. E <= max over all paths of the weighted path value (because of a.);
d. for the paper LUT: E >= the stay-put sum (the zero move always has weight 1), E is <=
   plain DP's E, and for K = 2 (every predecessor is START) it equals plain DP;
e. NOT guaranteed: E >= the value of every path whose consecutive moves satisfy
   v1 . v2 >= 0 (i.e. E = the best eq-(11)-admissible path). A hand-made scene shows a
   strict gap, so nobody relies on it."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.weights import paper_weights, plain_weights
from helpers.path_oracle import (SCENE_IDS, SCENES, evaluate_path, exhaustive_oracle,
                                 greedy_path_oracle, make_cfg, random_frames, run_model, window)


def states_per_frame(frames, cfg, fixed):
    """(E, d) after each frame 1..K of one segment, from the model (segment_frames = k)."""
    return [run_model(frames[:k], cfg.replace(segment_frames=k, segment_stride=None), fixed)
            for k in range(1, len(frames) + 1)]


def backtrack(states, y, x, radius):
    """The path obtained by following the stored directions back from (y, x) at frame K."""
    moves = window(radius)
    n_moves = len(moves)
    path = [(y, x)]
    for k in range(len(states) - 1, 0, -1):
        m = int(states[k][1][y, x])
        assert m < n_moves, f"d = START at frame {k + 1} > 1"
        dy, dx = moves[m]
        y, x = y - dy, x - dx
        assert 0 <= y < states[0][0].shape[0] and 0 <= x < states[0][0].shape[1], \
            "stored direction points outside the image"
        path.append((y, x))
    assert int(states[0][1][y, x]) == n_moves, "frame 1 must hold d = START"
    return path[::-1]


def weighted_luts(radius, rng):
    """Predecessor-dependent LUTs: the paper's, a random binary one, a random dyadic one."""
    n_moves = (2 * radius + 1) ** 2
    binary = rng.integers(0, 2, size=(n_moves + 1, n_moves)).astype(float)
    binary[:, n_moves // 2] = 1.0  # keep standing still allowed, like the paper
    dyadic = rng.choice([0.0, 0.25, 0.5, 0.75, 1.0], size=(n_moves + 1, n_moves))
    return {"paper": paper_weights(radius), "binary": binary, "dyadic": dyadic}


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
@pytest.mark.parametrize("fixed", [False, True], ids=["float", "fixed"])
@pytest.mark.parametrize("lut", ["paper", "binary", "dyadic"])
def test_weighted_backtracked_path_value_is_E(scene, fixed, lut):
    """Statement 2a: every (E, d) is a real path, and the oracle value of that path is E."""
    height, width, k_frames, radius = scene
    rng = np.random.default_rng(17 + k_frames + radius)
    weights = weighted_luts(radius, rng)[lut]
    for rounding in ("truncate", "half_up") if fixed else ("truncate",):
        cfg = make_cfg(height, width, k_frames, radius, weights=weights, rounding=rounding,
                       weight_frac_bits=2)
        for high in (2, 15):
            frames = random_frames(rng, k_frames, height, width, high)
            states = states_per_frame(frames, cfg, fixed)
            energy = states[-1][0]
            for y in range(height):
                for x in range(width):
                    path = backtrack(states, y, x, radius)
                    value, _ = evaluate_path(frames, path, cfg, fixed)
                    assert value == energy[y, x], (y, x, path)
            # statement 2c: never above the best weighted path over ALL paths
            best, _ = exhaustive_oracle(frames, cfg, fixed)
            assert np.all(energy <= best)


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
@pytest.mark.parametrize("fixed", [False, True], ids=["float", "fixed"])
@pytest.mark.parametrize("lut", ["paper", "binary", "dyadic"])
def test_weighted_dp_equals_greedy_path_oracle(scene, fixed, lut):
    """Statement 2b: (E, d) at every frame equals the path-form greedy oracle, ties included."""
    height, width, k_frames, radius = scene
    rng = np.random.default_rng(23 + k_frames)
    weights = weighted_luts(radius, rng)[lut]
    cfg = make_cfg(height, width, k_frames, radius, weights=weights, weight_frac_bits=2,
                   rounding="half_up" if lut == "dyadic" else "truncate")
    for high in (2, 9):
        frames = random_frames(rng, k_frames, height, width, high)
        states = states_per_frame(frames, cfg, fixed)
        history = greedy_path_oracle(frames, cfg, fixed)
        for k, ((e_model, d_model), (e_oracle, d_oracle)) in enumerate(zip(states, history)):
            np.testing.assert_array_equal(e_model, e_oracle, err_msg=f"E, frame {k + 1}")
            np.testing.assert_array_equal(d_model, d_oracle, err_msg=f"d, frame {k + 1}")


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
def test_paper_lut_bounds(scene):
    """Statement 2d for the paper LUT, float and fixed (integers: fixed == float here)."""
    height, width, k_frames, radius = scene
    rng = np.random.default_rng(41)
    cfg = make_cfg(height, width, k_frames, radius)  # weights=None: paper eq (11)
    plain = cfg.replace(weights=plain_weights(radius))
    for _ in range(4):
        frames = random_frames(rng, k_frames, height, width, 9)
        e_fix, d_fix = run_model(frames, cfg, True)
        e_flt, d_flt = run_model(frames, cfg, False)
        np.testing.assert_array_equal(e_fix, e_flt)  # 0/1 weights, integers: no rounding
        np.testing.assert_array_equal(d_fix, d_flt)
        stay_put = frames.astype(np.int64).sum(axis=0)
        assert np.all(e_fix >= stay_put)
        e_plain, _ = run_model(frames, plain, True)
        assert np.all(e_fix <= e_plain)
        # K = 2: every predecessor is START (all-ones row), so eq (10) is eq (8) exactly
        two = cfg.replace(segment_frames=2, segment_stride=None)
        np.testing.assert_array_equal(run_model(frames[:2], two, True)[0],
                                      run_model(frames[:2], plain.replace(segment_frames=2, segment_stride=None), True)[0])
        np.testing.assert_array_equal(run_model(frames[:2], two, True)[1],
                                      run_model(frames[:2], plain.replace(segment_frames=2, segment_stride=None), True)[1])


@pytest.mark.parametrize("fixed", [False, True], ids=["float", "fixed"])
def test_paper_lut_is_not_the_best_admissible_path(fixed):
    """Statement 2e: a strict gap between the DP and the best eq-(11)-admissible path.

    Frame 1: A = (2,1) holds 3, B = (2,3) holds 2.  Frame 2: q = (2,2) holds 2.
    At q the DP prefers arriving from A (moving right, candidate 3) over B (moving left,
    candidate 2) and stores d = right. In frame 3 the pixel (2,1) left of q can only get 0
    from q (a U-turn, weight 0), so E(2,1) = 3 (A standing still) although the path
    B -> q -> (2,1) moves left twice (v1 . v2 = 1 >= 0, weight 1) and is worth 2 + 2 = 4.
    """
    cfg = make_cfg(5, 5, 3, 1)
    frames = np.zeros((3, 5, 5), dtype=np.uint16)
    frames[0, 2, 1], frames[0, 2, 3], frames[1, 2, 2] = 3, 2, 2
    energy, direction = run_model(frames, cfg, fixed)
    states = states_per_frame(frames, cfg, fixed)
    assert states[1][1][2, 2] == 5  # q arrived moving (0, +1)
    assert energy[2, 1] == 3
    good_path = [(2, 3), (2, 2), (2, 1)]
    value, _ = evaluate_path(frames, good_path, cfg, fixed)
    assert value == 4
    best, _ = exhaustive_oracle(frames, cfg, fixed)
    assert best[2, 1] == 4 > energy[2, 1]
    assert np.all(energy <= best)
