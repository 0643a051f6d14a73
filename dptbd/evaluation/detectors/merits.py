"""Paper 000's merits ``P``: the stage index of the unified recursion (25)-(26)
(:mod:`dptbd.evaluation.detectors.unified`), a function of one cell's measurement.

* :func:`amplitude_merit` — eqs (14)-(15), (24): ``P(z) = z``;
* :func:`likelihood_difference_merit` — eqs (19)-(20): ``P = S(z)``.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Callable

import numpy as np

from dptbd.evaluation.detectors._checks import check_real

__all__ = ["Merit", "amplitude_merit", "likelihood_difference_merit"]


@dataclasses.dataclass(frozen=True)
class Merit:
    """A merit ``P(z)`` of one cell's measurement: the stage index of eq (25)."""

    name: str
    function: Callable[[np.ndarray], np.ndarray]
    params: dict

    def __call__(self, z: np.ndarray) -> np.ndarray:
        return np.asarray(self.function(np.asarray(z, dtype=np.float64)), dtype=np.float64)


def amplitude_merit() -> Merit:
    """Eq (14)-(15), (24): the measured amplitude itself, ``P(z) = z``."""
    return Merit("amplitude", lambda z: z, {})


def likelihood_difference_merit(amplitude: float, epsilon: float, sigma: float,
                                noise_sigma: float = 1.0) -> Merit:
    """Eqs (19)-(20): ``S(z) = exp(-(z - eps a)**2 / (2 sigma**2)) - p(z | H0)``.

    ``p(z | H0)`` is eq (18)'s unit-variance Gaussian density; measurements are divided by
    ``noise_sigma`` first (eq (18) assumes unit noise). Eq (20) states ``0 < eps < 1``
    and ``sigma > 1``; 000 §5.2 runs ``sigma`` (printed ``delta``) = 1, so any
    ``sigma > 0`` is accepted (``docs/detectors.md`` §1.2).

    Parameters
    ----------
    amplitude : float
        The expected target amplitude ``a`` (> 0), in the units of the measurements.
    epsilon : float
        Fraction of ``a`` at which S peaks, in (0, 1) (000 §5.2: 0.85 at 6 dB, 0.55 at 3 dB).
    sigma : float
        Width of the bump, > 0 (in noise standard deviations).
    noise_sigma : float
        Noise standard deviation of the measurements, > 0.
    """
    a = check_real("amplitude (a)", amplitude, 0.0, lo_open=True)
    eps = check_real("epsilon (printed alpha in 000 §5.2)", epsilon, 0.0, 1.0, lo_open=True, hi_open=True)
    sig = check_real("sigma (printed delta in 000 §5.2)", sigma, 0.0, lo_open=True)
    ns = check_real("noise_sigma", noise_sigma, 0.0, lo_open=True)
    centre = eps * a / ns

    def s(z: np.ndarray) -> np.ndarray:
        u = z / ns
        return np.exp(-(u - centre) ** 2 / (2.0 * sig * sig)) - np.exp(-0.5 * u * u) / math.sqrt(2 * math.pi)

    return Merit("likelihood-difference", s,
                 dict(amplitude=a, epsilon=eps, sigma=sig, noise_sigma=ns))
