"""The register map as data: layout rules every configuration must satisfy, and the ranges
it takes from ``DPConfig``."""

import pytest

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.register_map import ADDRESS_BITS, EVENTS, FIELD_KINDS, register_map
from helpers.refusals import whole
from helpers.seg_harness import make_config

CONFIGS = [dict(), dict(width=16, height=16, radius=2, weight_frac_bits=4),
           dict(width=640, height=512, energy_bits=20, candidate_count=700)]


@pytest.mark.parametrize("store", [False, True])
@pytest.mark.parametrize("params", CONFIGS)
def test_registers_are_aligned_disjoint_and_fit(params, store):
    cfg = make_config(**params)
    regmap = register_map(cfg, cfg.axi_store(data_bits=128) if store else None)
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
                assert field.event in (*regmap.events, "write_refused", "fault")
        if reg.kind == "setting":
            assert [f.lsb for f in reg.fields] == [0]      # the whole word is checked
    (lut,) = regmap.windows
    assert max(addresses) < lut.base and lut.end <= 1 << ADDRESS_BITS
    assert lut.entries == cfg.lut_entries


def test_ranges_follow_the_configuration():
    cfg = make_config(width=16, height=16, energy_bits=12, candidate_count=4,
                      candidate_capacity=9, weight_frac_bits=5)
    regmap = register_map(cfg)
    assert regmap["ID"].reset == 0x44505442          # ASCII "DPTB"
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


# ---- the build with the state store in external memory (--state-store axi) -------------

def test_the_state_store_adds_registers_after_each_group_and_two_error_bits():
    from dptbd.hw.register_map import STORE_EVENTS

    cfg = DPConfig().build_config()
    store = cfg.axi_store(data_bits=128, burst_beats=8, id_bits=4, outstanding=6,
                          base_address=0x8000)
    plain, full = register_map(cfg), register_map(cfg, store)
    assert plain.events == EVENTS and full.events == (*EVENTS, *STORE_EVENTS)
    assert not any("STATE" in r.name for r in plain.registers)
    old = {r.name: r for r in plain.registers}
    for reg in full.registers:              # every register of the plain map where it was
        if reg.name in old and reg.name != "ERROR":
            assert reg == old[reg.name]
    added = {r.name: r.address for r in full.registers if r.name not in old}
    assert added == {"BUILD_STATE_STORE": 0x020, "BUILD_STATE_LAYOUT": 0x024,
                     "BUILD_STATE_BYTES": 0x028, "STATE_BASE": 0x058,
                     "STATE_READ_ERRORS": 0x0B4, "STATE_WRITE_ERRORS": 0x0B8,
                     "STATE_BASE_ACTIVE": 0x0BC}
    assert full["ERROR"].fields[:5] == old["ERROR"].fields
    assert [(f.name, f.lsb, f.event) for f in full["ERROR"].fields[5:]] == [
        ("state_read", 5, "state_read_error"), ("state_write", 6, "state_write_error")]
    (base,) = full["STATE_BASE"].fields
    assert (base.kind, base.reset, base.align, base.limits) == (
        "setting", 0x8000, 128, (0, 2**32 - store.frame_bytes))
    fields = {f.name: f.reset for r in full.registers if r.name.startswith("BUILD_STATE")
              for f in r.fields}
    assert fields == {"data_bits": 128, "address_bits": 32, "id_bits": 4, "outstanding": 6,
                      "burst_beats": 8, "slot_bits": 16, "frame_bytes": 128 * 128 * 2}


def test_the_state_store_map_refuses_wide_addresses_and_a_foreign_store():
    cfg = DPConfig().build_config()
    with pytest.raises(ConfigError, match=whole(
            "address_bits=33: dptbd_axi's STATE_BASE register holds 32 bits; use "
            "address_bits <= 32")):
        register_map(cfg, cfg.axi_store(address_bits=33))
    other = DPConfig(width=64, height=64).build_config()
    with pytest.raises(ConfigError, match=whole(
            "the state store was made for another configuration than the register map's")):
        register_map(cfg, other.axi_store())
