"""``AXITopWide`` (``dptbd_axi`` at P = 2 and 4; simulated on Verilator in
``tests/sim/verilator/test_wide_axi.py``): its ports and the refusals of
``axi_top``."""

import pytest

from dptbd.hw.axi_top import AXITop
from dptbd.hw.wide.axi_top import AXITopWide, axi_top
from dptbd.hw.wide.axis_video import video_tdata_layout_wide
from dptbd.hw.layouts import field_offsets
from helpers.hw_harness import refused
from helpers.refusals import whole
from helpers.seg_harness import make_config


@pytest.mark.parametrize("p, bits, lane", [(2, 8, 8), (4, 8, 8), (2, 10, 16)])
def test_video_port_carries_p_byte_lanes(p, bits, lane):
    cfg = make_config(width=12, height=8, candidate_count=3, input_bits=bits,
                      pixels_per_clock=p)
    top = axi_top(cfg)
    assert isinstance(top, AXITopWide) and len(top.s_axis_video_tdata) == p * lane
    assert not top.state_output and len(top.m_axis_cand_tdata) % 8 == 0
    offsets = field_offsets(video_tdata_layout_wide(cfg))
    assert [offsets[f"pixel_{k}"] for k in range(p)] == [
        {"offset": k * lane, "width": bits} for k in range(p)]


def test_axi_top_picks_by_p_and_refuses_what_p_above_1_does_not_build():
    assert type(axi_top(make_config(width=12, height=8, candidate_count=3))) is AXITop
    cfg = make_config(width=12, height=8, candidate_count=3, pixels_per_clock=2)
    with refused(ValueError, whole(
            "external_state_store, state_output: not built at pixels_per_clock=2; dptbd_axi "
            "at P > 1 has the on-chip state store and no m_axis_state")):
        axi_top(cfg, state_output=True, external_state_store=True)
    with refused(ValueError, whole(
            "AXITopWide takes pixels_per_clock 2 or 4; at 1 use dptbd.hw.axi_top.AXITop "
            "(dptbd.hw.wide.axi_top.axi_top picks by P)")):
        AXITopWide(make_config(width=12, height=8, candidate_count=3))
