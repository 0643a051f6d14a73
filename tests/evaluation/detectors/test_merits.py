"""Paper 000's merits P: eqs (19)-(20) by hand, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.evaluation.detectors import DetectorError
from dptbd.evaluation.detectors.merits import likelihood_difference_merit
from helpers.refusals import whole

def test_likelihood_difference_by_hand():
    s = likelihood_difference_merit(amplitude=2.0, epsilon=0.85, sigma=1.0)
    z = np.array([0.0, 1.7, 3.0])
    expect = np.exp(-(z - 1.7) ** 2 / 2) - np.exp(-z ** 2 / 2) / math.sqrt(2 * math.pi)
    assert np.allclose(s(z), expect)
    assert math.isclose(float(s(np.array(1.7))), 1 - math.exp(-1.7 ** 2 / 2) / math.sqrt(2 * math.pi))
    # noise_sigma rescales the measurements
    s2 = likelihood_difference_merit(amplitude=4.0, epsilon=0.85, sigma=1.0, noise_sigma=2.0)
    assert np.allclose(s2(2 * z), expect)


@pytest.mark.parametrize("call, message", [
    (lambda: likelihood_difference_merit(2.0, epsilon=1.0, sigma=1.0),
     "epsilon (printed alpha in 000 §5.2) must be a finite real number in (0, 1), got 1.0"),
    (lambda: likelihood_difference_merit(2.0, epsilon=0.0, sigma=1.0),
     "epsilon (printed alpha in 000 §5.2) must be a finite real number in (0, 1), got 0.0"),
    (lambda: likelihood_difference_merit(2.0, epsilon=0.5, sigma=0.0),
     "sigma (printed delta in 000 §5.2) must be a finite real number in (0, inf), got 0.0"),
    (lambda: likelihood_difference_merit(0.0, epsilon=0.5, sigma=1.0),
     "amplitude (a) must be a finite real number in (0, inf), got 0.0"),
    (lambda: likelihood_difference_merit(2.0, 0.5, 1.0, noise_sigma=float("nan")),
     "noise_sigma must be a finite real number in (0, inf), got nan"),
])
def test_bad_input_names_the_parameter(call, message):
    with pytest.raises(DetectorError, match=whole(message)):
        call()
