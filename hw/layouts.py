"""Bit layouts of the words that cross the DP pipeline's ports, and helpers to pack them.

These are the *only* definitions of the stream payloads: the gateware builds its ports from
them and a testbench (Amaranth or cocotb) packs and unpacks with the same functions, so a
field can never move on one side only. Every layout is a
:class:`amaranth.lib.data.StructLayout`: fields are packed from bit 0 upwards in the order
listed.
"""

from __future__ import annotations

from amaranth.hdl import unsigned
from amaranth.lib import data

from dptbd.config import DPConfig

__all__ = [
    "pixel_layout",
    "state_layout",
    "state_word_layout",
    "field_offsets",
    "pack_pixel",
    "unpack_state",
    "pack_state_word",
    "unpack_state_word",
]


def pixel_layout(cfg: DPConfig) -> data.StructLayout:
    """Payload of the input stream ``pixels``: one pixel in raster order.

    ========= ============ =======================================================
    field     width        meaning
    ========= ============ =======================================================
    pixel     B_in         the unsigned pixel value x
    first     1            start of frame: this is pixel (0, 0) of a frame
    ========= ============ =======================================================
    """
    return data.StructLayout({
        "pixel": unsigned(cfg.input_bits),
        "first": unsigned(1),
    })


def state_layout(cfg: DPConfig) -> data.StructLayout:
    """Payload of the output stream ``states``: the new (E, d) of one pixel, raster order.

    ============== ====== ====================================================================
    field          width  meaning
    ============== ====== ====================================================================
    energy         B_E    accumulated energy E
    direction      B_d    arrival move d (0 … M-1), or START = M in a segment's first frame
    end_of_line    1      last pixel of a row (column W-1)
    end_of_frame   1      last pixel of a frame (row H-1, column W-1)
    end_of_segment 1      last pixel of the last frame of a segment (implies end_of_frame)
    ============== ====== ====================================================================
    """
    return data.StructLayout({
        "energy": unsigned(cfg.energy_bits),
        "direction": unsigned(cfg.direction_bits),
        "end_of_line": unsigned(1),
        "end_of_frame": unsigned(1),
        "end_of_segment": unsigned(1),
    })


def state_word_layout(cfg: DPConfig) -> data.StructLayout:
    """One word of the state store and of the line buffers: (E, d) of one pixel."""
    return data.StructLayout({
        "energy": unsigned(cfg.energy_bits),
        "direction": unsigned(cfg.direction_bits),
    })


def field_offsets(layout: data.StructLayout) -> dict[str, dict[str, int]]:
    """``{field: {"offset": lsb, "width": bits}}`` of a struct layout, in field order."""
    return {name: {"offset": field.offset, "width": field.width} for name, field in layout}


def _pack(layout: data.StructLayout, values: dict) -> int:
    word = 0
    for name, field in layout:
        value = int(values[name])
        if not 0 <= value < (1 << field.width):
            raise ValueError(f"{name}={value} does not fit {field.width} unsigned bits")
        word |= value << field.offset
    return word


def _unpack(layout: data.StructLayout, word: int) -> dict[str, int]:
    return {name: (int(word) >> field.offset) & ((1 << field.width) - 1) for name, field in layout}


def pack_pixel(cfg: DPConfig, pixel: int, first: bool) -> int:
    """The integer value of a ``pixels`` payload."""
    return _pack(pixel_layout(cfg), {"pixel": pixel, "first": int(bool(first))})


def unpack_state(cfg: DPConfig, word: int) -> dict[str, int]:
    """Split a ``states`` payload integer into its fields (see :func:`state_layout`)."""
    return _unpack(state_layout(cfg), word)


def pack_state_word(cfg: DPConfig, energy: int, direction: int) -> int:
    """The integer value of a state-store word."""
    return _pack(state_word_layout(cfg), {"energy": energy, "direction": direction})


def unpack_state_word(cfg: DPConfig, word: int) -> dict[str, int]:
    """Split a state-store word into ``energy`` and ``direction``."""
    return _unpack(state_word_layout(cfg), word)
