"""``dptbd.config.segmentation``: the segmentation parameters (``docs/arithmetic.md`` §6)."""

from __future__ import annotations

import math
import warnings
from fractions import Fraction

import pytest

from dptbd import ConfigError, DPConfig, EnergyWidthWarning
from helpers.refusals import not_integer, whole


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
