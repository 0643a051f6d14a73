"""Target amplitude and SNR: the two papers' definitions.

* **Paper 001 §4** (``../shared/seeds/001_*.txt``): i.i.d. Gaussian noise of mean ``mu``
  and standard deviation ``sigma`` (Table 1: ``mu = 30``, variance 3.0, so
  ``sigma = sqrt(3)``); with ``SNR = (TargetAmp - NoiseAmp) / sigma`` a target pixel is
  ``Noise + SNR * sigma`` and a non-target pixel is ``Noise``. We read "Noise" as the
  *noisy* background sample of that pixel: the target adds ``SNR * sigma`` on top of a
  draw of ``N(mu, sigma**2)``, so its expected value is ``mu + SNR * sigma`` (the
  target level replaces the noise-free background level ``mu``). Amplitude:
  :func:`amplitude_from_snr`.
* **Paper 000 §3 eq (8)** (``../shared/seeds/000_*.txt``): zero-mean noise of standard
  deviation ``sigma`` and ``SNR_dB = 10 lg(A**2 / mean(n**2))``. We use the expected
  noise power ``sigma**2`` for ``mean(n**2)``, so ``A = sigma * 10**(SNR_dB / 20)``
  (:func:`amplitude_from_snr_db`; 4.08 dB gives 000 §5.1's ``A = 1.6``).

Both become a :class:`dptbd.scenes.targets.Target` with an ``amplitude`` added to the noisy
background (:func:`dptbd.scenes.synthetic.make_scene`).
"""

from __future__ import annotations

import math

from dptbd.scenes._checks import SceneError, _check_real

__all__ = [
    "amplitude_from_snr",
    "snr_from_amplitude",
    "amplitude_from_snr_db",
    "snr_db_from_amplitude",
]


def amplitude_from_snr(snr: float, sigma: float) -> float:
    """Paper 001 §4: target amplitude above the background, ``SNR * sigma``.

    ``SNR = (TargetAmp - NoiseAmp) / sigma`` with TargetAmp and NoiseAmp the target and
    noise means.

    Parameters
    ----------
    snr : float
        Linear SNR, finite.
    sigma : float
        Noise standard deviation, > 0.

    Returns
    -------
    float
        The amplitude added to the background.
    """
    return _check_real("snr", snr) * _check_real("sigma", sigma, positive=True)


def snr_from_amplitude(amplitude: float, sigma: float) -> float:
    """Inverse of :func:`amplitude_from_snr`: ``amplitude / sigma``."""
    return _check_real("amplitude", amplitude) / _check_real("sigma", sigma, positive=True)


def amplitude_from_snr_db(snr_db: float, sigma: float) -> float:
    """Paper 000 eq (8): ``SNR_dB = 10 lg(A**2 / mean(n**2))``, so ``A = sigma * 10**(SNR_dB / 20)``.

    ``mean(n**2)`` is taken as the expected power ``sigma**2`` of zero-mean noise, not
    the power of one realised frame.

    Parameters
    ----------
    snr_db : float
        SNR in dB, finite.
    sigma : float
        Noise standard deviation, > 0.

    Returns
    -------
    float
        The target amplitude A (> 0).
    """
    snr_db = _check_real("snr_db", snr_db)
    return _check_real("sigma", sigma, positive=True) * 10.0 ** (snr_db / 20.0)


def snr_db_from_amplitude(amplitude: float, sigma: float) -> float:
    """Inverse of :func:`amplitude_from_snr_db`: ``20 lg(|A| / sigma)``; amplitude must be != 0."""
    amplitude = _check_real("amplitude", amplitude)
    sigma = _check_real("sigma", sigma, positive=True)
    if amplitude == 0.0:
        raise SceneError("amplitude must be non-zero to have an SNR in dB, got 0.0")
    return 20.0 * math.log10(abs(amplitude) / sigma)
