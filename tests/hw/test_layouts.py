"""Payload layouts: field order, widths, offsets and the pack/unpack helpers."""

import pytest

from dptbd.config import DPConfig
from dptbd.hw.layouts import (
    field_offsets,
    pack_pixel,
    pack_state_word,
    pixel_layout,
    state_layout,
    state_word_layout,
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
    with pytest.raises(ValueError, match="pixel=16"):
        pack_pixel(cfg, 16, False)
