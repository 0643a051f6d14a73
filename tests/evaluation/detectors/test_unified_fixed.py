"""The integer form of paper 000's unified recursion on paper 001's datapath: against paper
001's golden model, against the float recursion, bad input."""

from __future__ import annotations


import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.merits import amplitude_merit, likelihood_difference_merit
from dptbd.evaluation.detectors.transitions import no_penalty, velocity_log_penalty
from dptbd.evaluation.detectors.unified import run_unified
from dptbd.evaluation.detectors.unified_fixed import quantise_unified, run_unified_fixed
from dptbd.model.fixed import run_fixed
from dptbd.weights import plain_weights
from helpers.refusals import whole

def test_fixed_point_with_plain_lut_is_paper001_plain_dp():
    rng = np.random.default_rng(1)
    x = rng.integers(0, 256, size=(2, 6, 9, 11)).astype(np.uint16)
    cfg = DPConfig(width=11, height=9, segment_frames=6, radius=2, weights=plain_weights(2))
    golden = run_fixed(x, cfg)
    luts = quantise_unified(amplitude_merit(), no_penalty(2), radius=2, input_bits=8)
    e, d = run_unified_fixed(x, luts)
    assert np.array_equal(e, golden.energy[:, 0]) and np.array_equal(d, golden.direction[:, 0])


def test_fixed_point_equals_float_plus_bias_for_integer_luts():
    rng = np.random.default_rng(2)
    x = rng.integers(0, 256, size=(3, 5, 7, 8)).astype(np.uint16)
    q = -rng.integers(0, 4, size=(26, 25)).astype(float)
    luts = quantise_unified(amplitude_merit(), q, radius=2, input_bits=8, energy_bits=16)
    assert luts.merit_codes.min() >= luts.penalty_codes.max()  # candidates never negative
    e, d = run_unified_fixed(x, luts)
    ref = run_unified(x.astype(float), amplitude_merit(), q, radius=2)
    assert np.array_equal(luts.to_float(e, 5), ref.value)
    assert np.array_equal(d, ref.direction)
    v_t = float(np.median(ref.value))
    assert np.array_equal(e > luts.threshold_code(v_t, 5), ref.value > v_t)


def test_fixed_point_likelihood_lut_tracks_the_float_recursion():
    rng = np.random.default_rng(3)
    z = rng.normal(size=(8, 10, 10))
    z[:, 5, 5] += 2.0
    merit, q = likelihood_difference_merit(2.0, 0.85, 1.0), velocity_log_penalty(2, 1.0)
    gain, offset = 16.0, 128.0
    codes = np.clip(np.rint(z * gain + offset), 0, 255).astype(np.uint16)
    luts = quantise_unified(merit, q, radius=2, input_bits=8, gain=gain, offset=offset, scale=256.0)
    e, _ = run_unified_fixed(codes, luts)
    ref = run_unified((codes - offset) / gain, merit, q, radius=2).value
    # 8 frames of merit and penalty rounding, 1/512 each at most
    assert np.max(np.abs(luts.to_float(e, 8) - ref)) <= 16 / 512 + 1e-9


@pytest.mark.parametrize("call, message", [
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2), input_bits=17),
     "input_bits must be an integer in [1, 16], got 17"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2), gain=0.0),
     "gain must be a finite real number in (0, inf), got 0.0"),
    (lambda: run_unified_fixed(np.full((2, 3, 3), 256), quantise_unified(amplitude_merit(), no_penalty(2))),
     "codes must be in [0, 255] for input_bits=8, found [256, 256]"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2)).threshold_code(float("nan"), 5),
     "v_t (threshold V_T) must be a finite real number in (-inf, inf), got nan"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2)).threshold_code(float("inf"), 5),
     "v_t (threshold V_T) must be a finite real number in (-inf, inf), got inf"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2)).threshold_code("30", 5),
     "v_t (threshold V_T) must be a finite real number in (-inf, inf), got '30'"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2)).threshold_code(30.0, 0),
     "n_frames must be an integer in [1, inf), got 0"),
    (lambda: quantise_unified(amplitude_merit(), no_penalty(2)).to_float(np.zeros(3), 0),
     "n_frames must be an integer in [1, inf), got 0"),
])
def test_bad_input_names_the_parameter(call, message):
    with pytest.raises(DetectorError, match=whole(message)):
        call()
