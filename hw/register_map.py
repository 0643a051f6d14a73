"""The register map of the AXI top level (``dptbd_axi``), as data, read from its one source
``hw/registers.rdl`` (SystemRDL, compiled per build by :func:`dptbd.hw.registers.compile_map`).

:func:`register_map` returns, for a :class:`~dptbd.config.DPConfig`, every register of the
AXI4-Lite control port: its byte address, its fields (bit position, width, kind, reset value,
allowed range, meaning) and the weight LUT's register window. What reads it:

- the Amaranth register block (:mod:`dptbd.hw.register_file`) decodes it (its run-time range
  checks are the fields' ``limits``);
- :func:`register_constants` / :func:`constants_namespace`: the numbers the testbenches and
  the manifest use;
- the C header, HTML, Markdown (``docs/registers.md``) and IP-XACT are PeakRDL's renderings
  of the compiled ``.rdl`` (:mod:`dptbd.hw.flow.register_outputs`).

The control port is AXI4-Lite with 32-bit data and byte addresses (``docs/integration.md``
says why). Every register is one aligned 32-bit word (the ``addrmap``'s description says what
the port answers to unaligned, unmapped and window accesses). A field's *kind* says who writes
it; it is read from the field's SystemRDL properties (:func:`field_kind`):

=========== ======= ==================================================================
kind        access  behaviour
=========== ======= ==================================================================
constant    ro      a build parameter; reads its reset value, writes are refused
setting     rw      a run-time setting driving the core; a write outside ``limits`` is
                    refused (value not taken, ``ERROR.write_refused`` set, SLVERR)
enable      rw      interrupt enable bit, any value taken
pulse       wo      writing 1 makes a one-cycle pulse; reads 0
counter     ro      32-bit event counter, wraps modulo 2**32, cleared by
                    ``CONTROL.clear_counters``; writes are refused
sticky      w1c     set by its event, cleared by writing 1 (a set in the same cycle wins)
interrupt   w1c     pending interrupt: as ``sticky``; ``irq`` = any pending & enabled
status      ro      the core's state now (a level, not latched); writes are refused
=========== ======= ==================================================================
"""

from __future__ import annotations

import dataclasses
import types

from dptbd.config import DPConfig

__all__ = [
    "ADDRESS_BITS",
    "DATA_BITS",
    "COUNTER_BITS",
    "FIELD_KINDS",
    "FIELD_ACCESS",
    "EVENTS",
    "STORE_EVENTS",
    "FAULTS",
    "Field",
    "Register",
    "Window",
    "RegisterMap",
    "register_map",
    "field_kind",
    "register_constants",
    "constants_namespace",
]

#: Byte-address bits of the control port: a 4 KiB window.
ADDRESS_BITS = 12
#: AXI4-Lite data width.
DATA_BITS = 32
#: Width of every counter.
COUNTER_BITS = 32
#: Byte address of the weight LUT window's entry 0.
LUT_WINDOW_BASE = 0x400

#: The kinds of field the register file implements (``docs/integration.md``, "Registers").
FIELD_KINDS = ("constant", "setting", "enable", "pulse", "counter", "sticky", "interrupt",
               "status")
#: Bus access of each field kind.
FIELD_ACCESS = {"constant": "ro", "setting": "rw", "enable": "rw", "pulse": "wo", "counter": "ro",
           "sticky": "w1c", "interrupt": "w1c", "status": "ro"}

#: The frame-sync fault classes of the frame monitor (:mod:`dptbd.hw.frame_monitor`).
FAULTS = ("sof_unexpected", "frame_short", "frame_long", "line_length")
#: Event pulses the register block counts, in the order of its ``events`` port: the core's
#: (``frame_done`` … ``saturated``), the frame monitor's faults, and the stream stalls.
EVENTS = ("frame_done", "segment_done", "list_done", "saturated", *FAULTS,
          "input_stall", "output_stall")
#: Event pulses added by the build with the state store in external memory
#: (``--state-store axi``): an error response (SLVERR / DECERR) to a state read burst's beat
#: or a state write burst.
STORE_EVENTS = ("state_read_error", "state_write_error")


@dataclasses.dataclass(frozen=True)
class Field:
    """One bit field of a register.

    ``event`` names the pulse that counts / sets a ``counter``, ``sticky`` or ``interrupt``
    field: one of :data:`EVENTS`, ``"write_refused"`` or ``"fault"`` (any sticky bit set).
    ``limits`` is the allowed ``(lo, hi)`` of a ``setting``, checked on the whole written word;
    ``align`` (a setting's, optional): the written word must also be a multiple of it.
    """

    name: str
    lsb: int
    width: int
    kind: str
    reset: int
    doc: str
    limits: tuple[int, int] | None = None
    event: str | None = None
    align: int | None = None

    @property
    def mask(self) -> int:
        """The field's bits in the register word."""
        return ((1 << self.width) - 1) << self.lsb

    @property
    def access(self) -> str:
        return FIELD_ACCESS[self.kind]


@dataclasses.dataclass(frozen=True)
class Register:
    """One 32-bit register at byte ``address``; all its fields share one kind."""

    name: str
    address: int
    group: str
    doc: str
    fields: tuple[Field, ...]

    @property
    def kind(self) -> str:
        return self.fields[0].kind

    @property
    def access(self) -> str:
        return self.fields[0].access

    @property
    def reset(self) -> int:
        """The word read after reset."""
        return sum(f.reset << f.lsb for f in self.fields if f.kind != "pulse")


@dataclasses.dataclass(frozen=True)
class Window:
    """A write-only array of registers: entry i at ``base + 4 * i`` (reads answer SLVERR,
    a write must strobe every byte)."""

    name: str
    base: int
    entries: int
    field: Field
    doc: str

    @property
    def end(self) -> int:
        """First byte address after the window."""
        return self.base + 4 * self.entries


@dataclasses.dataclass(frozen=True)
class RegisterMap:
    """Every register and window of one configuration."""

    registers: tuple[Register, ...]
    windows: tuple[Window, ...]
    address_bits: int = ADDRESS_BITS
    #: the event pulses the register block counts, in the order of its ``events`` port
    events: tuple[str, ...] = EVENTS

    def __getitem__(self, name: str) -> Register:
        for reg in self.registers:
            if reg.name == name:
                return reg
        raise KeyError(f"no register {name!r}; the map has "
                       f"{[r.name for r in self.registers]}")

    def window(self, name: str) -> Window:
        return next(w for w in self.windows if w.name == name)

    def fields(self, kind: str) -> list[tuple[Register, Field]]:
        """Every (register, field) of one kind, in address order."""
        return [(r, f) for r in self.registers for f in r.fields if f.kind == kind]


def register_map(cfg: DPConfig, store=None, *, source=None) -> RegisterMap:
    """The register map of ``dptbd_axi`` built for ``cfg``, read from ``hw/registers.rdl``
    compiled for it (:func:`dptbd.hw.registers.compile_map`); with ``store`` (an
    :class:`~dptbd.config.AxiStoreConfig` of ``cfg``) the map of the build with the state
    store in external memory (``--state-store axi``), which adds the registers of that build
    after each group's own and the bits ``state_read`` / ``state_write`` to ``ERROR``.

    Identification registers from 0x000, control from 0x040, status from 0x080 (the
    ``addrmap`` of each group), the weight LUT window from 0x400 (a ``mem``; entry
    ``cfg.lut_address(p, m)`` at ``0x400 + 4 * address``). Each field's kind is read from
    its SystemRDL properties (:func:`field_kind`); ``events`` are the counters' events in
    address order. ``source``: another ``.rdl`` than ``hw/registers.rdl`` (tests).

    Raises
    ------
    dptbd.errors.ConfigError
        ``store`` with more than 32 address bits (``STATE_BASE`` is one 32-bit register) or
        made for another configuration.
    dptbd.hw.registers.RegisterMapError
        The ``.rdl`` does not compile (the compiler's errors, with file and line), or a
        register has an access the register file cannot implement (naming the register).
    """
    from dptbd.hw.registers import compile_map

    if store is not None:
        _check_store(cfg, store)
    return _read_map(compile_map(cfg, store, source=source))


def _read_map(top) -> RegisterMap:
    """The :class:`RegisterMap` of a compiled ``addrmap``: its ``addrmap`` children are the
    groups of registers, its ``mem`` children the windows."""
    from systemrdl.node import AddrmapNode, MemNode

    registers, windows = [], []
    for child in top.children(unroll=False):
        if isinstance(child, AddrmapNode):
            for reg in child.children(unroll=False):
                registers.append(_register(reg, child.inst_name))
        elif isinstance(child, MemNode):
            windows.append(_window(child))
        else:
            raise _refused(child.inst_name, "the map holds register groups (addrmap) and "
                                            "windows (mem) only")
    assert all(w.end <= 1 << ADDRESS_BITS for w in windows)
    events = tuple(f.event for r in registers for f in r.fields if f.kind == "counter")
    known = (*events, "write_refused", "fault")
    for reg in registers:
        for field in reg.fields:
            if field.kind in ("sticky", "interrupt") and field.event not in known:
                raise _refused(reg.name, f"field {field.name} is set by event "
                                         f"{field.event!r}, which is none of {known}")
    return RegisterMap(tuple(registers), tuple(windows), events=events)


def _refused(name: str, why: str):
    from dptbd.hw.registers import RegisterMapError

    return RegisterMapError(f"register {name}: {why}; the register file implements "
                            f"{', '.join(FIELD_KINDS)} (docs/integration.md)")


def field_kind(field) -> str | None:
    """The kind (:data:`FIELD_KINDS`) a compiled SystemRDL field implements, from its
    properties (``hw/registers.rdl`` lists them), or ``None`` if none."""
    from systemrdl.rdltypes import AccessType, OnWriteType

    prop = field.get_property
    sw, hw, onwrite = prop("sw"), prop("hw"), prop("onwrite")
    if (prop("onread") is not None or prop("swmod") or prop("swacc") or prop("hwclr")
            or prop("we") or prop("wel")):
        return None
    if prop("counter"):
        return "counter" if (sw, hw, onwrite) == (AccessType.r, AccessType.r, None) else None
    if prop("singlepulse"):
        return "pulse" if (sw, hw, onwrite) == (AccessType.w, AccessType.r, None) else None
    if onwrite == OnWriteType.woclr:
        if (sw, hw) == (AccessType.rw, AccessType.r) and prop("hwset"):
            return "interrupt" if prop("intr") else "sticky"
        return None
    if onwrite is not None or prop("hwset") or prop("intr"):
        return None
    if (sw, hw) == (AccessType.r, AccessType.na):
        return "constant"
    if (sw, hw) == (AccessType.r, AccessType.w):
        return "status"
    if (sw, hw) == (AccessType.rw, AccessType.r):
        return "setting" if prop("range_max") is not None else "enable"
    return None


def _access(field) -> str:
    """A field's SystemRDL access, as a refusal names it."""
    text = f"sw={field.get_property('sw').name}, hw={field.get_property('hw').name}"
    for name in ("onwrite", "onread"):
        value = field.get_property(name)
        if value is not None:
            text += f", {name}={value.name}"
    return text + "".join(f", {name}" for name in ("singlepulse", "counter", "hwset", "hwclr",
                                                    "intr", "swmod", "swacc")
                          if field.get_property(name))


def _field(node, kind: str, reg_doc: str) -> Field:
    lo, hi = node.get_property("range_min"), node.get_property("range_max")
    limits = None if hi is None else (0 if lo is None else lo, hi)
    return Field(node.inst_name, node.lsb, node.width, kind, node.get_property("reset") or 0,
                 node.get_property("desc") or reg_doc, limits, node.get_property("event"),
                 node.get_property("range_align"))


def _register(reg, group: str) -> Register:
    """The :class:`Register` of a compiled ``reg``, refused if the register file cannot
    implement it."""
    name = reg.inst_name
    if reg.is_array:
        raise _refused(name, "a register array is a window, at the top of the map")
    if reg.get_property("regwidth") != DATA_BITS:
        raise _refused(name, f"{reg.get_property('regwidth')} bits wide; every register is "
                             f"one {DATA_BITS}-bit word")
    fields = list(reg.fields())
    kinds = [field_kind(f) for f in fields]
    for node, kind in zip(fields, kinds):
        if kind is None:
            raise _refused(name, f"field {node.inst_name} has an access the register file "
                                 f"cannot implement ({_access(node)})")
    if len(set(kinds)) > 1:
        raise _refused(name, "fields of different kinds (" + ", ".join(
            f"{f.inst_name}: {k}" for f, k in zip(fields, kinds)) + "); a register's fields "
            "share one kind")
    if kinds[0] == "setting" and (len(fields) > 1 or fields[0].lsb != 0):
        raise _refused(name, "a setting register has one field, from bit 0 (the whole "
                             "written word is checked against its range)")
    if kinds[0] == "counter" and (len(fields) > 1 or fields[0].width != COUNTER_BITS):
        raise _refused(name, f"a counter register has one field of {COUNTER_BITS} bits")
    for node, kind in zip(fields, kinds):
        if kind in ("counter", "sticky", "interrupt") and node.get_property("event") is None:
            raise _refused(name, f"field {node.inst_name} is a {kind} without the event "
                                 f"that counts or sets it (property event)")
    doc = reg.get_property("desc") or ""
    return Register(name, reg.absolute_address, group, doc,
                    tuple(_field(f, k, doc) for f, k in zip(fields, kinds)))


def _window(mem) -> Window:
    """The :class:`Window` of a compiled ``mem``: an array of registers of one write-only
    field from bit 0 with a range (``sw = w; hw = r;``, ``range_max``), every write checked."""
    from systemrdl.rdltypes import AccessType

    (reg,) = mem.children(unroll=False)
    fields = list(reg.fields())
    node = fields[0]
    plain = not any(node.get_property(name) for name in (
        "onwrite", "onread", "singlepulse", "counter", "hwset", "hwclr", "intr", "swmod"))
    if (len(fields) > 1 or node.lsb != 0 or not plain or node.get_property("range_max") is None
            or (node.get_property("sw"), node.get_property("hw")) != (AccessType.w,
                                                                       AccessType.r)):
        raise _refused(mem.inst_name, "a window (mem) holds registers of one write-only field "
                                      "from bit 0 with a range (sw = w; hw = r; range_max)")
    doc = mem.get_property("desc") or ""
    return Window(mem.inst_name, mem.absolute_address, mem.get_property("mementries"),
                  _field(node, "setting", reg.get_property("desc") or doc), doc)


def register_constants(regmap: RegisterMap) -> dict[str, int]:
    """Every number a driver needs, by name (no prefix): ``MAGIC`` (the ``ID`` register's
    value), ``MAP_VERSION_MAJOR`` / ``_MINOR``, ``ADDRESS_BITS``, ``REG_<REGISTER>`` (byte
    address), ``<REGISTER>_RESET``, per field ``<REGISTER>_<FIELD>_SHIFT`` / ``_MASK`` /
    ``_RESET`` (and ``_MIN`` / ``_MAX`` for a setting), per window ``<WINDOW>_BASE`` /
    ``_ENTRIES`` / ``_MIN`` / ``_MAX``: what the manifest records and the testbenches use."""
    version = {f.name: f.reset for f in regmap["VERSION"].fields}
    out = {"MAGIC": regmap["ID"].reset, "MAP_VERSION_MAJOR": version["major"],
           "MAP_VERSION_MINOR": version["minor"], "ADDRESS_BITS": regmap.address_bits}
    for reg in regmap.registers:
        out[f"REG_{reg.name}"] = reg.address
        out[f"{reg.name}_RESET"] = reg.reset
        for field in reg.fields:
            stem = f"{reg.name}_{field.name.upper()}"
            out[f"{stem}_SHIFT"] = field.lsb
            out[f"{stem}_MASK"] = field.mask
            out[f"{stem}_RESET"] = field.reset
            if field.limits is not None:
                out[f"{stem}_MIN"], out[f"{stem}_MAX"] = field.limits
    for win in regmap.windows:
        out[f"{win.name}_BASE"] = win.base
        out[f"{win.name}_ENTRIES"] = win.entries
        out[f"{win.name}_MIN"], out[f"{win.name}_MAX"] = win.field.limits
    return out


def constants_namespace(cfg: DPConfig, store=None) -> types.SimpleNamespace:
    """:func:`register_constants` of ``cfg``'s map (with the state store ``store``, an
    :class:`~dptbd.config.AxiStoreConfig`, if given) as attributes (``regs.REG_ERROR``):
    what the testbenches read every offset and field through."""
    return types.SimpleNamespace(**register_constants(register_map(cfg, store)))


#: Most address bits of the state store of ``dptbd_axi`` (``STATE_BASE`` is one register).
STORE_ADDRESS_BITS = 32


def _check_store(cfg: DPConfig, store) -> None:
    """Refuse a state store the map cannot describe (see ``docs/integration.md``, "State
    store in external memory")."""
    from dptbd.errors import ConfigError

    if store.frame != cfg:
        raise ConfigError("the state store was made for another configuration than the "
                          "register map's")
    if store.address_bits > STORE_ADDRESS_BITS:
        raise ConfigError(
            f"address_bits={store.address_bits}: dptbd_axi's STATE_BASE register holds "
            f"{STORE_ADDRESS_BITS} bits; use address_bits <= {STORE_ADDRESS_BITS}")
