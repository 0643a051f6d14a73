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
- the memory map of ``s_axil``: the register map's one source, ``hw/registers.rdl``,
  compiled for the build and exported by peakrdl-ipxact (:func:`memory_map`);
- its file sets (the Verilog for Vivado's synthesis and simulation views, the C register
  header apart) and its parameters (the build's :class:`~dptbd.config.DPConfig` fields,
  fixed: the Verilog has no parameters).

ARM's AMBA bus definitions (vendor ``amba.com``) are the vendor-neutral alternative; the
block designs this file is for connect interfaces of Vivado's own definitions, so it names
those (``docs/integration.md`` says what other tools need).
"""

from __future__ import annotations

import dataclasses
import xml.etree.ElementTree as ET
from typing import Mapping, Sequence

from dptbd.config import DPConfig
from dptbd.hw.flow.register_outputs import IPXACT_LIBRARY, IPXACT_VENDOR, ipxact

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

#: Vendor and library of the component's VLNV (the FuseSoC core's ``dptbd:dptbd``; the
#: register map's IP-XACT, ``register_outputs.ipxact``, names the same).
VENDOR, LIBRARY = IPXACT_VENDOR, IPXACT_LIBRARY


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

def memory_map(cfg: DPConfig, state_store=None) -> ET.Element:
    """The ``spirit:memoryMap`` of the build's register map: ``hw/registers.rdl`` compiled
    for ``cfg`` (and ``state_store``) by :func:`~dptbd.hw.registers.compile_map`, exported
    by peakrdl-ipxact as IEEE 1685-2009 (:func:`~dptbd.hw.flow.register_outputs.ipxact`):
    an address block per group (identification, control, status; the store's registers,
    with ``--state-store axi``, in each of them) and one for the LUT window (a register
    array), each at its byte address in the port's ``2**ADDRESS_BITS``-byte window."""
    exported = ET.fromstring(ipxact(cfg, state_store, standard=2009))
    (mmap,) = exported.iterfind(f"{_tag('memoryMaps')}/{_tag('memoryMap')}")
    return mmap


# -- the component ---------------------------------------------------------------------------

#: Vivado's views: (name, environment identifier).
_VIEWS = (("xilinx_anylanguagesynthesis", ":vivado.xilinx.com:synthesis"),
          ("xilinx_anylanguagebehavioralsimulation", ":vivado.xilinx.com:simulation"))


def _bus_interface(parent: ET.Element, bus: BusInterface, names: Sequence[str],
                   reset: str | None, memory_map_name: str) -> None:
    element = _el(parent, "busInterface")
    _el(element, "name", bus.name)
    definition = bus.definition
    _el(element, "busType", **definition.vlnv())
    _el(element, "abstractionType", **definition.vlnv(abstraction=True))
    mode = _el(element, bus.mode)
    if bus.kind == "aximm" and bus.mode == "slave":
        _el(mode, "memoryMapRef", memoryMapRef=memory_map_name)
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


def component_xml(cfg: DPConfig, ports: Sequence[Mapping], *, verilog: str, header: str,
                  version: str, description: str, module: str = "dptbd_axi",
                  state_store=None) -> str:
    """The text of ``component.xml`` for the build of ``cfg`` with ``ports`` (the manifest's);
    ``verilog`` and ``header`` are the file names of the Verilog and the C header beside it,
    ``version`` the package's (the VLNV takes its major.minor), ``state_store`` the
    :class:`~dptbd.config.AxiStoreConfig` of ``--state-store axi``.

    Raises
    ------
    ValueError
        From :func:`bus_interfaces`.
    """
    interfaces = bus_interfaces(ports, module)
    mmap = memory_map(cfg, state_store)
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
        _bus_interface(buses, bus, streams, reset, mmap.find(_tag("name")).text)

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
        maps.append(mmap)

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
