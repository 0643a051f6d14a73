"""Parameter checks shared by the detectors: every refusal names the parameter and its domain."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["DetectorError", "check_int", "check_real", "check_bool", "check_shape", "check_frames", "check_prob"]


class DetectorError(ValueError):
    """A detector parameter or input is invalid; the message names it and its allowed domain."""


def check_int(name: str, value: Any, lo: int, hi: int | None = None) -> int:
    """An integer in ``[lo, hi]`` (``hi=None``: unbounded)."""
    span = f"[{lo}, inf)" if hi is None else f"[{lo}, {hi}]"
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise DetectorError(f"{name} must be an integer in {span}, got {value!r}")
    if value < lo or (hi is not None and value > hi):
        raise DetectorError(f"{name} must be in {span}, got {value}")
    return int(value)


def check_real(name: str, value: Any, lo: float = -math.inf, hi: float = math.inf, *,
               lo_open: bool = False, hi_open: bool = False) -> float:
    """A finite real in the interval given by ``lo``/``hi`` (open or closed ends)."""
    span = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise DetectorError(f"{name} must be a real number in {span}, got {value!r}")
    out = float(value)
    bad = (not math.isfinite(out) or out < lo or out > hi
           or (lo_open and out == lo) or (hi_open and out == hi))
    if bad:
        raise DetectorError(f"{name} must be a finite real number in {span}, got {value!r}")
    return out


def check_bool(name: str, value: Any) -> bool:
    """A real boolean (``True``/``False``, or a NumPy bool); strings and numbers are refused."""
    if not isinstance(value, (bool, np.bool_)):
        raise DetectorError(f"{name} must be true or false, got {value!r}")
    return bool(value)


def check_shape(name: str, value: Any, hi: int | None = None) -> tuple[int, int]:
    """An ``(H, W)`` pair of integers in ``[1, hi]`` (``hi=None``: unbounded)."""
    try:
        pair = not isinstance(value, (str, bytes)) and len(value) == 2
    except TypeError:
        pair = False
    if not pair:
        raise DetectorError(f"{name} must be an (H, W) pair of positive integers, got {value!r}")
    return (check_int(f"{name}[0] (H)", value[0], 1, hi), check_int(f"{name}[1] (W)", value[1], 1, hi))


def check_prob(name: str, value: Any, *, open_lo: bool = True, open_hi: bool = True) -> float:
    """A probability in (0, 1) (ends open unless told otherwise)."""
    return check_real(name, value, 0.0, 1.0, lo_open=open_lo, hi_open=open_hi)


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
