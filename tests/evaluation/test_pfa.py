"""Equal Pfa per pixel: the threshold calibrated on noise-only scenes named by seed."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.evaluation.pfa import (PfaError, calibrate_pixel_threshold, check_pfa, parse_pfas,
                                  pixel_threshold)
from helpers.refusals import whole


def _scene(seed: int) -> np.ndarray:
    """Noise-only "maps" of seed s: a permutation of s*1000 .. s*1000 + 999 (known quantiles)."""
    return np.random.default_rng(seed).permutation(np.arange(seed * 1000, seed * 1000 + 1000)
                                                   ).reshape(10, 10, 10).astype(np.float64)


def test_pixel_threshold_is_the_exact_quantile():
    values = np.random.default_rng(3).permutation(10_000).astype(float)
    # n = floor(1e-3 * 10000) = 10: the 11th largest, 9989; exactly 10 values above it
    assert pixel_threshold(values, 1e-3) == 9989.0
    assert np.count_nonzero(values > 9989.0) == 10
    assert pixel_threshold(values, 1e-4) == 9998.0  # n = 1
    assert pixel_threshold(values.reshape(100, 100), 0.5) == 4999.0


def test_pixel_threshold_ties_keep_at_most_the_rate():
    values = np.array([0.0] * 90 + [5.0] * 10)  # n = 5 of 100, but 10 tie at 5
    thr = pixel_threshold(values, 0.05)
    assert thr == 5.0 and np.count_nonzero(values > thr) == 0


def test_calibration_on_seeded_scenes_is_the_known_quantile_and_reproducible():
    cal = calibrate_pixel_threshold(_scene, [0, 1, 2, 3], 1e-3)
    # values 0 .. 3999, n = 4: the 5th largest is 3995; 4 pixels above
    assert (cal.threshold, cal.pixels, cal.above, cal.seeds) == (3995.0, 4000, 4, (0, 1, 2, 3))
    assert cal.measured_pfa == 1e-3
    assert cal == calibrate_pixel_threshold(_scene, [0, 1, 2, 3], 1e-3)
    assert cal.threshold_for(0.01) == 3959.0


@pytest.mark.parametrize("value, message", [
    (0.0, "pfa (false-alarm probability per pixel) must be a finite real number in (0, 1), got 0.0"),
    (1.0, "pfa (false-alarm probability per pixel) must be a finite real number in (0, 1), got 1.0"),
    (-1e-3, "pfa (false-alarm probability per pixel) must be a finite real number in (0, 1), got -0.001"),
    (float("nan"), "pfa (false-alarm probability per pixel) must be a finite real number in (0, 1), got nan"),
    ("0.1", "pfa (false-alarm probability per pixel) must be a finite real number in (0, 1), got '0.1'"),
])
def test_pfa_outside_the_open_unit_interval_is_refused(value, message):
    with pytest.raises(PfaError, match=whole(message)):
        check_pfa(value)
    with pytest.raises(PfaError, match=whole(message)):
        pixel_threshold(np.arange(100.0), value)


@pytest.mark.parametrize("call, message", [
    (lambda: pixel_threshold(np.arange(999.0), 1e-3),
     "pfa=0.001 needs at least 1000 noise-only pixels, got 999; add noise-only scenes or raise pfa"),
    (lambda: calibrate_pixel_threshold(_scene, [], 0.01),
     "seeds must name at least one noise-only scene"),
    (lambda: calibrate_pixel_threshold(_scene, [1, 1], 0.01), "seeds must be distinct, got [1, 1]"),
    (lambda: calibrate_pixel_threshold(_scene, [-1], 0.01),
     "seed (noise-only scene) must be an integer in [0, inf), got -1"),
    (lambda: calibrate_pixel_threshold(_scene, [0], 1e-4),
     "pfa=0.0001 needs at least 10000 noise-only pixels, got 1000; add noise-only scenes or raise pfa"),
    (lambda: parse_pfas("1e-3,x"), "pfa must be comma-separated numbers in (0, 1), got '1e-3,x'"),
    (lambda: parse_pfas(""), "pfa must hold at least one false-alarm probability in (0, 1)"),
    (lambda: parse_pfas("1e-3,2"),
     "pfa (false-alarm probability per pixel) must be a finite real number in (0, 1), got 2.0"),
])
def test_calibration_refusals(call, message):
    with pytest.raises(PfaError, match=whole(message)):
        call()


def test_parse_pfas():
    assert parse_pfas("1e-3, 1e-4") == (1e-3, 1e-4)
    assert parse_pfas([0.01]) == (0.01,)


def test_calibration_keeps_integer_maps_and_counts_above():
    cal = calibrate_pixel_threshold(lambda s: np.arange(1000, dtype=np.uint32) + s, [0], 0.01)
    assert cal.values.dtype == np.uint32 and cal.threshold == 989.0
    assert (cal.count_above(989.0), cal.count_above(989.5), cal.count_above(-1)) == (10, 10, 1000)


def test_figure_roc_writes_a_png(tmp_path):
    from dptbd.evaluation.pfa import figure_roc

    path = figure_roc({"a": [(1e-3, 0.5, 0.4, 0.6), (1e-4, float("nan"), float("nan"), float("nan"))],
                       "b": [(1e-3, 0.9, 0.8, 1.0)]}, tmp_path / "roc.png", title="t")
    assert path.read_bytes()[:4] == b"\x89PNG"
