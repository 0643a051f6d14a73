"""The family's RTL operators (``dptbd.model.family.operators``) against ``docs/arithmetic.md`` §8."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from dptbd.model.family.operators import (
    INVALID_SIGNED, add_clamped, lookup_merit_code, lookup_penalty_code, scale_by_forgetting,
    subtract_penalty)
from helpers.model_strategies import FAST


def test_merit_lut_reads_by_pixel_code():
    lut = np.array([-3, 0, 7, -8])
    np.testing.assert_array_equal(lookup_merit_code(lut, np.array([[3, 2], [0, 1]])),
                                  [[-8, 7], [-3, 0]])


def test_penalty_lut_clamps_the_direction_like_the_weight_lut():
    table = np.arange(10 * 9).reshape(10, 9)
    np.testing.assert_array_equal(lookup_penalty_code(table, np.array([0, 9, 12, 15]), 4),
                                  [4, 85, 85, 85])


def test_subtract_penalty_is_signed_and_exact():
    np.testing.assert_array_equal(subtract_penalty(np.array([0, 5, 65535]), np.array([3, 5, 1])),
                                  [-3, 0, 65534])


@FAST
@given(v=st.integers(-(1 << 17), 1 << 17), g=st.integers(0, 8), data=st.data(),
       mode=st.sampled_from(["truncate", "half_up"]))
def test_forgetting_rounds_as_specified(v, g, data, mode):
    a = data.draw(st.integers(1, 1 << g))
    got = int(scale_by_forgetting(np.array(v), a, g, mode))
    if mode == "truncate" or g == 0:
        want = (v * a) // (1 << g)  # Python floor division: towards -inf
    else:
        want = (v * a + (1 << (g - 1))) // (1 << g)
    assert got == want
    assert (0 <= got <= v) if v >= 0 else (v <= got <= 0)  # §8.4: fits B_E + 1 bits
    if a == 1 << g:
        assert got == v


def test_forgetting_floors_negative_values():
    assert int(scale_by_forgetting(np.array(-3), 1, 1, "truncate")) == -2
    assert int(scale_by_forgetting(np.array(-3), 1, 1, "half_up")) == -1
    assert int(scale_by_forgetting(np.array(3), 1, 1, "half_up")) == 2


def test_add_clamped_saturates_at_both_ends():
    np.testing.assert_array_equal(add_clamped(np.array([-10, 5, 250, 300]), np.array([3, -5, 5, 0]), 8),
                                  [0, 0, 255, 255])


def test_invalid_is_below_every_valid_candidate():
    assert INVALID_SIGNED < -(1 << 32)
