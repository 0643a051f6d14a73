"""Fixed delay lines, used to carry side-band data alongside the datapath.

:func:`delayed` is a chain of registers. :func:`delayed_in_memory` is the same delay as a
ring buffer in one small memory (a block RAM on iCE40, where each register of a long chain
costs a whole logic cell: the DP core's 98-bit side-band chain is ~100 of the HX8K's logic
cells); its output equals the chain's in every cycle, except that a reset does not clear it
(use it for data whose validity travels in registers).
"""

from __future__ import annotations

from amaranth.hdl import Module, Signal, Value
from amaranth.lib import data
from amaranth.lib.memory import Memory

__all__ = ["delayed", "delayed_in_memory"]


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


def delayed_in_memory(m: Module, value, cycles: int, *, name: str, domain: str = "sync",
                      ram_style: str | None = "block"):
    """Return ``value`` delayed by ``cycles`` clock cycles through a memory ring buffer.

    A memory of ``D`` words (the least power of two >= ``cycles``) written every cycle at a
    counter ``w`` and read, through its registered read port, at ``w - (cycles - 1)`` mod
    ``D``: the word written in cycle t is read in cycle t + cycles - 1 and out in cycle
    t + cycles, and ``D >= cycles`` means it is not overwritten before. The memory starts at
    0, so, as for :func:`delayed`, the first ``cycles`` outputs are 0; unlike the registers
    a reset does not clear it. Fewer than 3 cycles fall back to :func:`delayed`.

    Parameters
    ----------
    m, value, cycles, name, domain
        As :func:`delayed`; the memory is the submodule ``name``.
    ram_style : str or None
        The memory's ``ram_style`` synthesis attribute (default ``"block"``: Yosys
        otherwise keeps a memory this small in logic); ``None`` leaves it to inference.

    Returns
    -------
    amaranth.hdl.Value or amaranth.lib.data.View
        ``value`` as it was ``cycles`` cycles ago.
    """
    if cycles < 3:
        return delayed(m, value, cycles, name=name, domain=domain)
    shape = value.shape() if isinstance(value, (Value, data.View)) else Value.cast(value).shape()
    depth = 1 << (cycles - 1).bit_length()
    memory = Memory(shape=shape, depth=depth, init=[],
                    attrs=None if ram_style is None else {"ram_style": ram_style})
    m.submodules[name] = memory
    write = memory.write_port(domain=domain)
    read = memory.read_port(domain=domain)
    pointer = Signal(range(depth), name=f"{name}_pointer")
    m.d[domain] += pointer.eq(pointer + 1)       # wraps: depth is a power of two
    m.d.comb += [
        write.addr.eq(pointer),
        write.data.eq(value),
        write.en.eq(1),
        read.addr.eq(pointer - (cycles - 1)),    # mod depth by truncation
    ]
    return read.data
