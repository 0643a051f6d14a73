"""Fixed delay lines of registers, used to carry side-band data alongside the datapath."""

from __future__ import annotations

from amaranth.hdl import Module, Signal, Value
from amaranth.lib import data

__all__ = ["delayed"]


def delayed(m: Module, value, cycles: int, *, name: str, domain: str = "sync",
            reset_less: bool = False):
    """Return ``value`` delayed by ``cycles`` clock cycles through a chain of registers.

    Parameters
    ----------
    m : amaranth.hdl.Module
        The module to which the registers are added.
    value : amaranth.hdl.Value or amaranth.lib.data.View
        What to delay. A view comes back as a view of the same layout.
    cycles : int
        Number of registers, >= 0; 0 returns ``value`` itself.
    name : str
        Base name of the registers (``{name}_d1``, ``{name}_d2``, …).
    domain : str
        Clock domain of the registers.
    reset_less : bool
        Registers without reset (datapath values whose validity travels separately).

    Returns
    -------
    amaranth.hdl.Value or amaranth.lib.data.View
        ``value`` as it was ``cycles`` cycles ago (the registers start at 0).
    """
    if cycles < 0:
        raise ValueError(f"cycles must be an integer in [0, inf), got {cycles}")
    shape = value.shape() if isinstance(value, (Value, data.View)) else Value.cast(value).shape()
    for stage in range(1, cycles + 1):
        register = Signal(shape, name=f"{name}_d{stage}", reset_less=reset_less)
        m.d[domain] += register.eq(value)
        value = register
    return value
