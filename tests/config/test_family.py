"""``DPConfig``'s paper-000 family block against ``docs/arithmetic.md`` §8 (table, refusals)."""

from __future__ import annotations


import numpy as np
import pytest

from dptbd import ConfigError, DPConfig
from helpers.refusals import whole

M1 = 9  # moves for r = 1


def zeros_penalty(radius=1, value=0):
    m = (2 * radius + 1) ** 2
    return np.full((m + 1, m), value, dtype=np.int64)


def test_defaults_are_the_paper001_datapath():
    cfg = DPConfig()
    assert cfg.is_paper001_datapath
    assert (cfg.merit_codes, cfg.penalty_codes, cfg.forgetting, cfg.forgetting_bits,
            cfg.recursive) == (None, None, 1.0, 8, False)
    np.testing.assert_array_equal(cfg.merit_code_array, np.arange(256))
    np.testing.assert_array_equal(cfg.penalty_code_array, np.zeros((10, 9)))
    assert (cfg.merit_width, cfg.penalty_width, cfg.forgetting_code) == (9, 1, 256)
    assert (cfg.candidate_value_bits, cfg.accumulator_sum_bits) == (17, 18)


def test_to_mapping_leaves_out_family_defaults_and_round_trips():
    cfg = DPConfig()
    assert not {"merit_codes", "merit_bits", "penalty_codes", "penalty_bits", "forgetting",
                "forgetting_bits", "recursive"} & set(cfg.to_mapping())
    var = DPConfig(input_bits=2, merit_codes=[-3, 0, 1, 5], penalty_codes=zeros_penalty(1, 1),
                   forgetting=0.85, recursive=True)
    mapping = var.to_mapping()
    assert mapping["merit_codes"] == [-3, 0, 1, 5]
    assert mapping["penalty_codes"][0] == [1] * M1
    assert DPConfig.from_mapping(mapping) == var
    assert not var.is_paper001_datapath
    assert var.family_fields_in_use == ["merit_codes", "penalty_codes", "forgetting", "recursive"]


def test_explicit_identity_and_zero_tables_are_the_001_datapath():
    cfg = DPConfig(input_bits=2, merit_codes=[0, 1, 2, 3], penalty_codes=np.zeros((10, 9), int),
                   forgetting=0.999, forgetting_bits=4)
    assert cfg.forgetting_code == 16 and cfg.is_paper001_datapath
    assert cfg != DPConfig(input_bits=2)  # a different configuration all the same


@pytest.mark.parametrize("alpha, bits, code", [
    (1.0, 8, 256), (0.85, 8, 218), (0.85, 4, 14), (0.55, 4, 9), (0.5, 0, 1), (1.0, 0, 1),
    (0.03125, 4, 1), (0.75, 2, 3)])
def test_forgetting_code_rounds_half_up(alpha, bits, code):
    assert DPConfig(forgetting=alpha, forgetting_bits=bits).forgetting_code == code


def test_widths_follow_the_codes():
    cfg = DPConfig(input_bits=2, merit_codes=[-3, 0, 1, 5], penalty_codes=zeros_penalty(1, 5))
    assert (cfg.merit_width, cfg.penalty_width) == (4, 3)
    assert (cfg.candidate_value_bits, cfg.accumulator_sum_bits) == (17, 18)
    assert DPConfig(input_bits=2, merit_codes=[-4, 0, 0, 3]).merit_width == 3
    assert DPConfig(input_bits=2, merit_codes=[0, 0, 0, 0]).merit_width == 2
    wide = DPConfig(input_bits=2, energy_bits=4, merit_codes=[0, 0, 0, 0], merit_bits=5)
    assert wide.merit_width == 5 and wide.accumulator_sum_bits == 6


def test_merit_codes_are_frozen_tuples_and_hashable():
    cfg = DPConfig(input_bits=1, merit_codes=np.array([2, -1]))
    assert cfg.merit_codes == (2, -1)
    assert hash(cfg) == hash(DPConfig(input_bits=1, merit_codes=[2, -1]))


@pytest.mark.parametrize("kwargs, message", [
    (dict(forgetting=0), "forgetting must be a finite real number in (0, 1], got 0"),
    (dict(forgetting=1.5), "forgetting must be a finite real number in (0, 1], got 1.5"),
    (dict(forgetting=-0.5), "forgetting must be a finite real number in (0, 1], got -0.5"),
    (dict(forgetting=float("nan")), "forgetting must be a finite real number in (0, 1], got nan"),
    (dict(forgetting="0.5"), "forgetting must be a finite real number in (0, 1], got '0.5'"),
    (dict(forgetting=0.01, forgetting_bits=4),
     "forgetting must be a finite real number in [0.03125, 1] for forgetting_bits=4 "
     "(its code round(forgetting * 2**4) must be >= 1), got 0.01"),
    (dict(forgetting_bits=17), "forgetting_bits must be an integer in [0, 16], got 17"),
    (dict(forgetting_bits=-1), "forgetting_bits must be an integer in [0, 16], got -1"),
    (dict(recursive=1), "recursive must be true or false, got 1"),
    (dict(recursive=True, segment_frames=6, segment_stride=4),
     "segment_stride must be segment_frames=6 when recursive=True (one state that never "
     "resets), got 4"),
    (dict(merit_bits=8), "merit_bits must be an integer in [input_bits+1=9, energy_bits+1=17], got 8"),
    (dict(merit_bits=18), "merit_bits must be an integer in [input_bits+1=9, energy_bits+1=17], got 18"),
    (dict(input_bits=2, merit_codes=[0, 1, 2, 3], merit_bits=1),
     "merit_bits must be an integer in [2, energy_bits+1=17], got 1"),
    (dict(input_bits=2, merit_codes=[0, 1, 2, 300], merit_bits=8),
     "merit_codes must be integers in [-128, 127] for merit_bits=8, found [300]"),
    (dict(input_bits=2, merit_codes=[-129, 1, 2, 3], merit_bits=8),
     "merit_codes must be integers in [-128, 127] for merit_bits=8, found [-129]"),
    (dict(input_bits=2, energy_bits=4, merit_codes=[0, 1, 2, 300]),
     "merit_bits must be an integer in [2, energy_bits+1=5], got 10"),
    (dict(input_bits=2, merit_codes=[0, 1, 2]), "merit_codes must have shape (4,), got (3,)"),
    (dict(input_bits=2, merit_codes=[0.5, 1, 2, 3]), "merit_codes must hold integers, got dtype float64"),
    (dict(input_bits=1, merit_codes=[True, False]), "merit_codes must hold integers, got dtype bool"),
    (dict(penalty_bits=0), "penalty_bits must be an integer in [1, energy_bits=16], got 0"),
    (dict(penalty_bits=17), "penalty_bits must be an integer in [1, energy_bits=16], got 17"),
    (dict(penalty_codes=zeros_penalty(1, 8), penalty_bits=3),
     "penalty_codes must be integers in [0, 7] for penalty_bits=3, found [8, 8, 8]"),
    (dict(penalty_codes=zeros_penalty(1, -1)),
     "penalty_codes must be integers in [0, 1] for penalty_bits=1, found [-1, -1, -1]"),
    (dict(penalty_codes=zeros_penalty(2)), "penalty_codes must have shape (10, 9), got (26, 25)"),
    (dict(energy_bits=8, penalty_codes=zeros_penalty(1, 256)),
     "penalty_bits must be an integer in [1, energy_bits=8], got 9"),
])
def test_refusals(kwargs, message):
    with pytest.raises(ConfigError, match=whole(message)):
        DPConfig(**kwargs)


def test_replace_keeps_the_family():
    cfg = DPConfig(forgetting=0.5, recursive=True)
    other = cfg.replace(segment_frames=8)
    assert (other.forgetting, other.recursive, other.segment_stride) == (0.5, True, 8)
