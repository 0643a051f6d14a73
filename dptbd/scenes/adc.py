"""The sensor: float frames to unsigned integer ADC codes, and paper 001's ADC.

:func:`quantise` turns a float scene into the integer frames of ``docs/arithmetic.md`` §1
that the models and the gateware take; :data:`INPUT_BITS` and :data:`ADC_GAIN` are paper
001's 12-bit ADC at 16 LSB per grey level.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from dptbd.scenes._checks import SceneError, _check_int, _check_real

__all__ = ["quantise", "INPUT_BITS", "ADC_GAIN"]

#: Paper 001's sensor: a 12-bit ADC with 16 LSB per grey level, so the paper's grey levels
#: (mean 30, sigma 1.73) become mean 480, sigma 27.7 LSB. An 8-bit ADC at 1 LSB per grey
#: level (sigma < 2 LSB) makes so many pixels tie at the threshold that the
#: constant-count rule (docs/arithmetic.md §6) keeps far fewer than 0.2 %.
INPUT_BITS = 12
#: Paper 001's 12-bit ADC gain: LSB per grey level.
ADC_GAIN = 16.0

_QUANTISE_CHUNK = 1 << 22  # elements per chunk: bounds the float temporaries of quantise


def quantise(frames: Any, input_bits: int, *, gain: float = 1.0, offset: float = 0.0) -> np.ndarray:
    """Float frames to unsigned ``input_bits``-bit codes, like an ADC.

    ``code = clip(rint(gain * x + offset), 0, 2**input_bits - 1)``: rounded to the nearest
    integer (``np.rint``: exact halves to even), then clipped (saturated) to the code
    range. The result satisfies ``docs/arithmetic.md`` §1 and can be fed to the models.

    Parameters
    ----------
    frames : array_like
        Real frames of any shape, finite (NaN and inf are refused, never clipped).
    input_bits : int
        B_in in [1, 16].
    gain, offset : float
        Finite ADC gain and offset applied before rounding; e.g. paper 000's zero-mean
        scenes need an offset to keep negative noise off the bottom of the range.

    Returns
    -------
    numpy.ndarray
        ``uint16`` codes of the same shape.
    """
    bits = _check_int("input_bits", input_bits, 1, 16)
    gain = _check_real("gain", gain)
    offset = _check_real("offset", offset)
    arr = np.asarray(frames)
    if arr.dtype.kind not in "biuf":
        raise SceneError(f"frames must be a real numeric array, got dtype {arr.dtype}")
    top = float((1 << bits) - 1)
    out = np.empty(arr.shape, dtype=np.uint16)
    src, dst = arr.reshape(-1), out.reshape(-1)
    for lo in range(0, src.size, _QUANTISE_CHUNK):
        x = src[lo:lo + _QUANTISE_CHUNK].astype(np.float64)
        if not np.all(np.isfinite(x)):
            raise SceneError("frames must be finite: found NaN or inf")
        x *= gain
        x += offset
        np.rint(x, out=x)
        np.clip(x, 0.0, top, out=x)
        dst[lo:lo + _QUANTISE_CHUNK] = x
    return out
