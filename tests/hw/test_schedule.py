"""Pipeline schedule (latency formula) and the configurations the gateware refuses."""

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.schedule import PipelineSchedule, check_supported, read_ahead_distance


@pytest.mark.parametrize("radius, frac, latency", [
    (1, 8, 14),   # 6 + ceil(log2(10)) + ceil(log2(9))
    (2, 8, 15),   # 6 + 4 + ceil(log2(25))
    (1, 0, 11),   # 7 + 4: F = 0 has a single multiplier register
    (1, 1, 12),   # 6 + ceil(log2(3)) + 4
    (1, 2, 12),   # 6 + ceil(log2(4)) + 4
    (1, 3, 13),   # 6 + ceil(log2(5)) + 4
    (1, 16, 15),  # 6 + ceil(log2(18)) + 4
])
def test_latency_formula(radius, frac, latency):
    cfg = DPConfig(radius=radius, weight_frac_bits=frac)
    schedule = PipelineSchedule.from_config(cfg)
    assert schedule.latency == latency
    assert schedule.write_latency == schedule.state == latency - 2
    assert schedule.weighted == schedule.code + schedule.multiplier_levels
    assert schedule.best == schedule.weighted + schedule.tree_levels


@pytest.mark.parametrize("radius, frac, latency", [(1, 8, 18), (2, 8, 20), (1, 0, 15)])
def test_split_max_tree_adds_one_stage_per_level(radius, frac, latency):
    """``max_tree="split"`` (SplitMaxTree): ceil(log2 M) more cycles (4 for M = 9, 5 for
    M = 25), everything after the tree moves with it."""
    cfg = DPConfig(radius=radius, weight_frac_bits=frac)
    compact = PipelineSchedule.from_config(cfg)
    split = PipelineSchedule.from_config(cfg, max_tree="split")
    assert split.latency == latency == compact.latency + compact.tree_levels
    assert split.tree_levels == 2 * compact.tree_levels
    assert split.best == split.weighted + split.tree_levels and split.state == split.best + 1
    assert check_supported(cfg, max_tree="split") == split


def test_unknown_max_tree_is_refused():
    with pytest.raises(ValueError, match=r"^max_tree must be one of \('compact', 'split'\), "
                                         r"got 'fast'$"):
        PipelineSchedule.from_config(DPConfig(), max_tree="fast")


def test_latency_does_not_depend_on_rounding_or_widths():
    a = PipelineSchedule.from_config(DPConfig(rounding="truncate", energy_bits=10))
    b = PipelineSchedule.from_config(DPConfig(rounding="half_up", energy_bits=32))
    assert a == b


def test_overlapping_segments_are_refused():
    with pytest.raises(ConfigError,
                       match=r"^segment_stride=2 is not supported by the gateware: "
                             r"only non-overlapping segments "
                             r"\(segment_stride == segment_frames == 4\) "
                             r"are implemented, with a single state store$"):
        check_supported(DPConfig(segment_frames=4, segment_stride=2))


def test_frame_too_small_for_read_ahead_is_refused():
    # 5 x 4 with r = 2: 20 - 2 * 6 = 8 <= write latency 13.
    cfg = DPConfig(width=5, height=4, radius=2)
    assert read_ahead_distance(cfg) == 12
    with pytest.raises(ConfigError,
                       match=r"^width=5 x height=4 is too small for the read-ahead of radius=2: "
                             r"the gateware needs width\*height - radius\*\(width\+1\) > write latency 13 "
                             r"cycles, but it is 8; each state must be written before the next frame reads "
                             r"it; use a larger frame$"):
        check_supported(cfg)


def test_smallest_accepted_frames():
    # r = 1, write latency 12: W*H - (W+1) must exceed 12.
    check_supported(DPConfig(width=5, height=4))          # 20 - 6 = 14
    check_supported(DPConfig(width=3, height=8))          # 24 - 4 = 20
    with pytest.raises(ConfigError):
        check_supported(DPConfig(width=3, height=5))      # 15 - 4 = 11
    check_supported(DPConfig(width=7, height=6, radius=2))  # 42 - 16 = 26 > 13


def test_paper000_family_is_accepted_except_a_merit_lut_beyond_12_input_bits():
    check_supported(DPConfig(width=16, height=16, recursive=True))
    check_supported(DPConfig(width=16, height=16, input_bits=12, energy_bits=16,
                             merit_codes=np.arange(4096) - 2048))
    cfg = DPConfig(width=16, height=16, input_bits=13, energy_bits=16,
                   merit_codes=np.arange(8192) - 4096)
    with pytest.raises(ConfigError, match=(
            r"^input_bits must be an integer in \[1, 12\] for the gateware's merit LUT "
            r"\(merit_codes other than the identity: a 2\*\*input_bits-entry table in block "
            r"RAM\), got 13$")):
        check_supported(cfg)
    # the identity merit builds no LUT: any input_bits
    check_supported(DPConfig(width=16, height=16, input_bits=16, energy_bits=20, recursive=True))


@pytest.mark.parametrize("fields, penalty_levels, forgetting_levels", [
    (dict(recursive=True), 0, 0),
    (dict(merit_codes=np.arange(256) - 8), 0, 0),
    (dict(penalty_codes=np.ones((10, 9), int)), 1, 0),
    (dict(forgetting=0.85), 0, 3),                             # a = 218: 5 set bits
    (dict(forgetting=0.85, rounding="half_up"), 0, 3),         # 5 set bits + rounding
    (dict(forgetting=0.5, forgetting_bits=4), 0, 1),           # a = 8: one leaf, one level
    (dict(forgetting=0.75, forgetting_bits=2, rounding="half_up"), 0, 2),  # 2 bits + rounding
    (dict(forgetting=0.55, penalty_codes=np.ones((10, 9), int)), 1, 2),   # a = 141: 4 bits
])
def test_family_stages(fields, penalty_levels, forgetting_levels):
    """The §8 stages: latency = 14 (r = 1, F = 8) + penalty_levels + forgetting_levels."""
    schedule = PipelineSchedule.from_config(DPConfig(**fields))
    assert (schedule.penalty_levels, schedule.forgetting_levels) == (penalty_levels,
                                                                      forgetting_levels)
    assert schedule.penalised == schedule.weighted + penalty_levels
    assert schedule.best == schedule.penalised + schedule.tree_levels
    assert schedule.faded == schedule.best + forgetting_levels
    assert schedule.state == schedule.faded + 1
    assert schedule.latency == 14 + penalty_levels + forgetting_levels
