"""The weight LUTs and the default ADC mapping (:mod:`dptbd.evaluation.compare.luts`)."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.evaluation.compare.luts import adc_mapping, cosine_weights, lut_weights


def test_cosine_lut():
    lut = cosine_weights(1)
    assert lut.shape == (10, 9) and np.all(lut[9] == 1) and np.all(lut[:, 4] == 1)
    assert lut[0, 0] == pytest.approx(1.0) and lut[0, 8] == pytest.approx(0.0)
    assert lut[1, 5] == pytest.approx(0.5) and lut[0, 1] == pytest.approx((1 + 0.5 ** 0.5) / 2)
    assert not DPConfig(weights=lut, weight_frac_bits=8).weights_exact


def test_adc_mapping_puts_the_window_on_the_codes():
    for bits in (3, 8, 12):
        gain, offset = adc_mapping(bits, 30.0, 2.0)
        assert gain * (30.0 - 12.0) + offset == pytest.approx(0.0)           # mu - 6 sigma -> 0
        assert gain * (30.0 + 20.0) + offset == pytest.approx(2 ** bits)     # mu + 10 sigma -> 2**B
        assert gain * 2.0 == pytest.approx(2 ** bits / 16)                   # sigma in LSB


def test_unknown_lut_is_refused():
    with pytest.raises(ConfigError, match=r"^lut must be one of \('paper', 'plain', 'cosine'\) "
                                          r"\(or give 'weights' as a table\), got 'round'$"):
        lut_weights("round", 1)
