"""The scene layer's error class and the parameter checks its modules share.

:class:`SceneError` is what every scene module raises for a bad parameter (public homes:
``dptbd.scenes.SceneError`` and ``dptbd.scenes.synthetic.SceneError``); the checks write
the one message format of :mod:`dptbd.errors`.
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np

from dptbd.errors import DptbdError, check_int, check_real, check_shape

__all__ = ["SceneError"]

_MAX_SIZE = 65535
_MAX_FRAMES = 10**7


class SceneError(DptbdError):
    """A scene parameter is invalid; the message names it and its allowed range."""


# ---- validation helpers -------------------------------------------------------------------

_check_int = functools.partial(check_int, error=SceneError)


def _check_real(name: str, value: Any, *, positive: bool = False) -> float:
    """A finite real number (``> 0`` when ``positive``), else :class:`SceneError`."""
    return check_real(name, value, 0.0 if positive else -math.inf, lo_open=positive,
                      error=SceneError)


def _check_pair(name: str, value: Any) -> tuple[float, float]:
    """A pair of finite reals ``(row, col)``, else :class:`SceneError`."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise SceneError(f"{name} must be a (row, col) pair of finite reals, got {value!r}") from exc
    if arr.shape != (2,):
        raise SceneError(f"{name} must be a (row, col) pair of shape (2,), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise SceneError(f"{name} must be finite (no NaN or inf), got {value!r}")
    return float(arr[0]), float(arr[1])


def _check_shape(shape: Any) -> tuple[int, int]:
    """Frame size ``(height, width)``, each in ``[1, 65535]``."""
    return check_shape("shape", shape, _MAX_SIZE, axes=("height", "width"), error=SceneError)
