"""Parameter checks of the detectors: :mod:`dptbd.errors`' checks raising :class:`DetectorError`.

The generic checks (integer, real, probability, bool, shape) are those of
:mod:`dptbd.errors` with ``error=DetectorError``; only :func:`check_frames` is the
detectors' own.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

from dptbd import errors
from dptbd.errors import DptbdError

__all__ = ["DetectorError", "check_int", "check_real", "check_bool", "check_shape", "check_frames", "check_prob"]


class DetectorError(DptbdError):
    """A detector parameter or input is invalid; the message names it and its allowed domain."""


check_int = functools.partial(errors.check_int, error=DetectorError)
check_real = functools.partial(errors.check_real, error=DetectorError)
check_prob = functools.partial(errors.check_prob, error=DetectorError)
check_bool = functools.partial(errors.check_bool, error=DetectorError)
check_shape = functools.partial(errors.check_shape, error=DetectorError)


def check_frames(frames: Any, name: str = "frames", *, min_ndim: int = 3,
                 nonnegative: bool = False) -> np.ndarray:
    """A real, finite array of shape ``(..., T, H, W)`` as ``float64``."""
    arr = np.asarray(frames)
    if arr.dtype.kind not in "biuf":
        raise DetectorError(f"{name} must be a real numeric array, got dtype {arr.dtype}")
    if arr.ndim < min_ndim:
        raise DetectorError(
            f"{name} must have shape (..., T, H, W) with at least {min_ndim} axes, got shape {arr.shape}")
    if 0 in arr.shape:
        raise DetectorError(f"{name} must not be empty, got shape {arr.shape}")
    arr = arr.astype(np.float64, copy=False)
    if not np.all(np.isfinite(arr)):
        raise DetectorError(f"{name} must be finite: found NaN or inf")
    if nonnegative and arr.min() < 0:
        raise DetectorError(f"{name} must be magnitudes >= 0, found {arr.min():g}")
    return arr


def check_sequence(frames: Any, shape: tuple[int, int], likelihood: str) -> np.ndarray:
    """One sequence ``(T, H, W)`` of a filter on the grid ``shape`` (:func:`check_frames`),
    magnitudes >= 0 for the Rician ``likelihood``."""
    arr = check_frames(frames, min_ndim=3)
    if arr.ndim != 3 or arr.shape[1:] != shape:
        raise DetectorError(f"frames must be one sequence (T, {shape[0]}, {shape[1]}), "
                            f"got shape {arr.shape}")
    if likelihood == "rician" and arr.min() < 0:
        raise DetectorError("frames must be magnitudes >= 0 for the Rician likelihood")
    return arr
