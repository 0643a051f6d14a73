"""Property tests (hypothesis) of the golden model against ``docs/arithmetic.md``.

* fixed == float exactly when no product E * c needs rounding and nothing saturates
  (binary LUTs; dyadic LUTs on pixels that keep every product a multiple of 2^F), and
  a worked counterexample showing that an exactly representable weight alone is NOT
  enough (0.5 * 3 = 1.5: truncate gives 1, half_up 2);
* saturation clamps, never wraps (E <= E_max; plain DP with a narrow E is the wide
  result clamped; plain DP is monotone in the pixels; stay-put lower bound);
* the tie-break: lowest valid move index; invalid (out-of-image) candidates never win;
* an all-ones LUT is plain DP eq (8)-(9), computed here with a padded max filter;
* the operators of §7 against Python integers / fractions;
* segments and batch axes (§5).
"""

from __future__ import annotations

import math
import warnings
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from dptbd.config import DPConfig, EnergyWidthWarning, paper_weights, plain_weights
from dptbd.model import operators as ops
from dptbd.model.fixed import dp_step, run_fixed, segment_start
from dptbd.model.reference import run_float

SETTINGS = settings(max_examples=100, deadline=None, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
FAST = settings(SETTINGS, max_examples=300)


# ---------------------------------------------------------------------------------------
# helpers written from the spec, not from the model
# ---------------------------------------------------------------------------------------

def window(radius):
    """(dy, dx) in move-index order m = (dy + r)(2r + 1) + (dx + r)."""
    return [(dy, dx) for dy in range(-radius, radius + 1) for dx in range(-radius, radius + 1)]


def lowest_valid_move(height, width, radius):
    """Per pixel, the lowest move index whose predecessor (y - dy, x - dx) is in the image."""
    out = np.zeros((height, width), dtype=np.int64)
    for y in range(height):
        for x in range(width):
            out[y, x] = next(m for m, (dy, dx) in enumerate(window(radius))
                             if 0 <= y - dy < height and 0 <= x - dx < width)
    return out


def plain_dp(frames, radius):
    """Eq (8)-(9) for one segment: max filter over the window (padded with -inf) plus x;
    d = the first move attaining the max (strict > while scanning moves in index order)."""
    frames = np.asarray(frames, dtype=np.float64)
    _, height, width = frames.shape
    n_moves = (2 * radius + 1) ** 2
    energy = frames[0].copy()
    direction = np.full((height, width), n_moves)
    for x in frames[1:]:
        padded = np.pad(energy, radius, constant_values=-np.inf)
        best = np.full((height, width), -np.inf)
        direction = np.zeros((height, width), dtype=np.int64)
        for m, (dy, dx) in enumerate(window(radius)):
            # out[y, x] = energy[y - dy, x - dx] = padded[y - dy + r, x - dx + r]
            cand = padded[radius - dy:radius - dy + height, radius - dx:radius - dx + width]
            better = cand > best
            best = np.where(better, cand, best)
            direction = np.where(better, m, direction)
        energy = best + x
    return energy, direction


def make_cfg(**kw):
    """A DPConfig built with EnergyWidthWarning silenced (tests that care check it)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def no_saturation_cfg(**kw):
    """A DPConfig whose energy_bits is at least energy_bits_needed: must not warn."""
    probe = make_cfg(**kw)
    kw["energy_bits"] = probe.energy_bits_needed
    with warnings.catch_warnings():
        warnings.simplefilter("error", EnergyWidthWarning)
        return DPConfig(**kw)


@st.composite
def shapes(draw, max_k=4):
    return dict(height=draw(st.integers(3, 6)), width=draw(st.integers(3, 6)),
                radius=draw(st.sampled_from([1, 2])), segment_frames=draw(st.integers(1, max_k)))


def frames_for(draw, shape, high, n_frames=None):
    n_frames = shape["segment_frames"] if n_frames is None else n_frames
    return draw(arrays(np.int64, (n_frames, shape["height"], shape["width"]),
                       elements=st.integers(0, high)))


def run_both(frames, cfg):
    fix, flt = run_fixed(frames, cfg), run_float(frames, cfg)
    return fix.energy[0], fix.direction[0], flt.energy[0], flt.direction[0]


# ---------------------------------------------------------------------------------------
# fixed == float
# ---------------------------------------------------------------------------------------

@SETTINGS
@given(data=st.data(), shape=shapes(), rounding=st.sampled_from(["truncate", "half_up"]),
       frac_bits=st.integers(0, 8), input_bits=st.integers(1, 8))
def test_binary_lut_fixed_equals_float(data, shape, rounding, frac_bits, input_bits):
    """Weights in {0, 1} (codes 0 and 2^F): E * c / 2^F is an integer, rounding never acts."""
    n_moves = (2 * shape["radius"] + 1) ** 2
    lut = data.draw(arrays(np.float64, (n_moves + 1, n_moves), elements=st.sampled_from([0.0, 1.0])))
    cfg = no_saturation_cfg(**shape, rounding=rounding, weight_frac_bits=frac_bits,
                            input_bits=input_bits, weights=lut)
    assert cfg.weights_exact
    frames = frames_for(data.draw, shape, cfg.pixel_max)
    e_fix, d_fix, e_flt, d_flt = run_both(frames, cfg)
    assert e_fix.dtype == np.uint32 and d_fix.dtype == np.uint8
    np.testing.assert_array_equal(e_flt, np.round(e_flt))  # the float result is integer
    np.testing.assert_array_equal(e_fix.astype(np.float64), e_flt)
    np.testing.assert_array_equal(d_fix, d_flt)


@SETTINGS
@given(data=st.data(), shape=shapes(), frac_bits=st.integers(0, 3))
def test_exact_dyadic_lut_fixed_equals_float_when_products_are_exact(data, shape, frac_bits):
    """Exact LUT (codes / 2^F) and pixels that are multiples of 2^(F(K-1)): by induction
    E after frame k is a multiple of 2^(F(K-k)), so every E * c is a multiple of 2^F and the
    shift is exact. Then fixed == float and the rounding mode is irrelevant."""
    k_frames, n_moves = shape["segment_frames"], (2 * shape["radius"] + 1) ** 2
    codes = data.draw(arrays(np.int64, (n_moves + 1, n_moves), elements=st.integers(0, 1 << frac_bits)))
    lut = codes / (1 << frac_bits)
    grain = 1 << (frac_bits * (k_frames - 1))
    input_bits = grain.bit_length() - 1 + 3
    frames = frames_for(data.draw, shape, 7) * grain
    results = []
    for rounding in ("truncate", "half_up"):
        cfg = no_saturation_cfg(**shape, rounding=rounding, weight_frac_bits=frac_bits,
                                input_bits=input_bits, weights=lut)
        assert cfg.weights_exact
        np.testing.assert_array_equal(cfg.weight_codes, codes)
        e_fix, d_fix, e_flt, d_flt = run_both(frames, cfg)
        np.testing.assert_array_equal(e_fix.astype(np.float64), e_flt)
        np.testing.assert_array_equal(d_fix, d_flt)
        results.append((e_fix, d_fix))
    np.testing.assert_array_equal(results[0][0], results[1][0])
    np.testing.assert_array_equal(results[0][1], results[1][1])


def test_exact_weight_does_not_make_rounding_irrelevant():
    """w = 0.5 is exact for F = 1, yet 0.5 * 3 = 1.5 must be rounded (§4.3):
    truncate gives 1, half_up gives 2, float keeps 1.5. Exact weights only remove the
    weight-quantisation error, not the rounding of the product."""
    n_moves = 9
    lut = np.full((n_moves + 1, n_moves), 0.5)
    frames = np.zeros((2, 3, 3), dtype=np.int64)
    frames[0] = 3
    base = dict(width=3, height=3, segment_frames=2, input_bits=2, energy_bits=4,
                weight_frac_bits=1, weights=lut)
    for rounding, expected in (("truncate", 1), ("half_up", 2)):
        cfg = DPConfig(**base, rounding=rounding)
        assert cfg.weights_exact
        np.testing.assert_array_equal(run_fixed(frames, cfg).energy[0], np.full((3, 3), expected))
    np.testing.assert_array_equal(run_float(frames, DPConfig(**base)).energy[0], np.full((3, 3), 1.5))


# ---------------------------------------------------------------------------------------
# saturation
# ---------------------------------------------------------------------------------------

@SETTINGS
@given(data=st.data(), shape=shapes(), input_bits=st.integers(1, 6),
       rounding=st.sampled_from(["truncate", "half_up"]))
def test_saturation_clamps_plain_dp(data, shape, input_bits, rounding):
    """Plain DP with a narrow E is exactly the wide result clamped to E_max (clamping
    commutes with max and with adding a non-negative pixel), and E <= E_max."""
    radius = shape["radius"]
    wide = no_saturation_cfg(**shape, input_bits=input_bits, weights=plain_weights(radius),
                             rounding=rounding)
    energy_bits = data.draw(st.integers(input_bits, wide.energy_bits_needed))
    narrow = make_cfg(**shape, input_bits=input_bits, energy_bits=energy_bits,
                      weights=plain_weights(radius), rounding=rounding)
    frames = frames_for(data.draw, shape, narrow.pixel_max)
    e_wide = run_fixed(frames, wide).energy[0].astype(np.int64)
    e_narrow = run_fixed(frames, narrow).energy[0].astype(np.int64)
    assert e_narrow.max() <= narrow.e_max
    np.testing.assert_array_equal(e_narrow, np.minimum(e_wide, narrow.e_max))
    assert np.all(e_narrow[e_wide > narrow.e_max] == narrow.e_max)


@SETTINGS
@given(data=st.data(), shape=shapes(), input_bits=st.integers(1, 6), extra=st.integers(0, 3))
def test_plain_dp_is_monotone_in_the_pixels(data, shape, input_bits, extra):
    """Raising any pixel never lowers any E of plain DP, saturated or not."""
    needed = make_cfg(**shape, input_bits=input_bits).energy_bits_needed
    cfg = make_cfg(**shape, input_bits=input_bits, weights=plain_weights(shape["radius"]),
                   energy_bits=max(input_bits, needed - extra))
    frames = frames_for(data.draw, shape, cfg.pixel_max)
    bump = frames_for(data.draw, shape, cfg.pixel_max)
    higher = np.minimum(frames + bump, cfg.pixel_max)
    e_low = run_fixed(frames, cfg).energy[0]
    e_high = run_fixed(higher, cfg).energy[0]
    assert np.all(e_high >= e_low)


@SETTINGS
@given(data=st.data(), shape=shapes(), input_bits=st.integers(1, 8), extra=st.integers(0, 4),
       rounding=st.sampled_from(["truncate", "half_up"]), frac_bits=st.integers(0, 8))
def test_saturation_never_wraps_paper_lut(data, shape, input_bits, extra, rounding, frac_bits):
    """Paper LUT, narrow E: E <= E_max, and E >= min(stay-put sum, E_max) because the zero
    move has weight 1 (a wrapping adder would fall below that bound)."""
    needed = make_cfg(**shape, input_bits=input_bits).energy_bits_needed
    cfg = make_cfg(**shape, input_bits=input_bits, energy_bits=max(input_bits, needed - extra),
                   rounding=rounding, weight_frac_bits=frac_bits)
    frames = frames_for(data.draw, shape, cfg.pixel_max)
    energy = run_fixed(frames, cfg).energy[0].astype(np.int64)
    assert energy.max() <= cfg.e_max
    assert np.all(energy >= np.minimum(frames.sum(axis=0), cfg.e_max))


@pytest.mark.parametrize("radius", [1, 2])
def test_full_scale_saturates_to_emax(radius):
    """B_in = B_E = 8, K = 2, every pixel 255: 255 + 255 clamps to 255 (a wrap gives 254)."""
    with pytest.warns(EnergyWidthWarning):
        cfg = DPConfig(width=5, height=5, segment_frames=2, input_bits=8, energy_bits=8,
                       radius=radius)
    frames = np.full((2, 5, 5), 255, dtype=np.uint16)
    np.testing.assert_array_equal(run_fixed(frames, cfg).energy[0], np.full((5, 5), 255))
    # the 32-bit extreme: E_max = 2^32 - 1 held in uint32, still clamped
    cfg32 = make_cfg(width=3, height=3, segment_frames=2, input_bits=16, energy_bits=32,
                     radius=radius)
    e, d = np.full((3, 3), 2**32 - 1, dtype=np.uint32), np.full((3, 3), 4, dtype=np.uint8)
    e_new, _ = dp_step(e, d, np.full((3, 3), 2**16 - 1, dtype=np.uint16), cfg32)
    assert e_new.dtype == np.uint32
    np.testing.assert_array_equal(e_new, np.full((3, 3), 2**32 - 1))


# ---------------------------------------------------------------------------------------
# tie-break and image edges
# ---------------------------------------------------------------------------------------

@SETTINGS
@given(data=st.data(), shape=shapes(), frac_bits=st.integers(0, 8),
       rounding=st.sampled_from(["truncate", "half_up"]))
def test_all_zero_frames_pick_lowest_valid_move(data, shape, frac_bits, rounding):
    """All valid candidates are 0 (any LUT): d = the lowest VALID move; the invalid
    out-of-image candidates (lower indices at the bottom/right edges) never win."""
    n_moves = (2 * shape["radius"] + 1) ** 2
    lut = data.draw(arrays(np.float64, (n_moves + 1, n_moves),
                           elements=st.floats(0, 1, allow_nan=False)))
    cfg = make_cfg(**shape, weights=lut, weight_frac_bits=frac_bits, rounding=rounding)
    frames = np.zeros((shape["segment_frames"], shape["height"], shape["width"]), dtype=np.uint8)
    expected = lowest_valid_move(shape["height"], shape["width"], shape["radius"])
    if shape["segment_frames"] == 1:
        expected[:] = n_moves  # START
    for out in (run_fixed(frames, cfg), run_float(frames, cfg)):
        np.testing.assert_array_equal(out.direction[0], expected)
        np.testing.assert_array_equal(out.energy[0], 0)


@pytest.mark.parametrize("radius", [1, 2])
def test_lowest_valid_move_at_the_edges_explicitly(radius):
    """All-zero frames, r = 1 on 4 x 5 (H x W): interior, top row and left column -> 0
    (move (-1,-1)); bottom row -> 3 (dy must be >= 0, so (0,-1) is the first valid move);
    right column -> 1 (dx must be >= 0: (-1,0)); bottom-right corner -> 4 (the centre, the
    lowest move with dy >= 0 and dx >= 0)."""
    cfg = DPConfig(width=5, height=4, segment_frames=2, radius=radius)
    d = run_fixed(np.zeros((2, 4, 5), dtype=np.uint8), cfg).direction[0]
    if radius == 1:
        assert d[1, 1] == 0 and d[0, 0] == 0 and d[0, 2] == 0 and d[2, 0] == 0
        assert d[3, 2] == 3 and d[3, 0] == 3  # bottom row: dy must be 0 -> (0, -1) first
        assert d[1, 4] == 1 and d[0, 4] == 1  # right column: dx must be 0 -> (-1, 0) first
        assert d[3, 4] == 4                   # bottom-right: only dy, dx >= 0 -> centre
    np.testing.assert_array_equal(d, lowest_valid_move(4, 5, radius))


@SETTINGS
@given(data=st.data(), shape=shapes(max_k=1), lut_kind=st.sampled_from(["plain", "paper"]))
def test_tie_break_lowest_index_at_frame_two(data, shape, lut_kind):
    """Frame 1 from {0, 1, 2} (many ties); at frame 2 every predecessor is START (weight 1
    for both LUTs) so the candidates are E_1(q); d must be the lowest valid m attaining
    their max."""
    shape = dict(shape, segment_frames=2)
    radius = shape["radius"]
    lut = plain_weights(radius) if lut_kind == "plain" else paper_weights(radius)
    cfg = make_cfg(**shape, weights=lut)
    frames = frames_for(data.draw, shape, 2)
    height, width = shape["height"], shape["width"]
    expected_d = np.zeros((height, width), dtype=np.int64)
    expected_e = np.zeros((height, width), dtype=np.int64)
    for y in range(height):
        for x in range(width):
            cands = [(int(frames[0, y - dy, x - dx]), m) for m, (dy, dx) in enumerate(window(radius))
                     if 0 <= y - dy < height and 0 <= x - dx < width]
            top = max(c for c, _ in cands)
            expected_d[y, x] = min(m for c, m in cands if c == top)
            expected_e[y, x] = top + frames[1, y, x]
    for out in (run_fixed(frames, cfg), run_float(frames, cfg)):
        np.testing.assert_array_equal(out.direction[0], expected_d)
        np.testing.assert_array_equal(out.energy[0], expected_e)


def test_constructed_tie_goes_to_lowest_index():
    """Centre pixel (2,2) of a 5x5 frame, r = 1: equal E at the predecessors of moves 2, 4, 7
    (and 0 elsewhere) -> d = 2; with moves 4 and 7 only -> d = 4 (centre before 7)."""
    cfg = DPConfig(width=5, height=5, segment_frames=2, weights=plain_weights(1))
    for movers, expected in (([2, 4, 7], 2), ([4, 7], 4), ([7, 8], 7), ([8], 8)):
        frames = np.zeros((2, 5, 5), dtype=np.uint8)
        for m in movers:
            dy, dx = window(1)[m]
            frames[0, 2 - dy, 2 - dx] = 9
        out = run_fixed(frames, cfg)
        assert out.direction[0][2, 2] == expected and out.energy[0][2, 2] == 9


def test_invalid_candidate_never_wins_against_zero_weight():
    """Weights 0 for every move from a real direction (START row all ones). Frame 2: every
    E is 10; frame 3: every valid candidate is 0 * 10 = 0, and the out-of-image candidates
    must still lose against these zeros: d is the lowest VALID move (e.g. 4, the centre,
    at the bottom-right corner where moves 0-3 are invalid), E = 0 + 5."""
    n_moves = 9
    lut = np.zeros((n_moves + 1, n_moves))
    lut[n_moves] = 1.0  # START row all ones so frame 2 has real values
    cfg = DPConfig(width=4, height=4, segment_frames=3, weights=lut)
    frames = np.full((3, 4, 4), 5, dtype=np.uint8)
    out = run_fixed(frames, cfg)
    assert out.direction[0][3, 3] == 4   # every valid candidate is 0 * E = 0: centre wins
    assert out.energy[0][3, 3] == 5
    np.testing.assert_array_equal(out.direction[0], lowest_valid_move(4, 4, 1))


# ---------------------------------------------------------------------------------------
# all-ones LUT == plain DP eq (8)-(9)
# ---------------------------------------------------------------------------------------

@SETTINGS
@given(data=st.data(), shape=shapes(max_k=5), high=st.sampled_from([1, 3, 255]),
       rounding=st.sampled_from(["truncate", "half_up"]), frac_bits=st.integers(0, 8))
def test_all_ones_lut_is_plain_dp(data, shape, high, rounding, frac_bits):
    cfg = no_saturation_cfg(**shape, weights=plain_weights(shape["radius"]), rounding=rounding,
                            weight_frac_bits=frac_bits)
    frames = frames_for(data.draw, shape, high)
    expected_e, expected_d = plain_dp(frames, shape["radius"])
    for out in (run_fixed(frames, cfg), run_float(frames, cfg)):
        np.testing.assert_array_equal(out.energy[0], expected_e)
        np.testing.assert_array_equal(out.direction[0], expected_d)


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


# ---------------------------------------------------------------------------------------
# segments (§5) and batch axes
# ---------------------------------------------------------------------------------------

@SETTINGS
@given(data=st.data(), k_frames=st.integers(1, 4), n_frames=st.integers(1, 10))
def test_segments_are_independent_runs(data, k_frames, n_frames):
    stride = data.draw(st.integers(1, k_frames))
    cfg = make_cfg(width=4, height=3, segment_frames=k_frames, segment_stride=stride)
    frames = data.draw(arrays(np.int64, (n_frames, 3, 4), elements=st.integers(0, 255)))
    n_seg = 0 if n_frames < k_frames else (n_frames - k_frames) // stride + 1
    assert cfg.n_segments(n_frames) == n_seg
    if n_seg == 0:
        with pytest.raises(ValueError, match=rf"^a sequence of {n_frames} frames is shorter than one "
                                             rf"segment \(segment_frames={k_frames}\)$"):
            run_fixed(frames, cfg)
        return
    out = run_fixed(frames, cfg)
    assert out.energy.shape == (n_seg, 3, 4) and out.direction.shape == (n_seg, 3, 4)
    single = cfg.replace(segment_stride=k_frames)
    for s in range(n_seg):
        first = s * stride
        assert out.end_frames[s] == first + k_frames - 1
        ref = run_fixed(frames[first:first + k_frames], single)
        np.testing.assert_array_equal(out.energy[s], ref.energy[0])
        np.testing.assert_array_equal(out.direction[s], ref.direction[0])
    # the segment start ignores the previous state entirely: E = x, d = START
    e0, d0 = segment_start(frames[0], cfg)
    np.testing.assert_array_equal(e0, frames[0])
    np.testing.assert_array_equal(d0, cfg.start_code)


@SETTINGS
@given(data=st.data(), shape=shapes(), batch=st.integers(1, 3))
def test_batch_axes_are_independent_trials(data, shape, batch):
    cfg = make_cfg(**shape)
    frames = np.stack([frames_for(data.draw, shape, 255) for _ in range(batch)])
    for run in (run_fixed, run_float):
        out = run(frames, cfg)
        for b in range(batch):
            ref = run(frames[b], cfg)
            np.testing.assert_array_equal(out.energy[b], ref.energy)
            np.testing.assert_array_equal(out.direction[b], ref.direction)
