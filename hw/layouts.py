"""Bit layouts of the words that cross the DP pipeline's ports, and the one pack/unpack.

These are the *only* definitions of the stream payloads: the gateware builds its ports from
them and a testbench (Amaranth or cocotb) packs and unpacks with the same functions, so a
field can never move on one side only. Every layout is a
:class:`amaranth.lib.data.StructLayout`: fields are packed from bit 0 upwards in the order
listed.

:func:`pack` / :func:`unpack` (one word, Python ints) and :func:`pack_array` /
:func:`unpack_array` (numpy ``uint64`` words) work on any struct layout: they are the only
place where a field is shifted into or out of a word, for these layouts and for the
segmenter's (:mod:`dptbd.hw.candidate_layout`). The per-stream helpers below name them.
"""

from __future__ import annotations

from typing import Mapping

import numpy as np
from amaranth.hdl import unsigned
from amaranth.lib import data

from dptbd.config import DPConfig

__all__ = [
    "pixel_layout",
    "state_layout",
    "state_word_layout",
    "event_layout",
    "field_offsets",
    "pack",
    "unpack",
    "pack_array",
    "unpack_array",
    "pack_pixel",
    "unpack_state",
    "pack_states",
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


def event_layout(cfg: DPConfig) -> data.StructLayout:
    """The core's event pulses (``events`` of the DP pipeline and of ``DPSegmenter``).

    Each field is high for one cycle per event, in the cycle of the handshake it reports
    (``docs/gateware.md``, "Events"):

    ============ ====== ===================================================================
    field        width  pulse when
    ============ ====== ===================================================================
    frame_done   1      a ``states`` word with ``end_of_frame`` is transferred
    segment_done 1      a ``states`` word with ``end_of_segment`` is transferred
    list_done    1      a candidate list's trailer is transferred on ``candidates``
                        (always 0 on a DP pipeline without segmenter)
    saturated    1      a ``states`` word whose E the accumulator clipped at E_max is
                        transferred (``docs/arithmetic.md`` §4.5)
    ============ ====== ===================================================================
    """
    return data.StructLayout({
        "frame_done": unsigned(1),
        "segment_done": unsigned(1),
        "list_done": unsigned(1),
        "saturated": unsigned(1),
    })


def field_offsets(layout: data.StructLayout) -> dict[str, dict[str, int]]:
    """``{field: {"offset": lsb, "width": bits}}`` of a struct layout, in field order."""
    return {name: {"offset": field.offset, "width": field.width} for name, field in layout}


def _check_names(layout: data.StructLayout, names, what: str) -> None:
    fields = [name for name, _ in layout]
    missing = sorted(set(fields) - set(names))
    unknown = sorted(set(names) - set(fields))
    if missing or unknown:
        raise ValueError(f"{what} fields missing {missing}, unknown {unknown}; "
                         f"the layout has {fields}")


def _too_wide(name: str, value: int, width: int) -> ValueError:
    return ValueError(f"{name}={value} does not fit {width} unsigned bits")


def pack(layout: data.StructLayout, values: Mapping[str, int], what: str = "layout") -> int:
    """The integer whose bit fields hold ``values``, placed as ``layout`` places them.

    Every field of ``layout`` must be given, each an unsigned value that fits its width;
    otherwise ``ValueError`` (``what`` names the layout in the message: ``"state fields
    missing [...], unknown [...]; the layout has [...]"``, ``"row=8 does not fit 3 unsigned
    bits"``).
    """
    _check_names(layout, values, what)
    word = 0
    for name, field in layout:
        value = int(values[name])
        if not 0 <= value < (1 << field.width):
            raise _too_wide(name, value, field.width)
        word |= value << field.offset
    return word


def unpack(layout: data.StructLayout, word: int) -> dict[str, int]:
    """The fields of the integer ``word`` as ``layout`` places them (layout order); bits
    outside every field are ignored."""
    return {name: (int(word) >> field.offset) & ((1 << field.width) - 1)
            for name, field in layout}


def pack_array(layout: data.StructLayout, values: Mapping[str, np.ndarray],
               what: str = "layout") -> np.ndarray:
    """:func:`pack` for arrays of field values, all of one shape: ``uint64`` words of that
    shape (the layout must be at most 64 bits wide). Refusals as :func:`pack`, naming the
    first value that does not fit."""
    _check_names(layout, values, what)
    if data.Layout.cast(layout).size > 64:
        raise ValueError(f"{what} words are {data.Layout.cast(layout).size} bits wide, "
                         f"more than the 64 of a uint64")
    shape = np.shape(next(iter(values.values())))
    word = np.zeros(shape, dtype=np.uint64)
    for name, field in layout:
        value = np.asarray(values[name], dtype=np.int64)
        if value.shape != shape:
            raise ValueError(f"field {name} has shape {value.shape}, expected {shape}")
        bad = (value < 0) | (value >= (1 << field.width))
        if bad.any():
            raise _too_wide(name, int(value[bad].flat[0]), field.width)
        word |= value.astype(np.uint64) << np.uint64(field.offset)
    return word


def unpack_array(layout: data.StructLayout, words: np.ndarray) -> dict[str, np.ndarray]:
    """:func:`unpack` for an array of ``uint64`` words: ``{field: uint64 array}`` of the
    words' shape, layout order."""
    words = np.asarray(words, dtype=np.uint64)
    return {name: (words >> np.uint64(field.offset)) & np.uint64((1 << field.width) - 1)
            for name, field in layout}


def pack_pixel(cfg: DPConfig, pixel: int, first: bool) -> int:
    """The integer value of a ``pixels`` payload."""
    return pack(pixel_layout(cfg), {"pixel": pixel, "first": int(bool(first))}, "pixel")



def unpack_state(cfg: DPConfig, word: int) -> dict[str, int]:
    """Split a ``states`` payload integer into its fields (see :func:`state_layout`)."""
    return unpack(state_layout(cfg), word)


def pack_states(cfg: DPConfig, **fields: np.ndarray) -> np.ndarray:
    """``states`` payloads (``uint64``) of arrays of field values, all of one shape; every
    field of :func:`state_layout` must be given."""
    return pack_array(state_layout(cfg), fields, "state")


def pack_state_word(cfg: DPConfig, energy: int, direction: int) -> int:
    """The integer value of a state-store word."""
    return pack(state_word_layout(cfg), {"energy": energy, "direction": direction}, "state word")


def unpack_state_word(cfg: DPConfig, word: int) -> dict[str, int]:
    """Split a state-store word into ``energy`` and ``direction``."""
    return unpack(state_word_layout(cfg), word)
