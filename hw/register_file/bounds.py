"""The range check of a written setting of :class:`~dptbd.hw.register_file.RegisterFile`.

A written setting is taken if the whole merged word (the written bytes under ``wstrb``, the
setting's current bytes elsewhere) lies in its field's ``limits`` and, with ``align`` and a
lower limit of 0, is a multiple of it. Two forms give the same answer in the same cycle:

- :func:`word_check`, the generic build's: the merged word compared with the limits;
- :func:`byte_check`, ``bounds_registered=True`` (the ECP5 build's): byte-wise comparisons,
  each written byte against the limit's byte (constants), each byte not written from flags
  of the current value's byte kept in registers, so that no comparison runs from the
  setting's register to the write's decision.
"""

from __future__ import annotations

import functools
import operator

from amaranth.hdl import Mux, Signal

__all__ = ["word_check", "byte_check"]


def word_check(reg, merged):
    """Whether ``merged`` (the merged word of a write to the setting ``reg``) lies in its
    field's ``limits`` and, with ``align`` (a power of two) and lower limit 0, is a multiple."""
    (field,) = reg.fields
    lo, hi = field.limits
    if lo:
        return (merged >= lo) & (merged <= hi)
    return _aligned(merged <= hi, merged, field)


def byte_check(reg, bus, registered):
    """The W beat's check of a write to the setting register ``reg`` by bytes, and the
    stores that keep the current value's byte flags when the write is taken: (``ok``
    registered at the W handshake, the statements of a taken write).

    ``bus`` is the register bus of :class:`~dptbd.hw.axi_lite.AXILiteSubordinate`;
    ``registered(strobe, name, condition)`` returns a register named ``name`` loaded with
    ``condition`` when ``strobe`` is high.

    Byte j of the merged word is the written byte if strobed, else the setting's byte j
    (0 above the field). Per byte: ``lt`` / ``eq`` against the limit's byte (hi, and lo if
    not 0); the merged word is <= hi iff, from the top byte down, the first byte that is
    not equal is below (or none is), and >= lo alike; with ``align``, the low bits 0 (a
    flag per byte they span)."""
    (field,) = reg.fields
    lo, hi = field.limits
    name = reg.name.lower()
    reset = field.reset
    bounds = [("hi", hi, operator.lt)] + ([("lo", lo, operator.gt)] if lo else [])
    stores = []
    checks = []
    for tag, limit, beyond in bounds:
        within = None                                # the bytes below j: merged within
        for j in range(4):
            byte = (limit >> (8 * j)) & 0xFF
            written = bus.w_in_data[8 * j:8 * j + 8]
            flags = {"in": beyond(written, byte), "eq": written == byte}
            if 8 * j < field.width:                  # the current byte from registers
                current = (reset >> (8 * j)) & 0xFF
                for flag, want in (("in", beyond(current, byte)), ("eq", current == byte)):
                    kept = Signal(init=bool(want), name=f"{name}_{tag}{j}_{flag}")
                    beat = registered(bus.w_in_stb, f"{name}_{tag}{j}_{flag}_w",
                                      Mux(bus.w_in_strb[j], flags[flag], kept))
                    stores.append(kept.eq(beat))
                    flags[flag] = Mux(bus.w_in_strb[j], flags[flag], kept)
            else:                                    # 0 above the field
                flags = {flag: Mux(bus.w_in_strb[j], flags[flag], want) for flag, want in
                         (("in", beyond(0, byte)), ("eq", byte == 0))}
            within = (flags["in"] | flags["eq"] if within is None
                      else flags["in"] | (flags["eq"] & within))
        checks.append(within)
    if field.align is not None and not lo:       # as the generic check: align with lo = 0
        assert field.align & (field.align - 1) == 0
        low = field.align.bit_length() - 1       # the low bits that must be 0, by bytes
        for j in range((low + 7) // 8):
            bits = slice(8 * j, min(8 * j + 8, low))
            zero = Signal(init=(reset % field.align) >> (8 * j) & 0xFF == 0,
                          name=f"{name}_aligned{j}")
            written_zero = ~bus.w_in_data[bits].any()
            merged_zero = Mux(bus.w_in_strb[j], written_zero, zero)
            stores.append(zero.eq(registered(bus.w_in_stb, f"{name}_aligned{j}_w",
                                             merged_zero)))
            checks.append(merged_zero)
    ok = registered(bus.w_in_stb, f"write_ok_{name}", functools.reduce(operator.and_, checks))
    return ok, stores


def _aligned(ok, merged, field):
    """``ok`` and, for a setting with ``align`` (a power of two), ``merged`` a multiple of
    it (``ok`` itself without ``align``)."""
    if field.align is None:
        return ok
    assert field.align & (field.align - 1) == 0
    return ok & ~merged[:field.align.bit_length() - 1].any()
