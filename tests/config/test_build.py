"""``DPConfig.build_config``: the narrowed gateware build computes the same bits.

The build narrows B_E to ``energy_bits_needed`` and, for a binary LUT, F to 0
(``docs/synthesis.md``, "Build defaults"). The golden model run with the build
configuration must give the same accumulated images, direction maps and candidate lists as
with the configuration asked for, on scenes that reach full scale.
"""

import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.weights import paper_weights, plain_weights
from dptbd.model.fixed import run_fixed
from dptbd.model.segmentation import segment_sequence


def _scenes(cfg: DPConfig, seed: int) -> np.ndarray:
    """Three trials of 3K frames: uniform noise with full-scale pixels mixed in, and one
    trial at full scale everywhere (E reaches K * pixel_max, the bound B_E is narrowed to)."""
    rng = np.random.default_rng(seed)
    shape = (3, 3 * cfg.segment_frames, cfg.height, cfg.width)
    frames = rng.integers(0, cfg.pixel_max + 1, size=shape)
    frames[0][rng.random(shape[1:]) < 0.2] = cfg.pixel_max
    frames[2] = cfg.pixel_max
    return frames.astype(np.uint16)


def _same_outputs(a: DPConfig, b: DPConfig, seed: int) -> None:
    frames = _scenes(a, seed)
    out_a, out_b = run_fixed(frames, a), run_fixed(frames, b)
    np.testing.assert_array_equal(out_a.energy, out_b.energy)
    np.testing.assert_array_equal(out_a.direction, out_b.direction)
    for trial in range(frames.shape[0]):
        lists_a = segment_sequence(out_a.energy[trial], out_a.direction[trial], a)
        lists_b = segment_sequence(out_b.energy[trial], out_b.direction[trial], b)
        for la, lb in zip(lists_a, lists_b, strict=True):
            np.testing.assert_array_equal(la.records, lb.records)
            assert (la.threshold, la.overflow, la.primed) == (lb.threshold, lb.overflow, lb.primed)
            np.testing.assert_array_equal(la.histogram, lb.histogram)


def test_default_build_is_8_10_0():
    cfg = DPConfig()
    build = cfg.build_config()
    assert (build.input_bits, build.energy_bits, build.weight_frac_bits) == (8, 10, 0)
    assert cfg.weights_binary and build.weights_binary
    frac = cfg.build_config(fractional_lut=True)
    assert (frac.energy_bits, frac.weight_frac_bits) == (10, 8)
    assert build.build_config() is build


@pytest.mark.parametrize("changes", [
    {},                                                          # paper LUT, truncate
    {"rounding": "half_up", "segment_frames": 3, "input_bits": 6},
    {"weights": tuple(map(tuple, plain_weights(1)))},            # all ones
    {"histogram_bits": 4},                                       # coarser bins (s > 0)
])
def test_binary_build_computes_the_same_bits(changes):
    cfg = DPConfig(width=12, height=10, candidate_count=6, **changes)
    build = cfg.build_config()
    assert build.weight_frac_bits == 0 and build.energy_bits == cfg.energy_bits_needed
    _same_outputs(cfg, build, seed=len(changes))


def test_fractional_lut_keeps_f_and_narrows_b_e():
    weights = paper_weights(1) * 0.75
    cfg = DPConfig(width=12, height=10, candidate_count=6, weights=tuple(map(tuple, weights)))
    assert not cfg.weights_binary
    build = cfg.build_config()
    assert (build.energy_bits, build.weight_frac_bits) == (cfg.energy_bits_needed, 8)
    _same_outputs(cfg, build, seed=7)


def test_what_is_not_narrowed():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        saturating = DPConfig(energy_bits=9)            # below the 10 bits K = 4 needs
        assert saturating.build_config().energy_bits == 9
    shifted = DPConfig(histogram_shift=12)              # an explicit s keeps B_E > s
    assert shifted.build_config().energy_bits == 13
