"""``dptbd.config.beats``: P pixels per clock and the configuration in beats."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd import ConfigError, DPConfig
from helpers.refusals import whole


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
