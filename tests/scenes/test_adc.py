"""ADC quantisation of ``dptbd.scenes.adc``: float frames to unsigned integer codes."""

from __future__ import annotations


import numpy as np
import pytest

from dptbd.scenes import SceneError
from dptbd.scenes.adc import quantise
from helpers.refusals import whole


def test_quantise_rounds_and_clips():
    x = np.array([-3.0, -0.4, 0.4, 0.6, 1.5, 2.5, 254.4, 254.6, 300.0])
    q = quantise(x, 8)
    assert q.dtype == np.uint16
    assert q.tolist() == [0, 0, 0, 1, 2, 2, 254, 255, 255]
    assert quantise(np.array([70000.0]), 16).tolist() == [65535]
    assert quantise(np.array([0.6, 1.4, 5.0]), 1).tolist() == [1, 1, 1]


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_quantise_refuses_non_finite(bad):
    with pytest.raises(SceneError, match=whole("frames must be finite: found NaN or inf")):
        quantise(np.array([1.0, bad]), 8)


@pytest.mark.parametrize("bits", [0, 17, -1, 8.0, True])
def test_quantise_refuses_bad_bits(bits):
    with pytest.raises(SceneError, match=whole(f"input_bits must be an integer in [1, 16], got {bits!r}")):
        quantise(np.zeros(3), bits)


def test_quantise_refuses_bad_frames():
    with pytest.raises(SceneError, match=whole("frames must be a real numeric array, got dtype <U1")):
        quantise(np.array(["a"]), 8)
    with pytest.raises(SceneError, match=whole("gain must be a finite real number in (-inf, inf), got nan")):
        quantise(np.zeros(2), 8, gain=np.nan)
