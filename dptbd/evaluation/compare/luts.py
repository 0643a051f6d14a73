"""The weight LUTs a comparison can name, and the default ADC mapping of its configurations.

:data:`LUTS` names the built-in tables (:func:`lut_weights`): the paper's 0/1 LUT, the plain
(all-ones) LUT and a soft cosine LUT (:func:`cosine_weights`). :func:`adc_mapping` spreads a
window of the analogue scene over the ``2**B_in`` codes of a configuration.
"""

from __future__ import annotations

import numpy as np

from dptbd.weights import move_offsets, paper_weights, plain_weights
from dptbd.errors import ConfigError

__all__ = ["LUTS", "cosine_weights", "lut_weights", "adc_mapping"]

#: Built-in weight LUTs (a configuration may instead give ``weights`` as a table).
LUTS = ("paper", "plain", "cosine")


def cosine_weights(radius: int = 1) -> np.ndarray:
    """A soft direction LUT: ``w = (1 + cos theta) / 2`` for the turning angle theta.

    1 straight on, 0.854 at 45 deg, 0.5 at 90 deg, 0.146 at 135 deg, 0 for a reversal; a
    zero move and a ``START`` predecessor get 1 (as in the paper's LUT, ``paper_weights``).
    Not exact for any F, so it exercises the weight quantisation and the rounding mode,
    which the paper's 0/1 LUT (exact for every F >= 0) cannot.
    """
    moves = move_offsets(radius).astype(np.float64)
    n_moves = len(moves)
    norms = np.linalg.norm(moves, axis=1)
    lut = np.ones((n_moves + 1, n_moves))
    for p in range(n_moves):
        for m in range(n_moves):
            if norms[p] > 0 and norms[m] > 0:
                cos = moves[p] @ moves[m] / (norms[p] * norms[m])
                lut[p, m] = min(1.0, max(0.0, (1.0 + cos) / 2.0))
    return lut


def lut_weights(name: str, radius: int) -> np.ndarray:
    """The built-in LUT ``name`` (:data:`LUTS`) for ``radius``."""
    if name == "paper":
        return paper_weights(radius)
    if name == "plain":
        return plain_weights(radius)
    if name == "cosine":
        return cosine_weights(radius)
    raise ConfigError(f"lut must be one of {LUTS} (or give 'weights' as a table), got {name!r}")


def adc_mapping(input_bits: int, mu: float, sigma: float, *, low_sigma: float = 6.0,
                span_sigma: float = 16.0) -> tuple[float, float]:
    """``(gain, offset)`` of the default ADC for B_in bits.

    The analogue window ``[mu - low_sigma * sigma, mu - low_sigma * sigma + span_sigma * sigma]``
    (default ``[mu - 6 sigma, mu + 10 sigma]``) is spread over the ``2**B_in`` codes:
    ``gain = 2**B_in / (span_sigma * sigma)`` codes per grey level, ``offset`` such that the
    window's bottom is code 0. One sigma is ``2**B_in / span_sigma`` LSB. Noise below the
    window (6 sigma: 1e-9 of the pixels) clips at 0; the window's top leaves 10 sigma for
    noise plus target (SNR up to ~6).
    """
    gain = float(1 << input_bits) / (span_sigma * sigma)
    offset = -gain * (mu - low_sigma * sigma)
    return gain, offset
