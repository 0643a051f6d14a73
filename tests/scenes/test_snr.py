"""Amplitude and SNR conversions of ``dptbd.scenes.snr``: papers 001 §4 and 000 eq (8)."""

from __future__ import annotations


import numpy as np
import pytest

from dptbd.scenes import SceneError
from dptbd.scenes.snr import amplitude_from_snr, amplitude_from_snr_db, snr_db_from_amplitude
from helpers.refusals import whole


def test_amplitude_from_snr_db_paper000():
    assert amplitude_from_snr_db(4.08, 1.0) == pytest.approx(1.6, abs=1e-3)
    assert amplitude_from_snr_db(6.0, 1.0) == pytest.approx(2.0, abs=0.01)  # 000 §5.2
    assert amplitude_from_snr_db(0.0, 2.5) == 2.5
    assert snr_db_from_amplitude(amplitude_from_snr_db(3.3, 1.7), 1.7) == pytest.approx(3.3)
    with pytest.raises(SceneError, match=whole("amplitude must be non-zero to have an SNR in dB, got 0.0")):
        snr_db_from_amplitude(0.0, 1.0)


def test_snr_helpers_refuse_bad_parameters():
    with pytest.raises(SceneError, match=whole("sigma must be a finite real number in (0, inf), got 0.0")):
        amplitude_from_snr_db(4.0, 0.0)
    with pytest.raises(SceneError, match=whole(
            "snr_db must be a finite real number in (-inf, inf), got nan")):
        amplitude_from_snr_db(np.nan, 1.0)
    with pytest.raises(SceneError, match=whole("snr must be a finite real number in (-inf, inf), got inf")):
        amplitude_from_snr(np.inf, 1.0)
