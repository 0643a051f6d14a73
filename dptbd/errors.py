"""The error family of ``dptbd`` and the one set of parameter checks every module uses.

Every refusal of a parameter or input value is a :class:`DptbdError` (a ``ValueError``);
each area has its own subclass (``dptbd.scenes.SceneError``,
``dptbd.dsp.association.AssociationError``, …), defined where its area lives, so a caller
can catch one area or all of them. :class:`ConfigError`, the refusal of a
:class:`~dptbd.config.DPConfig` parameter, lives here: ``dptbd.config`` and
``dptbd.config.family`` (the §8 half of the configuration) both raise it.

The checks here write one message format, naming the parameter, its domain and the value
given::

    {name} must be an integer in [{lo}, {hi}], got {value!r}
    {name} must be a finite real number in [{lo}, {hi}], got {value!r}
    {name} must be true or false, got {value!r}
    {name} must be a pair ({first}, {second}) of integers in [1, {hi}], got {value!r}

An unbounded end is written ``-inf`` or ``inf`` with an open bracket; a bound that follows
from another parameter may be labelled by it (``[input_bits=8, 32]``). Each check takes
``error=``, the subclass to raise.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = [
    "DptbdError",
    "ConfigError",
    "interval",
    "shown",
    "check_int",
    "check_real",
    "check_prob",
    "check_bool",
    "check_shape",
]


class DptbdError(ValueError):
    """A parameter or input is outside its domain; the message names both."""


class ConfigError(DptbdError):
    """A :class:`~dptbd.config.DPConfig` parameter is outside its allowed range; the message
    names both."""


def shown(value: Any) -> str:
    """``repr`` of a value as it reads in a message: a NumPy scalar as its Python value."""
    if isinstance(value, np.generic):
        value = value.item()
    return repr(value)


def _bound(value: float, label: str) -> str:
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        text = str(int(value))
    else:
        text = f"{value:g}"
    return f"{label}{text}"


def interval(lo: float = -math.inf, hi: float = math.inf, *, lo_open: bool = False,
             hi_open: bool = False, lo_name: str = "", hi_name: str = "") -> str:
    """The domain ``[lo, hi]`` as a message writes it.

    An infinite end is open (``(-inf`` or ``inf)``); ``lo_name``/``hi_name`` label a bound
    that follows from another parameter, e.g. ``lo_name="input_bits="`` gives
    ``[input_bits=8, 32]``.
    """
    if hi is None:
        hi = math.inf
    lo_open = lo_open or lo == -math.inf
    hi_open = hi_open or hi == math.inf
    return (f"{'(' if lo_open else '['}{_bound(lo, lo_name)}, "
            f"{_bound(hi, hi_name)}{')' if hi_open else ']'}")


def check_int(name: str, value: Any, lo: int, hi: int | None = None, *,
              error: type[DptbdError] = DptbdError, lo_name: str = "", hi_name: str = "") -> int:
    """An integer in ``[lo, hi]`` (``hi=None``: no upper bound) as ``int``.

    ``bool`` is refused; so is a float even when it holds a whole number.

    Raises
    ------
    DptbdError
        (the class given as ``error``) ``{name} must be an integer in [lo, hi], got {value!r}``.
    """
    if (isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer))
            or value < lo or (hi is not None and value > hi)):
        span = interval(lo, hi, lo_name=lo_name, hi_name=hi_name)
        raise error(f"{name} must be an integer in {span}, got {shown(value)}")
    return int(value)


def check_real(name: str, value: Any, lo: float = -math.inf, hi: float = math.inf, *,
               lo_open: bool = False, hi_open: bool = False,
               error: type[DptbdError] = DptbdError) -> float:
    """A finite real number in ``[lo, hi]`` (either end open on request) as ``float``.

    Integers are accepted; ``bool``, NaN and infinities are refused.

    Raises
    ------
    DptbdError
        (the class given as ``error``) ``{name} must be a finite real number in [lo, hi],
        got {value!r}``.
    """
    ok = (not isinstance(value, (bool, np.bool_))
          and isinstance(value, (int, float, np.integer, np.floating)))
    if ok:
        out = float(value)
        ok = (math.isfinite(out) and lo <= out <= hi
              and not (lo_open and out == lo) and not (hi_open and out == hi))
    if not ok:
        span = interval(lo, hi, lo_open=lo_open, hi_open=hi_open)
        raise error(f"{name} must be a finite real number in {span}, got {shown(value)}")
    return out


def check_prob(name: str, value: Any, *, lo_open: bool = True, hi_open: bool = True,
               error: type[DptbdError] = DptbdError) -> float:
    """A probability in ``(0, 1)``; either end closed on request (:func:`check_real`)."""
    return check_real(name, value, 0.0, 1.0, lo_open=lo_open, hi_open=hi_open, error=error)


def check_bool(name: str, value: Any, *, error: type[DptbdError] = DptbdError) -> bool:
    """``True`` or ``False`` (or a NumPy bool); strings and numbers are refused.

    Raises
    ------
    DptbdError
        (the class given as ``error``) ``{name} must be true or false, got {value!r}``.
    """
    if not isinstance(value, (bool, np.bool_)):
        raise error(f"{name} must be true or false, got {shown(value)}")
    return bool(value)


def check_shape(name: str, value: Any, hi: int | None = None, *, axes: tuple[str, str] = ("H", "W"),
                error: type[DptbdError] = DptbdError) -> tuple[int, int]:
    """A pair of integers in ``[1, hi]`` (``hi=None``: no upper bound), e.g. ``(H, W)``.

    ``axes`` names the two entries; an entry out of range is refused by
    :func:`check_int` as ``{name}[0] ({axes[0]})``.

    Raises
    ------
    DptbdError
        (the class given as ``error``) ``{name} must be a pair ({axes[0]}, {axes[1]}) of
        integers in [1, hi], got {value!r}``.
    """
    try:
        pair = not isinstance(value, (str, bytes)) and len(value) == 2
    except TypeError:
        pair = False
    if not pair:
        raise error(f"{name} must be a pair ({axes[0]}, {axes[1]}) of integers in "
                    f"{interval(1, hi)}, got {shown(value)}")
    return (check_int(f"{name}[0] ({axes[0]})", value[0], 1, hi, error=error),
            check_int(f"{name}[1] ({axes[1]})", value[1], 1, hi, error=error))
