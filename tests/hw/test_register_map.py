"""The register map as data: layout rules every configuration must satisfy, and the ranges
it takes from ``DPConfig``."""

import pytest

from dptbd.hw.register_map import (ADDRESS_BITS, EVENTS, FIELD_KINDS, MAGIC, register_map)
from helpers.seg_harness import make_config

CONFIGS = [dict(), dict(width=16, height=16, radius=2, weight_frac_bits=4),
           dict(width=640, height=512, energy_bits=20, candidate_count=700)]


@pytest.mark.parametrize("params", CONFIGS)
def test_registers_are_aligned_disjoint_and_fit(params):
    cfg = make_config(**params)
    regmap = register_map(cfg)
    addresses = [reg.address for reg in regmap.registers]
    assert len(set(addresses)) == len(addresses)
    assert all(a % 4 == 0 for a in addresses)
    for reg in regmap.registers:
        assert {f.kind for f in reg.fields} == {reg.kind} and reg.kind in FIELD_KINDS
        used = 0
        for field in reg.fields:
            assert field.mask >> 32 == 0 and not used & field.mask, (reg.name, field.name)
            used |= field.mask
            assert 0 <= field.reset < 1 << field.width, (reg.name, field.name)
            if field.limits is not None:
                assert field.limits[1] < 1 << field.width
                assert field.limits[0] <= field.reset <= field.limits[1]
            if field.kind in ("counter", "sticky", "interrupt"):
                assert field.event in (*EVENTS, "write_refused", "fault")
        if reg.kind == "setting":
            assert [f.lsb for f in reg.fields] == [0]      # the whole word is checked
    (lut,) = regmap.windows
    assert max(addresses) < lut.base and lut.end <= 1 << ADDRESS_BITS
    assert lut.entries == cfg.lut_entries


def test_ranges_follow_the_configuration():
    cfg = make_config(width=16, height=16, energy_bits=12, candidate_count=4,
                      candidate_capacity=9, weight_frac_bits=5)
    regmap = register_map(cfg)
    assert regmap["ID"].reset == MAGIC
    assert regmap["SEGMENT_FRAMES"].fields[0].limits == (1, cfg.segment_frames)
    assert regmap["CANDIDATE_COUNT"].fields[0].limits == (0, 9)
    assert regmap["CANDIDATE_COUNT"].reset == 4
    assert regmap["HISTOGRAM_SHIFT"].fields[0].limits == (0, 11)
    assert regmap.window("LUT").field.limits == (0, 32)
    assert regmap["BUILD_FRAME"].reset == 16 | 16 << 16
    assert [f.name for _r, f in regmap.fields("sticky")][-1] == "write_refused"


def test_unknown_register_is_named():
    with pytest.raises(KeyError, match=r"^\"no register 'NOPE'; the map has \['ID', "):
        register_map(make_config())["NOPE"]


def test_segment_length_range_is_k_max():
    cfg = make_config(width=16, height=16, segment_frames=3, max_segment_frames=9)
    regmap = register_map(cfg)
    assert regmap["SEGMENT_FRAMES"].fields[0].limits == (1, 9)
    assert regmap["SEGMENT_FRAMES"].reset == 3
    assert regmap["BUILD_SEGMENT"].reset == 9 | 3 << 16
