"""The IP-XACT description of ``dptbd_axi``: ``component.xml``, written by ``dptbd verilog
--top axi`` beside the Verilog (``docs/integration.md``, "Block designs: the IP-XACT
component").

:func:`component_xml` describes one build of the core as an IEEE 1685-2009 component
(namespace :data:`SPIRIT_NS`, the version Vivado's IP packager writes and reads):

- its ports, taken from the built component (the manifest's ``ports``, which
  :func:`~dptbd.hw.flow.axi_package.axi_ports` reads off the Amaranth signature), never from
  a list of their own;
- its bus interfaces, each port in exactly one, with the bus and abstraction definitions
  Vivado IP Integrator knows (:data:`BUS_DEFINITIONS`, vendor ``xilinx.com``): AXI4-Stream
  ``s_axis_video`` (subordinate), ``m_axis_cand`` and, with ``--state-output``,
  ``m_axis_state`` (managers); AXI4-Lite ``s_axil`` (subordinate, with the memory map);
  with ``--state-store axi`` the AXI4 manager ``m_axi_state`` and its address space; the
  interrupt ``irq`` (level, active high); the reset ``aresetn`` (active low) and the clock
  ``aclk``, whose ``ASSOCIATED_BUSIF`` names every bus interface and whose
  ``ASSOCIATED_RESET`` names ``aresetn``. :func:`bus_interfaces` sorts the ports by name
  (:data:`INTERFACES`) and refuses a port no interface takes, a signal the bus definition
  does not have, or a direction the interface mode contradicts;
- the memory map of ``s_axil``: every register and field of
  :func:`~dptbd.hw.register_map.register_map` (:func:`memory_map`);
- its file sets (the Verilog for Vivado's synthesis and simulation views, the C register
  header apart) and its parameters (the build's :class:`~dptbd.config.DPConfig` fields,
  fixed: the Verilog has no parameters).

AMBA bus definitions of ARM (``amba.com``) are the vendor-neutral alternative; Vivado maps
them to its own only through its IP packager, so this file names Vivado's.
"""

from __future__ import annotations

import dataclasses
import xml.etree.ElementTree as ET
from typing import Mapping, Sequence

from dptbd.config import DPConfig
from dptbd.hw.register_map import DATA_BITS, RegisterMap

__all__ = ["COMPONENT_FILE", "SPIRIT_NS", "XILINX_NS", "VENDOR", "LIBRARY",
           "BusDefinition", "BUS_DEFINITIONS", "INTERFACES", "BusInterface",
           "bus_interfaces", "memory_map", "component_xml"]

#: File name of the component: Vivado looks for ``component.xml`` in an IP repository.
COMPONENT_FILE = "component.xml"

#: IEEE 1685-2009 (IP-XACT as the SPIRIT consortium's namespace names it).
SPIRIT_NS = "http://www.spiritconsortium.org/XMLSchema/SPIRIT/1685-2009"
#: Vivado's vendor extensions.
XILINX_NS = "http://www.xilinx.com"
_XSI_NS = "http://www.w3.org/2001/XMLSchema-instance"

#: Vendor and library of the component's VLNV (the FuseSoC core's ``dptbd:dptbd``).
VENDOR = "dptbd"
LIBRARY = "dptbd"


@dataclasses.dataclass(frozen=True)
class BusDefinition:
    """A bus definition of Vivado IP Integrator: bus type ``xilinx.com:{library}:{name}:1.0``,
    abstraction ``xilinx.com:{library}:{name}_rtl:1.0``, and which logical signals the
    manager (``master``) drives; the subordinate drives the others in ``signals``."""

    name: str
    library: str
    signals: tuple[str, ...]
    driven_by_master: frozenset[str]

    def vlnv(self, abstraction: bool = False) -> dict[str, str]:
        return {"vendor": "xilinx.com", "library": self.library,
                "name": self.name + ("_rtl" if abstraction else ""), "version": "1.0"}

    @property
    def abstraction(self) -> str:
        return f"xilinx.com:{self.library}:{self.name}_rtl:1.0"

    def direction(self, signal: str, mode: str) -> str:
        """``input`` or ``output``: the port of ``signal`` on an interface in ``mode``."""
        driven = (signal in self.driven_by_master) == (mode == "master")
        return "output" if driven else "input"


def _axi4_signals() -> tuple[tuple[str, ...], frozenset[str]]:
    channels = {"AW": ("ID", "ADDR", "LEN", "SIZE", "BURST", "LOCK", "CACHE", "PROT", "QOS",
                       "REGION", "USER", "VALID", "READY"),
                "W": ("ID", "DATA", "STRB", "LAST", "USER", "VALID", "READY"),
                "B": ("ID", "RESP", "USER", "VALID", "READY"),
                "AR": ("ID", "ADDR", "LEN", "SIZE", "BURST", "LOCK", "CACHE", "PROT", "QOS",
                       "REGION", "USER", "VALID", "READY"),
                "R": ("ID", "DATA", "RESP", "LAST", "USER", "VALID", "READY")}
    signals = tuple(c + s for c, names in channels.items() for s in names)
    # the manager drives the request channels but their READY, and the response channels'
    # READY
    master = frozenset(s for s in signals
                       if (s[0] in "AW" and not s.endswith("READY"))
                       or (s[0] in "BR" and s.endswith("READY")))
    return signals, master


_AXIS = ("TDATA", "TVALID", "TREADY", "TUSER", "TLAST", "TKEEP", "TSTRB", "TID", "TDEST")

#: The bus definitions the component uses, by kind.
BUS_DEFINITIONS = {
    "axis": BusDefinition("axis", "interface", _AXIS, frozenset(_AXIS) - {"TREADY"}),
    "aximm": BusDefinition("aximm", "interface", *_axi4_signals()),
    "clock": BusDefinition("clock", "signal", ("CLK",), frozenset({"CLK"})),
    "reset": BusDefinition("reset", "signal", ("RST",), frozenset({"RST"})),
    "interrupt": BusDefinition("interrupt", "signal", ("INTERRUPT",),
                               frozenset({"INTERRUPT"})),
}

#: The bus interfaces of ``dptbd_axi``: ``(name, kind, mode)``. A port belongs to the
#: interface of its name (``aclk``, ``aresetn``, ``irq``: one signal each) or of its name's
#: prefix (``s_axil_awaddr``: ``s_axil``, logical signal ``AWADDR``).
INTERFACES = (
    ("s_axis_video", "axis", "slave"),
    ("m_axis_cand", "axis", "master"),
    ("m_axis_state", "axis", "master"),
    ("s_axil", "aximm", "slave"),
    ("m_axi_state", "aximm", "master"),
    ("irq", "interrupt", "master"),
    ("aresetn", "reset", "slave"),
    ("aclk", "clock", "slave"),
)
_SINGLE = {"irq": "INTERRUPT", "aresetn": "RST", "aclk": "CLK"}


@dataclasses.dataclass(frozen=True)
class BusInterface:
    """One bus interface: its ``ports`` as ``(physical name, logical name)``."""

    name: str
    kind: str
    mode: str
    ports: tuple[tuple[str, str], ...]

    @property
    def definition(self) -> BusDefinition:
        return BUS_DEFINITIONS[self.kind]


def bus_interfaces(ports: Sequence[Mapping], module: str = "dptbd_axi") -> list[BusInterface]:
    """The bus interfaces of a module with ``ports`` (``{"name", "direction", "width"}``, the
    manifest's entries), in :data:`INTERFACES` order, those with no port left out.

    Raises
    ------
    ValueError
        A port in no interface, a port whose logical signal the bus definition does not
        have, or a port whose direction is not the one its interface mode gives it.
    """
    members: dict[str, list[tuple[str, str]]] = {name: [] for name, _, _ in INTERFACES}
    kinds = {name: (kind, mode) for name, kind, mode in INTERFACES}
    prefixes = [name for name in members if name not in _SINGLE]
    for port in ports:
        name = port["name"]
        if name in _SINGLE:
            owner, signal = name, _SINGLE[name]
        else:
            owner = next((p for p in prefixes if name.startswith(p + "_")), None)
            if owner is None:
                raise ValueError(
                    f"port {name} of {module} is in no bus interface: a port is one of "
                    f"{', '.join(_SINGLE)} or starts with one of "
                    f"{', '.join(p + '_' for p in prefixes)}")
            signal = name[len(owner) + 1:].upper()
        kind, mode = kinds[owner]
        bus = BUS_DEFINITIONS[kind]
        if signal not in bus.signals:
            raise ValueError(f"port {name} of {module}: {bus.abstraction} has no signal "
                             f"{signal}; it has {', '.join(bus.signals)}")
        expected = bus.direction(signal, mode)
        if port["direction"] != expected:
            raise ValueError(f"port {name} of {module} is an {port['direction']}, but "
                             f"{signal} of the {mode} interface {owner} ({bus.abstraction}) "
                             f"is an {expected}")
        members[owner].append((name, signal))
    return [BusInterface(name, kind, mode, tuple(members[name]))
            for name, kind, mode in INTERFACES if members[name]]


# -- XML -------------------------------------------------------------------------------------

def _tag(name: str, ns: str = SPIRIT_NS) -> str:
    return f"{{{ns}}}{name}"


def _el(parent: ET.Element, tag: str, text=None, **attributes) -> ET.Element:
    """``<spirit:tag spirit:key="value"…>text</spirit:tag>`` appended to ``parent``."""
    element = ET.SubElement(parent, _tag(tag),
                            {_tag(k): str(v) for k, v in attributes.items()})
    if text is not None:
        element.text = str(text)
    return element


def _parameter(parent: ET.Element, name: str, value, **attributes) -> None:
    parameter = _el(parent, "parameter")
    _el(parameter, "name", name)
    _el(parameter, "value", value, **attributes)


def _format(value) -> str:
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "long"
    if isinstance(value, float):
        return "float"
    return "string"


def _value(value) -> str:
    return str(value).lower() if isinstance(value, bool) else str(value)


# -- the memory map --------------------------------------------------------------------------
# Adapter from hw/register_map.py: replaced by peakrdl-ipxact's exporter once the register
# map is described in SystemRDL.

#: IEEE 1685-2009 ``access`` and ``modifiedWriteValue`` of each field kind
#: (:data:`~dptbd.hw.register_map.FIELD_KINDS`), and whether it is volatile (the core
#: changes it).
_FIELD_ACCESS = {
    "constant": ("read-only", None, False),
    "setting": ("read-write", None, False),
    "enable": ("read-write", None, False),
    "pulse": ("write-only", None, False),
    "counter": ("read-only", None, True),
    "sticky": ("read-write", "oneToClear", True),
    "interrupt": ("read-write", "oneToClear", True),
    "status": ("read-only", None, True),
}


def _field(parent: ET.Element, field, write_only: bool = False) -> None:
    access, modified, volatile = _FIELD_ACCESS[field.kind]
    access = "write-only" if write_only else access
    element = _el(parent, "field")
    _el(element, "name", field.name)
    doc = field.doc + ("" if field.align is None else
                       f" (a multiple of {field.align}, else refused)")
    _el(element, "description", f"{field.kind}: {doc}")
    _el(element, "bitOffset", field.lsb)
    _el(element, "bitWidth", field.width)
    _el(element, "volatile", str(volatile).lower())
    _el(element, "access", access)
    if modified is not None:
        _el(element, "modifiedWriteValue", modified)
    if field.limits is not None:
        constraint = _el(element, "writeValueConstraint")
        _el(constraint, "minimum", field.limits[0])
        _el(constraint, "maximum", field.limits[1])


def _register(block: ET.Element, name: str, doc: str, offset: int, fields, *,
              dim: int | None = None, reset: int | None = None) -> None:
    """A register; with ``dim`` an array of write-only registers (a window: reads SLVERR)."""
    element = _el(block, "register")
    _el(element, "name", name)
    _el(element, "description", doc)
    if dim is not None:
        _el(element, "dim", dim)
    _el(element, "addressOffset", f"0x{offset:03X}")
    _el(element, "size", DATA_BITS)
    kinds = {f.kind for f in fields}
    _el(element, "volatile", str(any(_FIELD_ACCESS[k][2] for k in kinds)).lower())
    access = {_FIELD_ACCESS[k][0] for k in kinds} if dim is None else {"write-only"}
    _el(element, "access", access.pop() if len(access) == 1 else "read-write")
    if reset is not None:
        mask = sum(f.mask for f in fields if f.kind != "pulse")
        value = _el(element, "reset")
        _el(value, "value", f"0x{reset:08X}")
        _el(value, "mask", f"0x{mask:08X}")
    for field in fields:
        _field(element, field, write_only=dim is not None)


def memory_map(regs: RegisterMap, name: str = "s_axil") -> ET.Element:
    """The ``spirit:memoryMap`` of ``regs``: one address block ``registers`` of
    ``2**address_bits`` bytes from 0, every register with its fields, the LUT window as a
    register array (``dim``)."""
    mmap = ET.Element(_tag("memoryMap"))
    _el(mmap, "name", name)
    block = _el(mmap, "addressBlock")
    _el(block, "name", "registers")
    _el(block, "baseAddress", "0x0")
    _el(block, "range", 1 << regs.address_bits)
    _el(block, "width", DATA_BITS)
    _el(block, "usage", "register")
    items = sorted([(r.address, r) for r in regs.registers]
                   + [(w.base, w) for w in regs.windows], key=lambda item: item[0])
    for _address, item in items:
        if hasattr(item, "fields"):
            _register(block, item.name, f"{item.group}: {item.doc}", item.address,
                      item.fields, reset=item.reset)
        else:
            _register(block, item.name, item.doc, item.base, (item.field,),
                      dim=item.entries)
    return mmap


# -- the component ---------------------------------------------------------------------------

#: Vivado's views: (name, environment identifier).
_VIEWS = (("xilinx_anylanguagesynthesis", ":vivado.xilinx.com:synthesis"),
          ("xilinx_anylanguagebehavioralsimulation", ":vivado.xilinx.com:simulation"))


def _bus_interface(parent: ET.Element, bus: BusInterface, names: Sequence[str],
                   reset: str | None) -> None:
    element = _el(parent, "busInterface")
    _el(element, "name", bus.name)
    definition = bus.definition
    _el(element, "busType", **definition.vlnv())
    _el(element, "abstractionType", **definition.vlnv(abstraction=True))
    mode = _el(element, bus.mode)
    if bus.kind == "aximm" and bus.mode == "slave":
        _el(mode, "memoryMapRef", memoryMapRef=bus.name)
    elif bus.kind == "aximm":
        _el(mode, "addressSpaceRef", addressSpaceRef=bus.name)
    maps = _el(element, "portMaps")
    for physical, logical in bus.ports:
        port_map = _el(maps, "portMap")
        _el(_el(port_map, "logicalPort"), "name", logical)
        _el(_el(port_map, "physicalPort"), "name", physical)
    parameters = {
        "clock": {"ASSOCIATED_BUSIF": ":".join(names), "ASSOCIATED_RESET": reset},
        "reset": {"POLARITY": "ACTIVE_LOW"},
        "interrupt": {"SENSITIVITY": "LEVEL_HIGH"},
    }.get(bus.kind, {})
    parameters = {k: v for k, v in parameters.items() if v is not None}
    if parameters:
        element_parameters = _el(element, "parameters")
        for key, value in parameters.items():
            _parameter(element_parameters, key, value,
                       id=f"BUSIFPARAM_VALUE.{bus.name.upper()}.{key}")


def _wire_port(parent: ET.Element, port: Mapping) -> None:
    element = _el(parent, "port")
    _el(element, "name", port["name"])
    wire = _el(element, "wire")
    _el(wire, "direction", {"input": "in", "output": "out"}[port["direction"]])
    if port["width"] > 1:
        vector = _el(wire, "vector")
        _el(vector, "left", port["width"] - 1, format="long")
        _el(vector, "right", 0, format="long")


def component_xml(cfg: DPConfig, ports: Sequence[Mapping], regs: RegisterMap, *,
                  verilog: str, header: str, version: str, description: str,
                  module: str = "dptbd_axi", state_store=None,
                  memory_map_element: ET.Element | None = None) -> str:
    """The text of ``component.xml`` for the build of ``cfg`` with ``ports`` (the manifest's)
    and register map ``regs``; ``verilog`` and ``header`` are the file names of the Verilog and
    the C header beside it, ``version`` the package's (the VLNV takes its major.minor),
    ``state_store`` the :class:`~dptbd.config.AxiStoreConfig` of ``--state-store axi``.
    ``memory_map_element``: the ``s_axil`` memory map (default :func:`memory_map` of
    ``regs``).

    Raises
    ------
    ValueError
        From :func:`bus_interfaces`.
    """
    interfaces = bus_interfaces(ports, module)
    for prefix in ("xilinx", "spirit", "xsi"):
        ET.register_namespace(prefix, {"xilinx": XILINX_NS, "spirit": SPIRIT_NS,
                                       "xsi": _XSI_NS}[prefix])
    root = ET.Element(_tag("component"), {
        f"{{{_XSI_NS}}}schemaLocation": f"{SPIRIT_NS} {SPIRIT_NS}/index.xsd"})
    _el(root, "vendor", VENDOR)
    _el(root, "library", LIBRARY)
    _el(root, "name", module)
    _el(root, "version", ".".join(version.split(".")[:2]))

    buses = _el(root, "busInterfaces")
    streams = [b.name for b in interfaces if b.kind in ("axis", "aximm")]
    reset = next((b.name for b in interfaces if b.kind == "reset"), None)
    for bus in interfaces:
        _bus_interface(buses, bus, streams, reset)

    masters = [b for b in interfaces if b.kind == "aximm" and b.mode == "master"]
    if masters:
        spaces = _el(root, "addressSpaces")
        for bus in masters:
            space = _el(spaces, "addressSpace")
            _el(space, "name", bus.name)
            _el(space, "range", 1 << state_store.address_bits)
            _el(space, "width", state_store.data_bits)
    if any(b.kind == "aximm" and b.mode == "slave" for b in interfaces):
        maps = _el(root, "memoryMaps")
        maps.append(memory_map(regs) if memory_map_element is None else memory_map_element)

    model = _el(root, "model")
    views = _el(model, "views")
    for name, environment in _VIEWS:
        view = _el(views, "view")
        _el(view, "name", name)
        _el(view, "envIdentifier", environment)
        _el(view, "language", "Verilog")
        _el(view, "modelName", module)
        _el(_el(view, "fileSetRef"), "localName", f"{name}_view_fileset")
    model_ports = _el(model, "ports")
    for port in ports:
        _wire_port(model_ports, port)

    file_sets = _el(root, "fileSets")
    for name, _environment in _VIEWS:
        file_set = _el(file_sets, "fileSet")
        _el(file_set, "name", f"{name}_view_fileset")
        file = _el(file_set, "file")
        _el(file, "name", verilog)
        _el(file, "fileType", "verilogSource")
    file_set = _el(file_sets, "fileSet")
    _el(file_set, "name", "software")
    file = _el(file_set, "file")
    _el(file, "name", header)
    _el(file, "fileType", "cSource")
    _el(file, "isIncludeFile", "true")

    _el(root, "description", description)
    parameters = _el(root, "parameters")
    _parameter(parameters, "Component_Name", module, resolve="user",
               id="PARAM_VALUE.Component_Name", order=1)
    fixed = {f.name: getattr(cfg, f.name) for f in dataclasses.fields(cfg)
             if f.name != "weights"}
    if state_store is not None:
        fixed.update({f"state_store_{name}": getattr(state_store, name) for name in
                      ("data_bits", "id_bits", "burst_beats", "address_bits", "base_address",
                       "outstanding")})
    for name, value in fixed.items():
        if value is not None:
            _parameter(parameters, name, _value(value), format=_format(value))

    extensions = _el(root, "vendorExtensions")
    core = ET.SubElement(extensions, _tag("coreExtensions", XILINX_NS))
    taxonomies = ET.SubElement(core, _tag("taxonomies", XILINX_NS))
    ET.SubElement(taxonomies, _tag("taxonomy", XILINX_NS)).text = "/UserIP"
    ET.SubElement(core, _tag("displayName", XILINX_NS)).text = module

    ET.indent(root)
    return ('<?xml version="1.0" encoding="UTF-8"?>\n'
            + ET.tostring(root, encoding="unicode") + "\n")
