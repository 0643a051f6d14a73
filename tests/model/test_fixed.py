"""Property tests (hypothesis) of the golden model against ``docs/arithmetic.md``.

* fixed == float exactly when no product E * c needs rounding and nothing saturates
  (binary LUTs; dyadic LUTs on pixels that keep every product a multiple of 2^F), and
  a worked counterexample showing that an exactly representable weight alone is NOT
  enough (0.5 * 3 = 1.5: truncate gives 1, half_up 2);
* saturation clamps, never wraps (E <= E_max; plain DP with a narrow E is the wide
  result clamped; plain DP is monotone in the pixels; stay-put lower bound);
* the tie-break: lowest valid move index; invalid (out-of-image) candidates never win;
* an all-ones LUT is plain DP eq (8)-(9), computed here with a padded max filter;

The operators of §7 are tested in ``test_operators.py``, segments and batch axes (§5) in
``test_segments.py``.
"""

from __future__ import annotations


import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.weights import paper_weights, plain_weights
from dptbd.model.fixed import dp_step, run_fixed
from dptbd.model.reference import run_float

from helpers.model_strategies import SETTINGS, frames_for, make_cfg, no_saturation_cfg, shapes



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
