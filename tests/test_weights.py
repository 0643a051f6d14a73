"""``dptbd.weights``: the move order of ``docs/arithmetic.md`` §2 and the weight LUTs of §3."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.errors import ConfigError, DptbdError
from dptbd.weights import check_move_table, move_offsets, paper_weights, plain_weights
from helpers.refusals import whole

# move indices for r = 1 (docs §2 table)
UL, U, UR, L, C, R, DL, D, DR = range(9)
START = 9

SHAPE_10_9 = "shape (10, 9) for radius=1 ([predecessor direction 0..9, move 0..8])"


# ---------------------------------------------------------------------------------------
# §2 move order
# ---------------------------------------------------------------------------------------

def test_move_offsets_match_the_doc_table():
    table = [(-1, -1), (-1, 0), (-1, +1), (0, -1), (0, 0), (0, +1), (+1, -1), (+1, 0), (+1, +1)]
    moves = move_offsets(1)
    assert moves.dtype == np.int64 and moves.shape == (9, 2)
    assert [tuple(int(v) for v in mv) for mv in moves] == table
    np.testing.assert_array_equal(DPConfig().moves, moves)


@pytest.mark.parametrize("radius", [1, 2])
def test_move_index_formula(radius):
    """m = (dy + r)(2r + 1) + (dx + r) for every move."""
    moves = move_offsets(radius)
    assert len(moves) == (2 * radius + 1) ** 2
    for m, (dy, dx) in enumerate(moves):
        assert (dy + radius) * (2 * radius + 1) + (dx + radius) == m
        assert abs(dy) <= radius and abs(dx) <= radius
    assert tuple(moves[len(moves) // 2]) == (0, 0)  # centre in the middle


# ---------------------------------------------------------------------------------------
# §3 weight LUT
# ---------------------------------------------------------------------------------------

def test_paper_weights_explicit_entries():
    """eq (11) read as w = 1 iff v1 . v2 >= 0 (v1 = predecessor's move d, v2 = candidate)."""
    w = paper_weights(1)
    assert w.shape == (10, 9) and w.dtype == np.float64
    # predecessor moved right (0,+1)
    assert w[R, L] == 0.0    # U-turn, 180 deg
    assert w[R, UR] == 1.0   # 45 deg
    assert w[R, U] == 1.0    # 90 deg: dot = 0 -> weight 1 (|theta| <= 90)
    assert w[R, D] == 1.0    # -90 deg
    assert w[R, UL] == 0.0   # 135 deg
    assert w[R, DL] == 0.0   # 135 deg
    assert w[R, R] == 1.0    # straight on
    assert w[R, C] == 1.0    # zero move: no angle, weight 1
    # predecessor moved up-left (-1,-1)
    assert w[UL, DR] == 0.0  # 180 deg
    assert w[UL, R] == 0.0   # (-1,-1).(0,1) = -1: 135 deg
    assert w[UL, UR] == 1.0  # (-1,-1).(-1,1) = 0: 90 deg
    assert w[UL, U] == 1.0
    # zero-move predecessor and START: every move allowed
    assert np.all(w[C] == 1.0)
    assert np.all(w[START] == 1.0)
    assert np.all(w[:, C] == 1.0)


@pytest.mark.parametrize("radius", [1, 2])
def test_paper_weights_from_angles(radius):
    """Independent derivation with angles: w = 1 iff |theta| <= 90 deg, zero moves and
    START weight 1."""
    moves = [tuple(int(v) for v in mv) for mv in move_offsets(radius)]
    w = paper_weights(radius)
    n_moves = len(moves)
    assert w.shape == (n_moves + 1, n_moves)
    for p, v1 in enumerate(moves):
        for m, v2 in enumerate(moves):
            if v1 == (0, 0) or v2 == (0, 0):
                expected = 1.0
            else:
                theta = math.degrees(abs(math.atan2(v1[0], v1[1]) - math.atan2(v2[0], v2[1])))
                theta = min(theta, 360.0 - theta)
                expected = 1.0 if theta <= 90.0 + 1e-9 else 0.0
            assert w[p, m] == expected, (v1, v2)
    assert np.all(w[n_moves] == 1.0)
    assert set(np.unique(w)) <= {0.0, 1.0}


@pytest.mark.parametrize("radius", [1, 2])
def test_plain_weights_all_ones(radius):
    n_moves = (2 * radius + 1) ** 2
    w = plain_weights(radius)
    assert w.shape == (n_moves + 1, n_moves) and np.all(w == 1.0)


def test_check_move_table_checks_any_table_shaped_like_the_weight_lut():
    table = check_move_table("transition", -np.ones((26, 25), dtype=np.int64), 2)
    assert table.dtype == np.float64 and table.shape == (26, 25) and table.max() == -1.0
    bad = np.zeros((10, 9))
    bad[3, 4] = 0.5
    with pytest.raises(ConfigError, match=whole("transition must be finite and in (-inf, 0], found [0.5]")):
        check_move_table("transition", bad, 1, hi=0.0)

    class OtherError(DptbdError):
        pass

    with pytest.raises(OtherError, match=whole(f"q must have {SHAPE_10_9}, got (9, 9)")):
        check_move_table("q", np.ones((9, 9)), 1, error=OtherError)
    with pytest.raises(OtherError, match=whole("q must be a numeric table, got dict")):
        check_move_table("q", {}, 1, error=OtherError)
