"""Test scenes: every scenario fits the configuration's frame and pixel range."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.sim.scenarios import SCENARIOS, make_frames


def small(**kw) -> DPConfig:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**{"width": 8, "height": 6, "segment_frames": 3, **kw})


@pytest.mark.parametrize("name", SCENARIOS)
def test_scenarios_fit_the_configuration(name):
    for cfg in (small(), small(width=13, height=7, input_bits=6, energy_bits=7)):
        frames = make_frames(name, cfg, 5, seed=3)
        assert frames.shape == (5, cfg.height, cfg.width) and frames.dtype == np.uint16
        assert frames.max() <= cfg.pixel_max
    saturating = make_frames("saturating", small(), 5)
    assert (saturating == 255).mean() > 0.1
    assert make_frames("ties", small(), 5).max() == 1
    with pytest.raises(ValueError, match=r"^unknown scenario 'fog'; choose one of table1, "
                                         r"two-targets, noise, mixed, saturating, ties, "
                                         r"edges, random$"):
        make_frames("fog", small(), 3)
