"""``dptbd.config.lut``: the weight LUT's codes (``docs/arithmetic.md`` §3), its address map and
its run-time rewrite (the LUT tables themselves: tests/test_weights.py)."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from dptbd import ConfigError, DPConfig
from dptbd.weights import plain_weights
from helpers.luts import lut_with


# ---------------------------------------------------------------------------------------
# §3 weight codes (the LUT tables themselves: tests/test_weights.py)
# ---------------------------------------------------------------------------------------

def exact_code(w, frac_bits):
    return math.floor(Fraction(w) * 2**frac_bits + Fraction(1, 2))


@pytest.mark.parametrize("value, frac_bits, code", [
    (0.25, 1, 1),     # 0.5 -> 1: half goes up, not to even (0)
    (0.75, 1, 2),     # 1.5 -> 2
    (0.125, 2, 1),    # 0.5 -> 1
    (0.375, 2, 2),    # 1.5 -> 2
    (0.625, 2, 3),    # 2.5 -> 3 (round-half-even would give 2)
    (0.3, 8, 77),     # 76.8
    (0.3, 0, 0),
    (0.5, 0, 1),      # 0.5 -> 1 with F = 0
    (0.4, 0, 0),
    (1.0, 16, 65536),
    (0.0, 16, 0),
])
def test_weight_codes_round_half_up(value, frac_bits, code):
    cfg = DPConfig(weight_frac_bits=frac_bits, weights=lut_with(value))
    codes = cfg.weight_codes
    assert codes.dtype == np.uint32
    assert int(codes[0, 0]) == code == exact_code(value, frac_bits)
    assert np.all(codes[1:] == 2**frac_bits)


@pytest.mark.parametrize("frac_bits", [0, 1, 3, 8, 16])
def test_weight_codes_random_against_fractions(frac_bits):
    rng = np.random.default_rng(frac_bits)
    lut = rng.uniform(0, 1, size=(10, 9))
    # sprinkle exact half points k + 1/2 (in units of 2^-F)
    halves = (rng.integers(0, 2**frac_bits, size=9) + 0.5) / 2**frac_bits
    lut[3, :] = np.minimum(halves, 1.0)
    cfg = DPConfig(weight_frac_bits=frac_bits, weights=lut)
    expected = np.array([[exact_code(w, frac_bits) for w in row] for row in lut])
    np.testing.assert_array_equal(cfg.weight_codes, expected)


@pytest.mark.parametrize("frac_bits", [0, 1, 8])
def test_weight_codes_just_below_a_half(frac_bits):
    value = math.nextafter(0.5, 0.0) / 2**frac_bits  # w * 2^F = 0.49999999999999994
    cfg = DPConfig(weight_frac_bits=frac_bits, weights=lut_with(value))
    assert int(cfg.weight_codes[0, 0]) == exact_code(value, frac_bits) == 0


def test_weights_exact():
    for frac_bits in range(17):  # the default LUT is exact for every F >= 0
        assert DPConfig(weight_frac_bits=frac_bits).weights_exact
        assert DPConfig(weight_frac_bits=frac_bits, weights=plain_weights(1)).weights_exact
    assert not DPConfig(weight_frac_bits=8, weights=lut_with(0.3)).weights_exact
    assert not DPConfig(weight_frac_bits=0, weights=lut_with(0.5)).weights_exact
    assert DPConfig(weight_frac_bits=1, weights=lut_with(0.5)).weights_exact
    assert not DPConfig(weight_frac_bits=2, weights=lut_with(0.125)).weights_exact
    assert DPConfig(weight_frac_bits=3, weights=lut_with(0.125)).weights_exact


def test_weights_are_stored_immutable_and_hashable():
    cfg = DPConfig(weights=np.ones((10, 9)))
    assert isinstance(cfg.weights, tuple) and isinstance(cfg.weights[0], tuple)
    assert hash(cfg) == hash(DPConfig(weights=plain_weights(1).tolist()))
    assert cfg == DPConfig(weights=plain_weights(1))


def test_lut_address_is_p_times_m_plus_m():
    cfg = DPConfig(width=16, height=12)
    assert [cfg.lut_address(p, m) for p, m in ((0, 0), (0, 8), (1, 0), (9, 8))] == [0, 8, 9, 89]


@pytest.mark.parametrize("entry", [(10, 0), (0, 9), (-1, 0)])
def test_lut_address_refuses_entries_outside_the_table(entry):
    cfg = DPConfig(width=16, height=12)
    with pytest.raises(ConfigError, match=rf"^LUT entry must have predecessor in \[0, 9\] and move "
                                          rf"in \[0, 8\], got \({entry[0]}, {entry[1]}\)$"):
        cfg.lut_address(*entry)


def test_with_weight_codes_round_trips_the_codes():
    cfg = DPConfig(width=16, height=12, weight_frac_bits=3)
    codes = np.arange(90).reshape(10, 9) % 9
    assert np.array_equal(cfg.with_weight_codes(codes).weight_codes, codes)


def test_with_weight_codes_refusals():
    cfg = DPConfig(width=16, height=12, weight_frac_bits=3)
    with pytest.raises(ConfigError, match=r"^LUT codes must have shape \(10, 9\) for radius=1, "
                                          r"got \(9, 9\)$"):
        cfg.with_weight_codes(np.zeros((9, 9)))
    with pytest.raises(ConfigError, match=r"^LUT codes must be in \[0, 2\*\*F = 8\], found \[9, 9, 9\]$"):
        cfg.with_weight_codes(np.full((10, 9), 9))
