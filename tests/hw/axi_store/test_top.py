"""AXITopStore (``dptbd_axi --state-store axi``): its ports are the on-chip top's with the
AXI4 manager port instead of the store inside (at P = 2 and 4 ``AXITopWide``'s), its register
map the store's, and a store the map cannot hold, or ``state_output`` at P > 1, is refused at
construction. Its behaviour is run on Verilator
(``tests/sim/verilator/test_axi_store.py``)."""

import gc
import re
import warnings

import pytest
from amaranth.hdl import Shape
from amaranth.lib.wiring import In, Out

from dptbd.errors import ConfigError
from dptbd.hw.axi_store.top import AXITopStore
from dptbd.hw.axi_top import AXITop
from dptbd.hw.flow.family import ECP5
from dptbd.hw.flow.to_verilog import to_verilog
from dptbd.hw.register_map import register_map
from dptbd.hw.wide.axi_top import AXITopWide
from helpers.refusals import whole
from helpers.seg_harness import make_config


def config():
    return make_config(width=12, height=10, segment_frames=2, candidate_count=4)


@pytest.mark.parametrize("state_output", [False, True])
def test_ports_are_the_axi_tops_plus_the_manager_port(state_output):
    cfg = config()
    store = cfg.axi_store(data_bits=128, burst_beats=2, id_bits=5, address_bits=20)
    top = AXITopStore(store, state_output=state_output)
    plain = AXITop(cfg, state_output=state_output)
    to_verilog(plain, "dptbd_axi")
    ports = dict(top.signature.members)
    added = {name: member for name, member in ports.items()
             if name not in plain.signature.members}
    assert all(name.startswith("m_axi_state_") for name in added)
    assert {name: (m.flow, Shape.cast(m.shape).width) for name, m in added.items()
            if name in ("m_axi_state_araddr", "m_axi_state_awid", "m_axi_state_rdata",
                        "m_axi_state_wstrb", "m_axi_state_rready")} == {
        "m_axi_state_araddr": (Out, 20), "m_axi_state_awid": (Out, 5),
        "m_axi_state_rdata": (In, 128), "m_axi_state_wstrb": (Out, 16),
        "m_axi_state_rready": (Out, 1)}
    assert len(added) == 37                   # AW, AR 11 each, W 5, B 4, R 6
    assert set(plain.signature.members) <= set(ports)
    assert top.register_map == register_map(cfg, store)
    assert top.store is store and top.core.latency == plain.core.latency
    text = to_verilog(top, "dptbd_axi")                # it elaborates, with m_axis_state too
    assert "input [127:0] m_axi_state_rdata;" in text
    assert ("output m_axis_state_tvalid;" in text) == state_output


def test_a_store_the_register_map_cannot_hold_is_refused_without_a_warning():
    cfg = config()
    gc.collect()                        # other tests' components collected outside the check
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ConfigError, match=whole(
                "address_bits=48: dptbd_axi's STATE_BASE register holds 32 bits; use "
                "address_bits <= 32")):
            AXITopStore(cfg.axi_store(address_bits=48))
        gc.collect()                    # an UnusedElaboratable warning would be an error here


@pytest.mark.parametrize("p", [2, pytest.param(4, marks=pytest.mark.slow)])
def test_at_p_above_1_the_ports_are_the_wide_tops_plus_the_manager_port(p):
    cfg = make_config(width=16, height=12, segment_frames=2, candidate_count=4,
                      pixels_per_clock=p)
    store = cfg.axi_store(data_bits=128, burst_beats=2)
    top = AXITopStore(store)
    wide = AXITopWide(cfg)
    ports = {name: (m.flow, Shape.cast(m.shape).width)
             for name, m in top.signature.members.items()}
    plain = {name: (m.flow, Shape.cast(m.shape).width)
             for name, m in wide.signature.members.items()}
    assert {name: ports[name] for name in plain} == plain
    assert ports["s_axis_video_tdata"] == (In, 8 * p)
    added = set(ports) - set(plain)
    assert len(added) == 37 and all(name.startswith("m_axi_state_") for name in added)
    assert top.register_map == register_map(cfg, store)
    assert top.core.latency == wide.core.latency and top.core.scan_cycles == wide.core.scan_cycles
    text = to_verilog(top, "dptbd_axi")
    to_verilog(wide, "dptbd_axi")
    assert f"input [{8 * p - 1}:0] s_axis_video_tdata;" in text
    assert "input [127:0] m_axi_state_rdata;" in text


def test_state_output_at_p_above_1_is_refused_without_a_warning():
    cfg = make_config(width=16, height=12, segment_frames=2, candidate_count=4,
                      pixels_per_clock=2)
    gc.collect()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=whole(
                "state_output: not built at pixels_per_clock=2; dptbd_axi at P > 1 has no "
                "m_axis_state")):
            AXITopStore(cfg.axi_store(data_bits=128), state_output=True)
        gc.collect()


@pytest.mark.parametrize("p, histogram_cells", [(1, 1), (2, 2)])
def test_the_family_options_reach_the_segmenter(p, histogram_cells):
    """With the state in external memory, the ECP5 family's options reach the segmenter as
    they do on chip: at P = 1 its histogram is a DP16KD (beside the prefetcher's four) and
    its control the registered one; at P = 2 each of its two histogram banks is a DP16KD
    (``histogram_style``; the P > 1 segmenter has no ``control_style``). The generic build
    has no DP16KD."""
    cfg = make_config(width=12, height=10, segment_frames=2, candidate_count=4,
                      pixels_per_clock=p)
    store = cfg.axi_store(data_bits=64, burst_beats=2)
    cells = {}
    for family, options in (("generic", {}), ("ecp5", ECP5.options_for(cfg))):
        text = to_verilog(AXITopStore(store, core_options=options), "dptbd_axi")
        cells[family] = re.findall(r"DP16KD #\(.*?\) (\S+) \(", text, re.S)
    assert cells["generic"] == []
    assert len(cells["ecp5"]) == 4 + histogram_cells
    assert cells["ecp5"].count("memory_0") == histogram_cells    # the histogram's
