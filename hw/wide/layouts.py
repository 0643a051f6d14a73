"""The beats of the P-pixel streams (``docs/gateware.md``, "P pixels per clock"): P pixels
of one row per input beat (pixel 0 in the low bits, then ``first``), P states per output
beat (state 0 in the low bits, then the end flags), and their packing for test benches."""

from __future__ import annotations

from amaranth.hdl import unsigned
from amaranth.lib import data

from dptbd.config import DPConfig
from dptbd.hw.layouts import pack, state_word_layout, unpack


def wide_pixel_layout(cfg: DPConfig) -> data.StructLayout:
    """Payload of the input stream ``pixels`` at P pixels per clock: one beat, the pixels
    ``(y, gP)`` … ``(y, gP + P - 1)`` of a row, pixel 0 in the low bits.

    ========== ====== ============================================================
    field      width  meaning
    ========== ====== ============================================================
    pixel_k    B_in   pixel k of the beat (k = 0 … P-1, in this order from bit 0)
    first      1      start of frame: this beat holds pixel (0, 0) of a frame
    ========== ====== ============================================================
    """
    fields = {f"pixel_{k}": unsigned(cfg.input_bits) for k in range(cfg.pixels_per_clock)}
    return data.StructLayout({**fields, "first": unsigned(1)})


def wide_state_layout(cfg: DPConfig) -> data.StructLayout:
    """Payload of the output stream ``states`` at P pixels per clock: the new (E, d) of the P
    pixels of one beat, pixel 0 in the low bits, then the beat's end flags
    (:func:`~dptbd.hw.layouts.state_layout`'s, ``end_of_line`` on a row's last beat)."""
    fields = {}
    for k in range(cfg.pixels_per_clock):
        fields[f"energy_{k}"] = unsigned(cfg.energy_bits)
        fields[f"direction_{k}"] = unsigned(cfg.direction_bits)
    return data.StructLayout({**fields, "end_of_line": unsigned(1), "end_of_frame": unsigned(1),
                              "end_of_segment": unsigned(1)})


def beat_word_layout(cfg: DPConfig) -> data.ArrayLayout:
    """One word of the state store and of the line buffer: the P states (E, d) of a beat,
    state 0 in the low bits."""
    return data.ArrayLayout(state_word_layout(cfg), cfg.pixels_per_clock)


def pack_beat(cfg: DPConfig, pixels, first: bool) -> int:
    """The integer value of a ``pixels`` beat of P pixel values."""
    values = {f"pixel_{k}": int(v) for k, v in enumerate(pixels)}
    return pack(wide_pixel_layout(cfg), {**values, "first": int(bool(first))}, "beat")


def unpack_beat_states(cfg: DPConfig, word: int) -> list[dict[str, int]]:
    """The P states of a ``states`` beat, each as :func:`~dptbd.hw.layouts.unpack_state`
    gives a P = 1 state: ``end_of_line``, ``end_of_frame`` and ``end_of_segment`` only on
    the beat's last pixel."""
    fields = unpack(wide_state_layout(cfg), word)
    last = cfg.pixels_per_clock - 1
    return [{"energy": fields[f"energy_{k}"], "direction": fields[f"direction_{k}"],
             **{flag: fields[flag] if k == last else 0
                for flag in ("end_of_line", "end_of_frame", "end_of_segment")}}
            for k in range(cfg.pixels_per_clock)]
