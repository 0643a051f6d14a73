"""Counters that wrap: ``value + 1`` modulo a fixed modulus, without a comparator when it
is a power of two.

A raster or ring-buffer counter of ``modulus`` states wraps to 0 after ``modulus - 1``.
Written as ``Mux(value == modulus - 1, 0, value + 1)`` it costs a ``bitlen``-wide equality
and a multiplexer per bit, which Yosys keeps even when ``modulus`` is a power of two and the
counter's own width already wraps it (the 128-wide line buffer and column counter, the
16384-pixel read-ahead address). :func:`increment_mod` drops them in that case.
"""

from __future__ import annotations

from amaranth.hdl import Mux, Value

__all__ = ["increment_mod"]


def increment_mod(value, modulus: int) -> Value:
    """``(value + 1) mod modulus`` for ``value`` in ``[0, modulus)``.

    Parameters
    ----------
    value : ValueLike
        The counter, ``bitlen(modulus - 1)`` bits wide (``Signal(range(modulus))``).
    modulus : int
        Number of states, >= 1.

    Returns
    -------
    amaranth.hdl.Value
        ``value + 1`` truncated to ``len(value)`` bits when ``modulus == 2 ** len(value)``
        (the truncation is the wrap), ``Mux(value == modulus - 1, 0, value + 1)`` otherwise.
    """
    if modulus < 1:
        raise ValueError(f"modulus must be an integer in [1, inf), got {modulus}")
    value = Value.cast(value)
    if modulus == 1 << len(value):
        return (value + 1)[:len(value)]
    return Mux(value == modulus - 1, 0, value + 1)
