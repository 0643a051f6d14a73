"""The checks of a comparison's TOML values (:mod:`dptbd.evaluation.compare.spec`): ranges by the
one family of :mod:`dptbd.errors` (raising :class:`~dptbd.errors.ConfigError`, "NAME must be an
integer in [lo, hi], got VALUE"); lists checked here.
"""

from __future__ import annotations

from typing import Any

from dptbd.errors import ConfigError, check_int, check_real, shown

__all__ = ["checked_int", "checked_real", "as_list", "increasing_reals"]


def checked_int(name: str, v: Any, lo: int, hi: int | None = None) -> int:
    """``v`` as an int in ``[lo, hi]``: :func:`dptbd.errors.check_int` raising
    :class:`~dptbd.errors.ConfigError`."""
    return check_int(name, v, lo, hi, error=ConfigError)


def checked_real(name: str, v: Any, *, positive: bool = False) -> float:
    """``v`` as a finite float (``> 0`` if ``positive``): :func:`dptbd.errors.check_real`."""
    if positive:
        return check_real(name, v, 0.0, lo_open=True, error=ConfigError)
    return check_real(name, v, error=ConfigError)


def as_list(name: str, v: Any) -> list:
    """``v`` as a list (any iterable but a string)."""
    if isinstance(v, (str, bytes)) or not hasattr(v, "__iter__"):
        raise ConfigError(f"{name} must be a list, got {shown(v)}")
    return list(v)


def increasing_reals(name: str, v: Any, *, min_len: int = 1, positive: bool = False) -> tuple:
    """``v`` as a strictly increasing tuple of at least ``min_len`` finite floats."""
    vals = as_list(name, v)
    if len(vals) < min_len:
        raise ConfigError(f"{name} must hold at least {min_len} value(s), got {vals!r}"
                          + (" (an empty list)" if not vals else ""))
    out = tuple(checked_real(f"{name}[{i}]", x, positive=positive) for i, x in enumerate(vals))
    bad = [i for i in range(1, len(out)) if out[i] <= out[i - 1]]
    if bad:
        i = bad[0]
        raise ConfigError(f"{name} must be strictly increasing, but {name}[{i}] = {out[i]:g} <= "
                          f"{name}[{i - 1}] = {out[i - 1]:g}")
    return out
