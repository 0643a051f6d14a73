"""Small comparisons shared by the tests of :mod:`dptbd.evaluation.compare`."""

from __future__ import annotations

import pytest


@pytest.fixture
def small_compare() -> dict:
    """A small run as a parsed TOML file: 16 x 16, 12 frames (3 segments of K = 4), 5
    candidates per frame, three configurations, no sweep."""
    return {
        "trials": 6, "seed": 7, "snr": [1.5, 2.5, 3.5], "size": 16, "frames": 12,
        "velocity": [1.0, 0.0], "segment_frames": 4, "false_alarm_rate": 0.02, "chunk": 2,
        "bootstrap": 50, "thresholds": [2.0, 3.0, 4.0],
        "config": [{"name": "eight", "input_bits": 8},
                   {"name": "four", "input_bits": 4, "energy_bits": 5},
                   {"name": "cos", "input_bits": 8, "lut": "cosine", "weight_frac_bits": 2}],
        "sweep": {},
    }


#: A small run with a sweep, as the text of a TOML file.
SMALL_SWEEP_TOML = """
trials = 4
seed = 3
snr = [1.5, 2.5, 3.5]
size = 16
frames = 12
segment_frames = 4
false_alarm_rate = 0.02
chunk = 2
bootstrap = 40
thresholds = [2.0, 3.0, 4.0]
[[config]]
name = "exact-ish"
input_bits = 10
[sweep]
input_bits = [4, 6]
"""


@pytest.fixture
def small_sweep_toml(tmp_path):
    """:data:`SMALL_SWEEP_TOML` written to a file; its path."""
    path = tmp_path / "small.toml"
    path.write_text(SMALL_SWEEP_TOML)
    return path
