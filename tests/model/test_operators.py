"""Property tests (hypothesis) of the RTL operators of ``docs/arithmetic.md`` §7
(:mod:`dptbd.model.operators`) against Python integers and fractions."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from dptbd.weights import paper_weights
from dptbd.model import operators as ops
from dptbd.model.fixed import dp_step

from helpers.model_strategies import FAST, make_cfg




# ---------------------------------------------------------------------------------------
# operators (§7) against Python integers and fractions
# ---------------------------------------------------------------------------------------

PRODUCTS = st.integers(0, 2**47)
FRAC = st.integers(0, 16)


@FAST
@given(p=st.integers(-2**47, 2**47), f=FRAC)
def test_shift_right_truncate_is_floor_division(p, f):
    assert int(ops.shift_right_rounded(np.int64(p), f, "truncate")) == p // 2**f


@FAST
@given(p=PRODUCTS, f=FRAC)
def test_shift_right_half_up(p, f):
    assert int(ops.shift_right_rounded(np.int64(p), f, "half_up")) == math.floor(
        Fraction(p, 2**f) + Fraction(1, 2))


@FAST
@given(e=st.integers(0, 2**32 - 1), f=FRAC, mode=st.sampled_from(["truncate", "half_up"]))
def test_scale_by_unit_weight_is_identity(e, f, mode):
    assert int(ops.scale_by_weight(np.int64(e), np.int64(2**f), f, mode)) == e


@FAST
@given(e=st.integers(0, 2**32 - 1), f=FRAC, data=st.data(), mode=st.sampled_from(["truncate", "half_up"]))
def test_scale_by_weight_matches_fraction_and_never_exceeds_e(e, f, data, mode):
    c = data.draw(st.integers(0, 2**f))
    exact = Fraction(e * c, 2**f)
    expected = math.floor(exact) if mode == "truncate" else math.floor(exact + Fraction(1, 2))
    got = int(ops.scale_by_weight(np.int64(e), np.int64(c), f, mode))
    assert got == expected and 0 <= got <= e


def test_shift_right_rounded_vectorised_and_half_points():
    p = np.array([0, 1, 2, 3, 4, 5, 6, 7, 8], dtype=np.int64)
    np.testing.assert_array_equal(ops.shift_right_rounded(p, 2, "truncate"), [0, 0, 0, 0, 1, 1, 1, 1, 2])
    # 2/4 = 0.5 -> 1 and 6/4 = 1.5 -> 2: halves go up, not to even
    np.testing.assert_array_equal(ops.shift_right_rounded(p, 2, "half_up"), [0, 0, 1, 1, 1, 1, 2, 2, 2])
    np.testing.assert_array_equal(ops.shift_right_rounded(p, 0, "half_up"), p)
    with pytest.raises(ValueError, match=(r"^rounding must be 'truncate' or 'half_up', got "
                                          r"'nearest_even'$")):
        ops.shift_right_rounded(p, 2, "nearest_even")


@FAST
@given(a=st.integers(0, 2**32 - 1), b=st.integers(0, 2**16 - 1), bits=st.integers(1, 32))
def test_add_saturating_is_python_min(a, b, bits):
    assert int(ops.add_saturating(np.int64(a), np.int64(b), bits)) == min(a + b, 2**bits - 1)
    assert int(ops.saturate_unsigned(np.int64(a), bits)) == min(a, 2**bits - 1)


@FAST
@given(data=st.data(), n=st.integers(1, 25), cols=st.integers(1, 4))
def test_argmax_lowest_index(data, n, cols):
    cand = data.draw(arrays(np.int64, (n, cols), elements=st.integers(-1, 2)))
    best, index = ops.argmax_lowest_index(cand, axis=0)
    for j in range(cols):
        col = [int(v) for v in cand[:, j]]
        assert best[j] == max(col)
        assert index[j] == col.index(max(col))


@FAST
@given(data=st.data(), radius=st.sampled_from([1, 2]))
def test_lookup_weight_code_reads_start_row_above_m(data, radius):
    """§3: c[min(d, M), m] for every B_d-bit code d, M = START included."""
    n_moves = (2 * radius + 1) ** 2
    codes = data.draw(arrays(np.int64, (n_moves + 1, n_moves), elements=st.integers(0, 256)))
    top = 2**n_moves.bit_length() - 1                        # largest B_d-bit code
    d = data.draw(arrays(np.int64, (4, 3), elements=st.integers(0, top)))
    move = data.draw(st.integers(0, n_moves - 1))
    got = ops.lookup_weight_code(codes, d, move)
    for (i, j), code in np.ndenumerate(d):
        assert got[i, j] == codes[min(int(code), n_moves), move]


@FAST
@given(data=st.data(), h=st.integers(1, 5), w=st.integers(1, 5), dy=st.integers(-2, 2),
       dx=st.integers(-2, 2))
def test_predecessor_shift(data, h, w, dy, dx):
    state = data.draw(arrays(np.int64, (h, w), elements=st.integers(0, 99)))
    out = ops.predecessor(state, dy, dx, fill=-7)
    for y in range(h):
        for x in range(w):
            inside = 0 <= y - dy < h and 0 <= x - dx < w
            assert out[y, x] == (state[y - dy, x - dx] if inside else -7)


@pytest.mark.parametrize("radius", [1, 2])
@pytest.mark.parametrize("lut", ["paper", "random"])
def test_direction_above_m_weighs_like_start(radius, lut):
    """§3/§4.2: a previous-state d > M (only a corrupted store holds one) is looked up as M."""
    cfg = make_cfg(width=7, height=6, radius=radius, segment_frames=2, weights=(
        paper_weights(radius) if lut == "paper"
        else np.random.default_rng(radius).random(((2 * radius + 1) ** 2 + 1,
                                                   (2 * radius + 1) ** 2))))
    rng = np.random.default_rng(10 + radius)
    top = (1 << cfg.direction_bits) - 1                       # 15 for r = 1, 31 for r = 2
    shape = (cfg.height, cfg.width)
    differs = False
    for _ in range(5):
        energy = rng.integers(0, 2000, shape).astype(np.uint32)
        direction = rng.integers(0, top + 1, shape).astype(np.uint8)
        pixels = rng.integers(0, 256, shape).astype(np.uint16)
        assert (direction > cfg.start_code).any()
        clamped = np.minimum(direction, cfg.start_code).astype(np.uint8)
        got, want = dp_step(energy, direction, pixels, cfg), dp_step(energy, clamped, pixels, cfg)
        for a, b in zip(got, want):
            np.testing.assert_array_equal(a, b)
        # not vacuous: reading those codes as direction 0 instead would change the result
        zeroed = np.where(direction > cfg.start_code, 0, direction).astype(np.uint8)
        other = dp_step(energy, zeroed, pixels, cfg)
        differs |= any(not np.array_equal(a, b) for a, b in zip(other, got))
    assert differs
