"""``dptbd.config.DPConfig`` against ``docs/arithmetic.md`` (parameter table, §2, §3, §5)."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from dptbd import ConfigError, DPConfig, EnergyWidthWarning
from dptbd.config import ROUNDING_MODES
from dptbd.weights import paper_weights, plain_weights
from dptbd.errors import DptbdError
from helpers.luts import lut_with
from helpers.refusals import not_integer, whole


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


# ---- derived quantities: one home ------------------------------------------------------------

def test_state_bits_and_lut_entries():
    cfg = DPConfig(width=16, height=12, segment_frames=3, energy_bits=12, radius=2)
    assert cfg.state_bits == 12 + 5            # B_d = bitlen(25)
    assert cfg.lut_entries == 26 * 25


def test_to_mapping_is_the_inverse_of_from_mapping():
    import json
    for cfg in (DPConfig(width=16, height=12),
                DPConfig(width=9, height=7, segment_frames=5, segment_stride=2, radius=2,
                         candidate_count=3, histogram_shift=1, rounding="half_up")):
        values = json.loads(json.dumps(cfg.to_mapping()))   # plain JSON values
        assert DPConfig.from_mapping(values) == cfg


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


def test_describe_names_p_above_one_only():
    assert DPConfig(width=12, pixels_per_clock=4).describe() == \
        "12x128, K=4, B_in=8, B_E=16, F=8, r=1, truncate, P=4"
    assert DPConfig(width=12, pixels_per_clock=1).describe().endswith("truncate")
