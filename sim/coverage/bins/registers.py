"""The register accesses of an AXI run and why the register block refuses one
(``docs/registers.md``): the ``register`` group of :mod:`dptbd.sim.coverage.bins`."""

from __future__ import annotations

from typing import Mapping

from dptbd.sim.coverage.bins.groups import ALIGN, RANGE

__all__ = ["ranged_registers", "aligned_registers", "bus_reason", "merged_write",
           "bus_operations"]


def ranged_registers(cfg, store=None) -> list[str]:
    """The registers (and the LUT window) that refuse a value out of range; ``store``: the
    build's state store (its map), if any."""
    from dptbd.hw.register_map import register_map

    regs = register_map(cfg, store)
    return [r.name for r in regs.registers if r.kind == "setting"] + \
        [w.name for w in regs.windows]


def aligned_registers(cfg, store=None) -> list[str]:
    """The settings that refuse a value in range that is not a multiple of their
    ``align`` (``STATE_BASE`` of a store build)."""
    from dptbd.hw.register_map import register_map

    return [r.name for r in register_map(cfg, store).registers
            if r.kind == "setting" and r.fields[0].align]


def bus_reason(regs, kind: str, address: int, data: int, wstrb: int,
               held: Mapping[int, int]) -> str | None:
    """Why the register block refuses a raw access (``docs/registers.md``), or None;
    ``held``: the value each setting register (by address) holds before the access."""
    verb = "write" if kind == "w" else "read"
    if address % 4:
        return f"unaligned {verb}"
    for window in regs.windows:
        if window.base <= address < window.end:
            if kind == "r":
                return f"{window.name} read"
            if wstrb != 0xF:
                return f"{window.name} write without wstrb = 1111"
            lo, hi = window.field.limits
            return None if lo <= data <= hi else window.name + RANGE
    for reg in regs.registers:
        if reg.address == address:
            if kind == "r":
                return None
            if reg.kind in ("constant", "counter", "status"):
                return {"constant": "write to a constant register",
                        "counter": "write to a counter",
                        "status": "write to the status register"}[reg.kind]
            if reg.fields[0].limits is None:
                return None
            lo, hi = reg.fields[0].limits
            value, align = merged_write(data, wstrb, held[address]), reg.fields[0].align
            if not lo <= value <= hi:
                return reg.name + RANGE
            return reg.name + ALIGN if align and value % align else None
    return f"unmapped {verb}"


def merged_write(data: int, wstrb: int, held: int) -> int:
    """The word a write with strobes ``wstrb`` makes of a register holding ``held``."""
    mask = sum(0xFF << 8 * lane for lane in range(4) if wstrb >> lane & 1)
    return (data & mask) | (held & ~mask & 0xFFFFFFFF)


def bus_operations(cfg, steps: list[dict]) -> list[tuple[int, tuple[str, int, int, int]]]:
    """(step index, ``(kind "w" or "r", byte address, data, wstrb)``) of every register
    access the ``steps`` make besides the checked reads, soft resets and counter clears, in
    the order :func:`~dptbd.sim.verilator.axi.step_operations` performs them: ``writes``,
    ``lut_codes``, ``lut_writes``, ``bus``."""
    from dptbd.hw.register_map import register_map

    regs = register_map(cfg)
    lut = regs.window("LUT").base
    out = []
    for j, step in enumerate(steps):
        ops = [("w", regs[name].address, int(value), 0xF)
               for name, value in step.get("writes", [])]
        if step.get("lut_codes") is not None:
            ops += [("w", lut + 4 * cfg.lut_address(p, m), int(code), 0xF)
                    for p, row in enumerate(step["lut_codes"]) for m, code in enumerate(row)]
        ops += [("w", lut + 4 * cfg.lut_address(p, m), int(code), int(strobe))
                for p, m, code, strobe in step.get("lut_writes", [])]
        ops += [("w", int(a), int(rest[0]), int(rest[1])) if k == "w" else ("r", int(a), 0, 0)
                for k, a, *rest in step.get("bus", [])]
        out += [(j, op) for op in ops]
    return out
