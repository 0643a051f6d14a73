"""The register map as data: layout rules every configuration must satisfy, and the ranges
it takes from ``DPConfig``."""

import pytest

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.register_map import ADDRESS_BITS, EVENTS, FIELD_KINDS, register_map
from dptbd.hw.registers import RDL_PATH, RegisterMapError
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


# ---- read from hw/registers.rdl ---------------------------------------------------------

def test_events_are_the_counters_events_in_address_order():
    cfg = DPConfig().build_config()
    regmap = register_map(cfg)
    assert regmap.events == tuple(f.event for _r, f in regmap.fields("counter")) == EVENTS


def test_each_kind_is_read_from_the_systemrdl_properties():
    """One field of each kind, as ``hw/registers.rdl`` writes it."""
    from dptbd.hw.register_map import field_kind
    from dptbd.hw.registers import compile_map

    top = compile_map(DPConfig().build_config())
    kinds = {path: field_kind(top.find_by_path(path)) for path in (
        "identification.ID.magic", "control.SEGMENT_FRAMES.segment_frames",
        "control.IRQ_ENABLE.fault", "control.CONTROL.soft_reset", "status.FRAMES.count",
        "status.ERROR.write_refused", "status.IRQ_STATUS.fault",
        "status.STATUS.soft_reset_busy", "LUT.entry.code")}
    assert list(kinds.values()) == ["constant", "setting", "enable", "pulse", "counter",
                                    "sticky", "interrupt", "status", None]


def _edited(tmp_path, old: str, new: str):
    text = RDL_PATH.read_text()
    assert text.count(old) == 1
    path = tmp_path / "edited.rdl"
    path.write_text(text.replace(old, new))
    return path


KINDS = ("constant, setting, enable, pulse, counter, sticky, interrupt, status "
         "(docs/integration.md)")


@pytest.mark.parametrize("field, access", [
    ("field { sw = rw; hw = w; } soft_reset_busy[1] = 0;", "sw=rw, hw=w"),
    ("field { sw = r; hw = w; rclr; } soft_reset_busy[1] = 0;", "sw=r, hw=w, onread=rclr"),
    ("field { sw = r; hw = w; hwset; } soft_reset_busy[1] = 0;", "sw=r, hw=w, hwset")])
def test_an_access_the_register_file_cannot_implement_is_refused_with_the_register(
        tmp_path, field, access):
    path = _edited(tmp_path, "status soft_reset_busy[1] = 0;", field)
    with pytest.raises(RegisterMapError, match=whole(
            f"register STATUS: field soft_reset_busy has an access the register file cannot "
            f"implement ({access}); the register file implements {KINDS}")):
        register_map(make_config(), source=path)


def test_fields_of_different_kinds_in_one_register_are_refused(tmp_path):
    path = _edited(tmp_path, "enable fault[1] = 0;", "pulse fault[1] = 0;")
    with pytest.raises(RegisterMapError, match=whole(
            f"register IRQ_ENABLE: fields of different kinds (segment_done: enable, fault: "
            f"pulse); a register's fields share one kind; the register file implements "
            f"{KINDS}")):
        register_map(make_config(), source=path)


def test_a_setting_register_of_two_fields_is_refused(tmp_path):
    path = _edited(tmp_path, "            no_sof->range_max = 1;\n",
                   "            no_sof->range_max = 1;\n            setting other[1] = 0;\n"
                   "            other->range_max = 1;\n")
    with pytest.raises(RegisterMapError, match=whole(
            f"register VIDEO_INPUT: a setting register has one field, from bit 0 (the whole "
            f"written word is checked against its range); the register file implements "
            f"{KINDS}")):
        register_map(make_config(), source=path)


def test_a_field_added_to_the_rdl_appears_in_the_map_the_constants_and_the_register_file(
        tmp_path):
    """A constant added to ``BUILD_LUT`` in the ``.rdl`` only: the map, the testbenches'
    constants and the register file's read of the register carry it."""
    from dptbd.hw.register_file import RegisterFile
    from dptbd.hw.register_map import register_constants
    from helpers.axil_harness import axil_read
    from helpers.hw_harness import simulate

    path = _edited(tmp_path, "            constant weight_bits[8] = WEIGHT_BITS;\n",
                   "            constant weight_bits[8] = WEIGHT_BITS;\n"
                   "            constant spare[8] = 0xA5;\n")
    cfg = make_config(width=8, height=6, candidate_count=2)
    regmap = register_map(cfg, source=path)
    (spare,) = [f for f in regmap["BUILD_LUT"].fields if f.name == "spare"]
    assert (spare.lsb, spare.width, spare.kind, spare.reset) == (24, 8, "constant", 0xA5)
    consts = register_constants(regmap)
    assert consts["BUILD_LUT_SPARE_MASK"] == 0xFF << 24
    dut = RegisterFile(cfg, regmap)
    got = []

    async def bench(ctx):
        got.append(await axil_read(ctx, dut.axil, regmap["BUILD_LUT"].address))

    simulate(dut, bench)
    assert got[0][0] >> 24 == 0xA5
    assert got[0][0] == regmap["BUILD_LUT"].reset


def test_a_counter_without_its_event_is_refused(tmp_path):
    path = _edited(tmp_path, '        LISTS.count->event = "list_done";\n', "")
    with pytest.raises(RegisterMapError, match=whole(
            f"register LISTS: field count is a counter without the event that counts or sets "
            f"it (property event); the register file implements {KINDS}")):
        register_map(make_config(), source=path)


def test_a_sticky_bit_set_by_an_unknown_event_is_refused(tmp_path):
    path = _edited(tmp_path, 'frame_long->event = "frame_long";',
                   'frame_long->event = "frame_lost";')
    events = ("frame_done", "segment_done", "list_done", "saturated", "sof_unexpected",
              "frame_short", "frame_long", "line_length", "input_stall", "output_stall",
              "write_refused", "fault")
    with pytest.raises(RegisterMapError, match=whole(
            f"register ERROR: field frame_long is set by event 'frame_lost', which is none of "
            f"{events}; the register file implements {KINDS}")):
        register_map(make_config(), source=path)
