"""Payload layouts: field order, widths, offsets and the pack/unpack helpers."""

import numpy as np
import pytest
from amaranth.hdl import unsigned
from amaranth.lib import data

from dptbd.config import DPConfig
from dptbd.hw.layouts import (
    event_layout,
    field_offsets,
    pack,
    pack_array,
    pack_pixel,
    pack_state_word,
    pack_states,
    pixel_layout,
    state_layout,
    state_word_layout,
    unpack,
    unpack_array,
    unpack_state,
    unpack_state_word,
)


def test_pixel_layout_fields():
    cfg = DPConfig(input_bits=10)
    assert field_offsets(pixel_layout(cfg)) == {
        "pixel": {"offset": 0, "width": 10},
        "first": {"offset": 10, "width": 1},
    }
    assert pixel_layout(cfg).size == 11


@pytest.mark.parametrize("radius, direction_bits", [(1, 4), (2, 5)])
def test_state_layout_fields(radius, direction_bits):
    cfg = DPConfig(energy_bits=16, radius=radius)
    assert field_offsets(state_layout(cfg)) == {
        "energy": {"offset": 0, "width": 16},
        "direction": {"offset": 16, "width": direction_bits},
        "end_of_line": {"offset": 16 + direction_bits, "width": 1},
        "end_of_frame": {"offset": 17 + direction_bits, "width": 1},
        "end_of_segment": {"offset": 18 + direction_bits, "width": 1},
    }
    assert state_word_layout(cfg).size == 16 + direction_bits


def test_pack_unpack_round_trip():
    cfg = DPConfig(input_bits=8, energy_bits=12)
    assert pack_pixel(cfg, 0xA5, True) == 0x1A5
    assert pack_pixel(cfg, 3, False) == 3
    word = 0xABC | (9 << 12) | (1 << 16) | (0 << 17) | (1 << 18)
    assert unpack_state(cfg, word) == {
        "energy": 0xABC, "direction": 9, "end_of_line": 1, "end_of_frame": 0, "end_of_segment": 1}
    assert unpack_state_word(cfg, pack_state_word(cfg, 4095, 7)) == {"energy": 4095, "direction": 7}


def test_pack_refuses_values_that_do_not_fit():
    cfg = DPConfig(input_bits=4, energy_bits=8)
    with pytest.raises(ValueError, match=r"^pixel=16 does not fit 4 unsigned bits$"):
        pack_pixel(cfg, 16, False)
    with pytest.raises(ValueError, match=r"^energy=-1 does not fit 8 unsigned bits$"):
        pack_state_word(cfg, -1, 0)


def test_array_packing_agrees_with_the_scalar_one():
    cfg = DPConfig(radius=2, energy_bits=20)
    rng = np.random.default_rng(1)
    values = {name: rng.integers(0, 1 << field.width, size=(5, 7))
              for name, field in state_layout(cfg)}
    words = pack_states(cfg, **values)
    assert words.dtype == np.uint64 and words.shape == (5, 7)
    for index in np.ndindex(words.shape):
        one = {name: int(v[index]) for name, v in values.items()}
        assert int(words[index]) == pack(state_layout(cfg), one)
        assert unpack_state(cfg, int(words[index])) == one
        assert unpack(state_layout(cfg), words[index]) == one
        # the (E, d) part sits where the state-store word has it
        low = pack_state_word(cfg, one["energy"], one["direction"])
        assert int(words[index]) & ((1 << cfg.state_bits) - 1) == low
    back = unpack_array(state_layout(cfg), words)
    assert list(back) == list(values)
    for name in values:
        np.testing.assert_array_equal(back[name], values[name])


def test_array_packing_refusals():
    cfg = DPConfig()
    fields = {name: np.zeros(3, dtype=np.int64) for name, _ in state_layout(cfg)}
    fields["direction"] = np.array([0, 1 << cfg.direction_bits, 0])
    with pytest.raises(ValueError, match=r"^direction=16 does not fit 4 unsigned bits$"):
        pack_states(cfg, **fields)
    fields["direction"] = np.zeros(4, dtype=np.int64)
    with pytest.raises(ValueError, match=r"^field direction has shape \(4,\), expected \(3,\)$"):
        pack_states(cfg, **fields)
    del fields["direction"]
    with pytest.raises(ValueError, match=r"^state fields missing \['direction'\], unknown \[\]; "
                                         r"the layout has \['energy', 'direction', 'end_of_line', "
                                         r"'end_of_frame', 'end_of_segment'\]$"):
        pack_states(cfg, **fields)
    wide = data.StructLayout({"a": unsigned(40), "b": unsigned(25)})
    with pytest.raises(ValueError, match=r"^layout words are 65 bits wide, more than the 64 of a "
                                         r"uint64$"):
        pack_array(wide, {"a": [0], "b": [0]})
    with pytest.raises(ValueError, match=r"^layout fields missing \[\], unknown \['c'\]; the "
                                         r"layout has \['a', 'b'\]$"):
        pack(wide, {"a": 0, "b": 0, "c": 1})


def test_event_layout_fields():
    """The event pulses, bit 0 up, as the register block and the harness read them."""
    assert field_offsets(event_layout(DPConfig())) == {
        "frame_done": {"offset": 0, "width": 1},
        "segment_done": {"offset": 1, "width": 1},
        "list_done": {"offset": 2, "width": 1},
        "saturated": {"offset": 3, "width": 1},
    }
