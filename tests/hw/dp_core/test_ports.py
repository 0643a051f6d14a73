"""The port members DPCore shares with the tops around it."""

from amaranth.lib import wiring

from dptbd.config import DPConfig
from dptbd.hw.dp_core.ports import (family_write_members, family_write_ports,
                                    lut_write_members, run_time_k_members)
from helpers.family_harness import variant


def test_paper_001_has_no_family_ports():
    cfg = DPConfig(width=6, height=5)
    assert family_write_members(cfg) == {}
    assert family_write_ports(cfg) == ()


def test_family_ports_exist_only_for_the_luts_built():
    merit = DPConfig(**variant("likelihood-penalty-r1")[0])
    assert family_write_ports(merit) == ("merit_addr", "merit_data", "merit_we",
                                         "penalty_addr", "penalty_data", "penalty_we")
    penalty_only = DPConfig(**variant("amplitude-penalty-r1")[0])
    assert family_write_ports(penalty_only) == ("penalty_addr", "penalty_data", "penalty_we")


def test_lut_and_run_time_k_members():
    cfg = DPConfig(width=6, height=5, segment_frames=3, max_segment_frames=5)
    lut = lut_write_members(cfg)
    assert list(lut) == ["lut_addr", "lut_data", "lut_we"]
    assert all(member.flow is wiring.In for member in lut.values())
    k = run_time_k_members(cfg)["segment_frames"]
    assert k.flow is wiring.In and k.init == 3
