"""Which §8 blocks the gateware builds for a configuration, and the forgetting leaves."""

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.family_blocks import FamilyBlocks, forgetting_leaves


@pytest.mark.parametrize("fields, built", [
    ({}, ()),
    (dict(merit_codes=np.arange(256), penalty_codes=np.zeros((10, 9), int), forgetting=1.0),
     ()),                                                   # explicit defaults: nothing
    (dict(merit_codes=np.arange(256) - 1), ("merit_lut", "clamped_accumulator")),
    (dict(penalty_codes=np.ones((10, 9), int)), ("penalty_lut", "clamped_accumulator")),
    (dict(forgetting=0.5), ("forgetting", "clamped_accumulator")),
    (dict(recursive=True), ("recursive", "clamped_accumulator")),
])
def test_blocks_follow_the_fields_in_use(fields, built):
    blocks = FamilyBlocks.from_config(DPConfig(**fields))
    names = ("merit_lut", "penalty_lut", "forgetting", "clamped_accumulator", "recursive")
    assert {n for n in names if getattr(blocks, n)} == set(built)
    assert blocks.signed_candidates == blocks.penalty_lut


@pytest.mark.parametrize("alpha, bits, rounding, leaves", [
    (0.85, 8, "truncate", [1, 3, 4, 6, 7]),     # a = 218 = 0b11011010
    (0.85, 8, "half_up", [1, 3, 4, 6, 7, -1]),  # plus the rounding constant
    (0.5, 4, "half_up", [3, -1]),
    (2 ** -16, 16, "half_up", [0, -1]),
    (0.5, 1, "truncate", [0]),
])
def test_forgetting_leaves(alpha, bits, rounding, leaves):
    cfg = DPConfig(forgetting=alpha, forgetting_bits=bits, rounding=rounding)
    assert forgetting_leaves(cfg) == leaves
