"""``dptbd.config.DPConfig`` against ``docs/arithmetic.md`` (parameter table, §2, §3, §5)."""

from __future__ import annotations

import dataclasses
import math
import warnings
from fractions import Fraction

import numpy as np
import pytest

from dptbd import ConfigError, DPConfig, EnergyWidthWarning
from dptbd.config import ROUNDING_MODES
from dptbd.weights import paper_weights, plain_weights
from dptbd.errors import DptbdError
from helpers.refusals import whole


# ---------------------------------------------------------------------------------------
# defaults and derived quantities
# ---------------------------------------------------------------------------------------

def test_defaults_match_the_parameter_table():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the defaults must not warn
        cfg = DPConfig()
    assert (cfg.width, cfg.height) == (128, 128)
    assert cfg.segment_frames == 4
    assert cfg.segment_stride == 4  # None means K
    assert cfg.input_bits == 8
    assert cfg.energy_bits == 16
    assert cfg.weight_frac_bits == 8
    assert cfg.radius == 1
    assert cfg.rounding == "truncate"
    assert ROUNDING_MODES == ("truncate", "half_up")
    np.testing.assert_array_equal(cfg.weight_array, paper_weights(1))
    # derived
    assert cfg.n_moves == 9 and cfg.start_code == 9
    assert cfg.direction_bits == 4
    assert cfg.weight_bits == 9
    assert cfg.e_max == 2**16 - 1
    assert cfg.pixel_max == 255
    assert cfg.energy_bits_needed == (4 * 255).bit_length() == 10


def test_direction_bits_and_moves_per_radius():
    """B_d = bit length of M: 4 for r = 1 (codes 0..9), 5 for r = 2 (codes 0..25)."""
    r1, r2 = DPConfig(radius=1), DPConfig(radius=2)
    assert (r1.n_moves, r1.direction_bits, r1.start_code) == (9, 4, 9)
    assert (r2.n_moves, r2.direction_bits, r2.start_code) == (25, 5, 25)
    assert r2.weight_array.shape == (26, 25)  # weights=None follows the radius
    assert r2.moves.shape == (25, 2)


@pytest.mark.parametrize("frac_bits", [0, 1, 8, 16])
def test_weight_bits_hold_one(frac_bits):
    cfg = DPConfig(weight_frac_bits=frac_bits)
    assert cfg.weight_bits == frac_bits + 1
    assert int(cfg.weight_codes.max()) == 2**frac_bits < 2**cfg.weight_bits


def test_numpy_integers_are_accepted_as_plain_ints():
    cfg = DPConfig(width=np.int64(5), height=np.int32(6), segment_frames=np.uint8(3))
    assert (cfg.width, cfg.height, cfg.segment_frames) == (5, 6, 3)
    assert all(type(v) is int for v in (cfg.width, cfg.height, cfg.segment_frames, cfg.segment_stride))


# ---------------------------------------------------------------------------------------
# §3 weight codes (the LUT tables themselves: tests/test_weights.py)
# ---------------------------------------------------------------------------------------

def lut_with(value, radius=1):
    w = plain_weights(radius)
    w[0, 0] = value
    return w


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


# ---------------------------------------------------------------------------------------
# §5 segments
# ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("k, stride, n_frames, n_seg", [
    (4, None, 100, 25),
    (5, 4, 100, 24),   # Table 1's 24 outputs
    (8, 4, 100, 24),
    (4, 4, 3, 0),      # shorter than one segment
    (4, 4, 4, 1),
    (4, 4, 7, 1),      # trailing frames produce nothing
    (4, 1, 7, 4),
    (1, 1, 5, 5),
])
def test_n_segments(k, stride, n_frames, n_seg):
    cfg = DPConfig(segment_frames=k, segment_stride=stride)
    assert cfg.n_segments(n_frames) == n_seg
    assert n_seg == (0 if n_frames < k else (n_frames - k) // cfg.segment_stride + 1)


# ---------------------------------------------------------------------------------------
# frozen, replace, from_mapping
# ---------------------------------------------------------------------------------------

def test_frozen():
    cfg = DPConfig()
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.width = 64
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.weights = None


def test_replace_validates_again():
    cfg = DPConfig()
    assert cfg.replace(width=64).width == 64
    with pytest.raises(ConfigError, match=r"^width must be an integer in \[3, 4096\], got 2$"):
        cfg.replace(width=2)


def test_replace_segment_frames_keeps_default_stride():
    cfg = DPConfig()  # stride left at its default (= K)
    assert cfg.replace(segment_frames=8).segment_stride == 8
    assert cfg.replace(segment_frames=2).segment_stride == 2


def test_from_mapping():
    values = {"width": 64, "height": 32, "segment_frames": 5, "segment_stride": 4,
              "rounding": "half_up"}
    assert DPConfig.from_mapping(values) == DPConfig(**values)


@pytest.mark.parametrize("bad", [{"widht": 64}, {"width": 64, "energy": 16, "Radius": 1}])
def test_from_mapping_rejects_unknown_keys_by_name(bad):
    known = sorted(f.name for f in dataclasses.fields(DPConfig))
    unknown = sorted(set(bad) - set(known))  # named, and the allowed names listed
    with pytest.raises(ConfigError, match=whole(f"unknown parameter(s) {unknown}; allowed: {known}")):
        DPConfig.from_mapping(bad)


def test_from_mapping_validates_values():
    with pytest.raises(ConfigError, match=r"^radius must be an integer in \[1, 2\], got 3$"):
        DPConfig.from_mapping({"radius": 3})


# ---------------------------------------------------------------------------------------
# out-of-range parameters: ConfigError naming the parameter and its range
# ---------------------------------------------------------------------------------------


def not_integer(name, span, value):
    """The refusal of an integer parameter outside its domain (``dptbd.errors.check_int``)."""
    return f"{name} must be an integer in {span}, got {value!r}"


SHAPE_10_9 = "shape (10, 9) for radius=1 ([predecessor direction 0..9, move 0..8])"
BAD = [
    # (overrides, the whole message)
    *[({f: v}, not_integer(f, "[3, 4096]", v)) for f in ("width", "height")
      for v in (2, 0, -1, 4097, 3.0, True, "8", None)],
    *[({"segment_frames": v}, not_integer("segment_frames", "[1, 65535]", v))
      for v in (0, -4, 65536, 4.0, None)],
    *[({"segment_stride": v}, not_integer("segment_stride", "[1, segment_frames=4]", v))
      for v in (0, 5, -1, 2.0, True)],
    ({"segment_frames": 2, "segment_stride": 3},
     "segment_stride must be an integer in [1, segment_frames=2], got 3"),
    *[({"input_bits": v}, not_integer("input_bits", "[1, 16]", v)) for v in (0, 17, 8.0)],
    *[({"energy_bits": v}, not_integer("energy_bits", "[input_bits=8, 32]", v))
      for v in (7, 1, 0, 33, 64, 16.0)],
    ({"input_bits": 12, "energy_bits": 11}, "energy_bits must be an integer in [input_bits=12, 32], got 11"),
    *[({"weight_frac_bits": v}, not_integer("weight_frac_bits", "[0, 16]", v)) for v in (-1, 17, 1.5)],
    *[({"radius": v}, not_integer("radius", "[1, 2]", v)) for v in (0, 3, 1.0)],
    *[({"rounding": v}, f"rounding must be one of ('truncate', 'half_up'), got {v!r}")
      for v in ("round", "", "TRUNCATE", None, 0)],
    ({"weights": np.ones((9, 9))}, f"weights must have {SHAPE_10_9}, got (9, 9)"),
    ({"weights": np.ones((10, 9)), "radius": 2}, "weights must have shape (26, 25) for radius=2 "
     "([predecessor direction 0..25, move 0..24]), got (10, 9)"),
    ({"weights": np.ones(90)}, f"weights must have {SHAPE_10_9}, got (90,)"),
    ({"weights": lut_with(1.5)}, "weights must be finite and in [0, 1], found [1.5]"),
    ({"weights": lut_with(-0.1)}, "weights must be finite and in [0, 1], found [-0.1]"),
    ({"weights": lut_with(np.nan)}, "weights must be finite and in [0, 1], found [nan]"),
    ({"weights": lut_with(np.inf)}, "weights must be finite and in [0, 1], found [inf]"),
    ({"weights": "abc"}, "weights must be a numeric table, got str"),
    ({"weights": [[1.0, 1.0], [1.0]]}, "weights must be a numeric table, got list"),
]


@pytest.mark.parametrize("overrides, message", BAD, ids=[f"{o}" for o, _ in BAD])
def test_out_of_range_raises_config_error(overrides, message):
    with pytest.raises(ConfigError, match=whole(message)):
        DPConfig(**overrides)
    assert issubclass(ConfigError, DptbdError) and issubclass(ConfigError, ValueError)


@pytest.mark.parametrize("energy_bits", [0, 33])
def test_energy_bits_message_states_the_real_lower_bound(energy_bits):
    with pytest.raises(ConfigError, match=whole(not_integer("energy_bits", "[input_bits=8, 32]",
                                                               energy_bits))):
        DPConfig(input_bits=8, energy_bits=energy_bits)


# (parameters at a bound of their domain, the derived quantities they must give)
BOUNDARIES = [
    ({"width": 3, "height": 4096}, {"n_moves": 9, "lut_entries": 90}),
    ({"width": 4096, "height": 3}, {"n_moves": 9, "lut_entries": 90}),
    ({"segment_frames": 1}, {"k_max": 1, "segment_stride": 1, "energy_bits_needed": 8}),
    ({"segment_frames": 65535, "energy_bits": 32},
     {"k_max": 65535, "energy_bits_needed": 24, "e_max": 2**32 - 1}),
    ({"segment_frames": 5, "segment_stride": 1}, {"energy_bits_needed": 11}),
    ({"segment_frames": 5, "segment_stride": 5}, {"energy_bits_needed": 11}),
    ({"input_bits": 1, "energy_bits": 1}, {"pixel_max": 1, "e_max": 1, "energy_bits_needed": 3}),
    ({"input_bits": 16, "energy_bits": 16},
     {"pixel_max": 65535, "e_max": 65535, "energy_bits_needed": 18}),
    ({"energy_bits": 32}, {"e_max": 2**32 - 1, "state_bits": 36}),
    ({"weight_frac_bits": 0}, {"weight_bits": 1}),
    ({"weight_frac_bits": 16}, {"weight_bits": 17}),
    ({"radius": 2}, {"n_moves": 25, "start_code": 25, "direction_bits": 5, "lut_entries": 650,
                     "state_bits": 21}),
    ({"rounding": "half_up"}, {"state_bits": 20}),
    ({"weights": np.zeros((10, 9))}, {"weights_binary": True}),
    ({"weights": plain_weights(1)}, {"weights_binary": True}),
]


@pytest.mark.parametrize("kw, derived", BOUNDARIES)
def test_boundary_values_are_accepted(kw, derived):
    """A value at a bound of its domain is kept as given (not clipped, not refused), gives
    the derived quantities it must, and the configuration survives its mapping."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        cfg = DPConfig(**kw)
        assert DPConfig.from_mapping(cfg.to_mapping()) == cfg
    for name, value in kw.items():
        if name == "weights":
            assert np.array_equal(cfg.weight_array, value)
        else:
            assert getattr(cfg, name) == value
    assert {name: getattr(cfg, name) for name in derived} == derived


# ---------------------------------------------------------------------------------------
# EnergyWidthWarning
# ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("input_bits, k", [(8, 4), (8, 5), (1, 1), (4, 16), (16, 2), (12, 100)])
def test_energy_width_warning_exactly_below_needed(input_bits, k):
    needed = max(input_bits, (k * (2**input_bits - 1)).bit_length())
    for energy_bits in range(input_bits, 33):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            cfg = DPConfig(input_bits=input_bits, segment_frames=k, energy_bits=energy_bits)
        hits = [w for w in caught if issubclass(w.category, EnergyWidthWarning)]
        assert cfg.energy_bits_needed == needed
        if energy_bits < needed:
            assert len(hits) == 1, energy_bits
            assert "energy_bits" in str(hits[0].message)
            assert f">= {needed}" in str(hits[0].message)
        else:
            assert not hits, energy_bits


# ---------------------------------------------------------------------------------------
# segmentation parameters (docs/arithmetic.md §6)
# ---------------------------------------------------------------------------------------

def test_segmentation_defaults():
    cfg = DPConfig()
    assert (cfg.candidate_count, cfg.candidate_capacity, cfg.histogram_bits,
            cfg.histogram_shift) == (None, None, 10, None)
    assert cfg.n_candidates == 33                 # 0.2 % of 128 x 128, rounded half up
    assert cfg.record_capacity == 66              # 2n
    assert cfg.n_bins == 1024 and cfg.threshold_bits == 11
    assert cfg.bin_shift == 0                     # bitlen(4 * 255) = 10 bits fit 1024 bins
    assert cfg.bin_count_bits == 7                # bitlen(C + 1) = bitlen(67)


@pytest.mark.parametrize("width, height, n", [(128, 128, 33), (25, 10, 1), (83, 3, 0),
                                              (250, 3, 2), (64, 64, 8), (10, 10, 0),
                                              (4096, 4096, 33554)])
def test_default_count_is_point_two_percent_half_up(width, height, n):
    cfg = DPConfig(width=width, height=height)
    assert cfg.n_candidates == n
    assert n == math.floor(Fraction(width * height, 500) + Fraction(1, 2))   # exact 0.2 %


def test_default_count_follows_the_frame_size():
    cfg = DPConfig(width=64, height=64)
    assert cfg.n_candidates == 8 and cfg.record_capacity == 16
    assert cfg.replace(width=128, height=128).n_candidates == 33
    assert DPConfig(width=10, height=10).n_candidates == 0            # 0.2 points rounds to 0


@pytest.mark.parametrize("kw, shift", [
    (dict(), 0),
    (dict(input_bits=12, segment_frames=6), 5),              # bitlen(6 * 4095) = 15
    (dict(histogram_bits=8), 2),
    (dict(histogram_bits=16), 0),
    (dict(input_bits=8, energy_bits=9, segment_frames=4), 0),  # saturating: B_E = 9 < 10
    (dict(input_bits=16, energy_bits=32, segment_frames=65535, histogram_bits=1), 31),
])
def test_default_bin_shift_covers_the_reachable_energies(kw, shift):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        cfg = DPConfig(**kw)
    assert cfg.bin_shift == shift
    reach = min(cfg.energy_bits, cfg.energy_bits_needed)
    assert ((1 << reach) - 1) >> cfg.bin_shift <= cfg.n_bins - 1 or cfg.bin_shift == 0


def test_explicit_segmentation_parameters():
    cfg = DPConfig(width=16, height=16, candidate_count=5, candidate_capacity=5,
                   histogram_bits=4, histogram_shift=3)
    assert (cfg.n_candidates, cfg.record_capacity, cfg.n_bins, cfg.bin_shift,
            cfg.bin_count_bits) == (5, 5, 16, 3, 3)
    assert DPConfig(width=4, height=4, candidate_count=16).record_capacity == 16   # min(2n, WH)
    assert DPConfig(width=4, height=4, candidate_count=0).record_capacity == 0


SEG_BAD = [
    *[({"candidate_count": v}, not_integer("candidate_count", "[0, 16384]", v))
      for v in (-1, 16385, 3.0, True, "33")],
    ({"width": 4, "height": 4, "candidate_count": 17},
     "candidate_count must be an integer in [0, 16], got 17"),
    *[({"candidate_capacity": v}, not_integer("candidate_capacity", "[candidate_count=33, 16384]", v))
      for v in (32, 0, 16385, 40.0, False)],
    ({"candidate_count": 5, "candidate_capacity": 4},
     "candidate_capacity must be an integer in [candidate_count=5, 16384], got 4"),
    *[({"histogram_bits": v}, not_integer("histogram_bits", "[1, 16]", v)) for v in (0, 17, None, 10.0)],
    *[({"histogram_shift": v}, not_integer("histogram_shift", "[0, 15]", v)) for v in (-1, 16, 2.0)],
    ({"energy_bits": 12, "histogram_shift": 12}, "histogram_shift must be an integer in [0, 11], got 12"),
]


@pytest.mark.parametrize("overrides, message", SEG_BAD, ids=[f"{o}" for o, _ in SEG_BAD])
def test_segmentation_parameters_out_of_range(overrides, message):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        with pytest.raises(ConfigError, match=whole(message)):
            DPConfig(**overrides)


def test_segmentation_parameters_from_mapping():
    values = {"candidate_count": 10, "candidate_capacity": 12, "histogram_bits": 8,
              "histogram_shift": 2}
    assert DPConfig.from_mapping(values) == DPConfig(**values)


# ---- derived quantities: one home ------------------------------------------------------------

def test_state_bits_and_lut_entries():
    cfg = DPConfig(width=16, height=12, segment_frames=3, energy_bits=12, radius=2)
    assert cfg.state_bits == 12 + 5            # B_d = bitlen(25)
    assert cfg.lut_entries == 26 * 25


def test_lut_address_is_p_times_m_plus_m():
    cfg = DPConfig(width=16, height=12)
    assert [cfg.lut_address(p, m) for p, m in ((0, 0), (0, 8), (1, 0), (9, 8))] == [0, 8, 9, 89]


@pytest.mark.parametrize("entry", [(10, 0), (0, 9), (-1, 0)])
def test_lut_address_refuses_entries_outside_the_table(entry):
    cfg = DPConfig(width=16, height=12)
    with pytest.raises(ConfigError, match=rf"^LUT entry must have predecessor in \[0, 9\] and move "
                                          rf"in \[0, 8\], got \({entry[0]}, {entry[1]}\)$"):
        cfg.lut_address(*entry)


def test_to_mapping_is_the_inverse_of_from_mapping():
    import json
    for cfg in (DPConfig(width=16, height=12),
                DPConfig(width=9, height=7, segment_frames=5, segment_stride=2, radius=2,
                         candidate_count=3, histogram_shift=1, rounding="half_up")):
        values = json.loads(json.dumps(cfg.to_mapping()))   # plain JSON values
        assert DPConfig.from_mapping(values) == cfg


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


def test_non_saturating_energy_bits():
    from dptbd.config import non_saturating_energy_bits
    assert non_saturating_energy_bits(12, 6) == 15          # 6 * 4095 = 24570 < 2**15
    assert non_saturating_energy_bits(8, 1) == 8
    assert DPConfig(width=16, height=12, segment_frames=6, input_bits=12).energy_bits_needed == 15


# ---------------------------------------------------------------------------------------
# run-time segment length: K_max (docs/gateware.md, "Run-time settings")
# ---------------------------------------------------------------------------------------

def test_k_max_defaults_to_k_and_is_left_out_of_the_mapping():
    cfg = DPConfig(segment_frames=6)
    assert cfg.max_segment_frames is None and cfg.k_max == 6
    assert "max_segment_frames" not in cfg.to_mapping()
    wide = DPConfig(segment_frames=6, max_segment_frames=300, energy_bits=17)
    assert wide.k_max == 300 and wide.to_mapping()["max_segment_frames"] == 300
    assert DPConfig.from_mapping(wide.to_mapping()) == wide


def test_k_max_sizes_what_depends_on_k():
    cfg = DPConfig(input_bits=8, energy_bits=20, segment_frames=4, max_segment_frames=64)
    assert cfg.energy_bits_needed == 14                 # bitlen(64 * 255) = 14
    assert cfg.bin_shift == 4                           # 14 - b (10)
    assert DPConfig(input_bits=8, energy_bits=20, segment_frames=4).bin_shift == 0


def test_k_max_warns_when_b_e_saturates_at_k_max():
    with pytest.warns(EnergyWidthWarning, match=whole(
            "energy_bits=12 saturates: K_max=17 full-scale 8-bit pixels sum to 4335 > 4095; "
            "energy_bits >= 13 never saturates")):
        DPConfig(input_bits=8, energy_bits=12, segment_frames=4, max_segment_frames=17)


K_MAX_BAD = [
    *[({"max_segment_frames": v}, not_integer("max_segment_frames", "[segment_frames=4, 65535]", v))
      for v in (3, 0, 65536, 8.0, True, "8")],
    ({"segment_frames": 9, "max_segment_frames": 8},
     "max_segment_frames must be an integer in [segment_frames=9, 65535], got 8"),
]


@pytest.mark.parametrize("overrides, message", K_MAX_BAD, ids=[f"{o}" for o, _ in K_MAX_BAD])
def test_k_max_out_of_range(overrides, message):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        with pytest.raises(ConfigError, match=whole(message)):
            DPConfig(**overrides)


def test_describe_is_the_one_summary_line():
    assert DPConfig().describe() == "128x128, K=4, B_in=8, B_E=16, F=8, r=1, truncate"
    cfg = DPConfig(width=40, height=24, segment_frames=6, input_bits=12, energy_bits=20,
                   weight_frac_bits=3, radius=2, rounding="half_up")
    assert cfg.describe() == "40x24, K=6, B_in=12, B_E=20, F=3, r=2, half_up"


@pytest.mark.parametrize("kw, reach", [
    (dict(segment_frames=2), 9),                          # 2 * 255 = 510: 9 of B_E = 16 bits
    (dict(segment_frames=4, max_segment_frames=6), 11),   # K_max = 6: 1530
    (dict(segment_frames=6, energy_bits=9), 9),           # saturating: all of B_E
    (dict(segment_frames=1, input_bits=12), 12),
    (dict(segment_frames=8, input_bits=12, energy_bits=15), 15),  # exactly the needed width
])
def test_energy_reach_bits_is_the_width_of_the_largest_reachable_energy(kw, reach):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        cfg = DPConfig(**kw)
    assert cfg.energy_reach_bits == reach
    assert cfg.energy_reach_bits == min(cfg.e_max, cfg.k_max * cfg.pixel_max).bit_length()
    assert cfg.build_config().energy_bits == reach          # what dptbd verilog builds


# ---- P pixels per clock ------------------------------------------------------------------
@pytest.mark.parametrize("p", [1, 2, 4])
def test_pixels_per_clock_and_its_beats(p):
    cfg = DPConfig(width=24, height=5, pixels_per_clock=p)
    assert cfg.pixels_per_clock == p
    assert (cfg.row_beats, cfg.frame_beats) == (24 // p, 24 // p * 5)
    beats = cfg.beat_config()
    assert (beats.width, beats.height, beats.pixels_per_clock) == (24 // p, 5, 1)
    assert beats.replace(width=24, pixels_per_clock=p) == cfg.replace(
        candidate_count=None, candidate_capacity=None)
    assert DPConfig.from_mapping(cfg.to_mapping()) == cfg


def test_pixels_per_clock_default_is_one_and_absent_from_the_mapping():
    cfg = DPConfig()
    assert cfg.pixels_per_clock == 1 and cfg.beat_config() is cfg
    assert "pixels_per_clock" not in cfg.to_mapping()
    assert DPConfig(pixels_per_clock=np.int64(2)).to_mapping()["pixels_per_clock"] == 2


def test_beat_config_keeps_an_explicit_candidate_count_out():
    cfg = DPConfig(width=12, height=3, candidate_count=36, pixels_per_clock=4)
    assert cfg.beat_config().candidate_count is None


@pytest.mark.parametrize("overrides, message", [
    (dict(pixels_per_clock=3), "pixels_per_clock must be one of (1, 2, 4), got 3"),
    (dict(pixels_per_clock=8), "pixels_per_clock must be one of (1, 2, 4), got 8"),
    (dict(pixels_per_clock=True), "pixels_per_clock must be one of (1, 2, 4), got True"),
    (dict(pixels_per_clock=2.0), "pixels_per_clock must be one of (1, 2, 4), got 2.0"),
    (dict(width=130, pixels_per_clock=4),
     "width=130 is not a multiple of pixels_per_clock=4: a beat of P pixels never straddles "
     "two rows"),
    (dict(width=7, pixels_per_clock=2),
     "width=7 is not a multiple of pixels_per_clock=2: a beat of P pixels never straddles "
     "two rows"),
    (dict(width=8, pixels_per_clock=4),
     "width=8 is less than 3 * pixels_per_clock = 12: a row needs at least 3 beats of P pixels"),
    (dict(width=4, pixels_per_clock=2),
     "width=4 is less than 3 * pixels_per_clock = 6: a row needs at least 3 beats of P pixels"),
])
def test_pixels_per_clock_refusals(overrides, message):
    with pytest.raises(ConfigError, match=whole(message)):
        DPConfig(**overrides)


def test_describe_names_p_above_one_only():
    assert DPConfig(width=12, pixels_per_clock=4).describe() == \
        "12x128, K=4, B_in=8, B_E=16, F=8, r=1, truncate, P=4"
    assert DPConfig(width=12, pixels_per_clock=1).describe().endswith("truncate")
