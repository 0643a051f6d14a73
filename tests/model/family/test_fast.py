"""``dptbd.model.family.fast`` equals ``dptbd.model.family`` bit for bit (§8)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from dptbd.config import DPConfig
from dptbd.model.family import family_step, run_family_fixed
from dptbd.model.family.fast import fast_family_step, run_family_fast
from helpers.family_strategies import family_configs, family_frames
from helpers.model_strategies import SETTINGS

pytestmark = pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")


@SETTINGS
@given(data=st.data())
def test_fast_equals_the_model_on_random_configurations(data):
    cfg = data.draw(family_configs())
    frames = family_frames(data.draw, cfg)
    want, got = run_family_fixed(frames, cfg), run_family_fast(frames, cfg)
    np.testing.assert_array_equal(got.energy, want.energy)
    np.testing.assert_array_equal(got.direction, want.direction)
    assert got.energy.dtype == want.energy.dtype and got.direction.dtype == want.direction.dtype


def test_fast_step_reads_corrupted_directions_like_the_model():
    rng = np.random.default_rng(1)
    cfg = DPConfig(width=6, height=5, penalty_codes=rng.integers(0, 30, (10, 9)), forgetting=0.6)
    energy = rng.integers(0, 500, (2, 5, 6)).astype(np.uint32)
    direction = rng.integers(0, 16, (2, 5, 6)).astype(np.uint8)  # codes above START = 9
    pixels = rng.integers(0, 256, (2, 5, 6))
    for got, want in zip(fast_family_step(energy, direction, pixels, cfg),
                         family_step(energy, direction, pixels, cfg)):
        np.testing.assert_array_equal(got, want)


def test_fast_on_a_full_size_recursive_scene():
    rng = np.random.default_rng(2)
    cfg = DPConfig(radius=2, recursive=True, forgetting=0.85, rounding="half_up",
                   penalty_codes=rng.integers(0, 200, (26, 25)), merit_codes=rng.integers(-300, 300, 256))
    frames = rng.integers(0, 256, (6, 128, 128))
    want, got = run_family_fixed(frames, cfg), run_family_fast(frames, cfg)
    np.testing.assert_array_equal(got.energy, want.energy)
    np.testing.assert_array_equal(got.direction, want.direction)
