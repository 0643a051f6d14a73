"""Input words for the RTL: pixels packed with the gateware's own layout, LUT writes.

Plain numpy (no simulator import): used by the cocotb tests (:mod:`dptbd.sim.benches.dp`), the
compiled simulation (:mod:`dptbd.sim.verilator`) and the verification campaign alike.
"""

from __future__ import annotations

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.layouts import pack_array, pixel_layout

__all__ = ["pixel_words", "pack_pixels", "lut_writes"]


def pixel_words(cfg: DPConfig, frames: np.ndarray) -> np.ndarray:
    """``pixels`` payloads (``uint64``) of ``frames`` ``(T, H, W)`` in raster order, with
    ``first`` on pixel (0, 0) of every frame."""
    frames = np.asarray(frames)
    first = np.zeros(frames.shape, dtype=np.int64)
    first[:, 0, 0] = 1
    return pack_array(pixel_layout(cfg), {"pixel": frames, "first": first}, "pixel").ravel()


def pack_pixels(cfg: DPConfig, frames: np.ndarray) -> list[int]:
    """:func:`pixel_words` as a list of Python ints (what cocotb drivers take)."""
    return [int(w) for w in pixel_words(cfg, frames)]


def lut_writes(cfg: DPConfig, codes) -> list[tuple[int, int]]:
    """(address, code) for every entry of the table, address
    :meth:`~dptbd.config.DPConfig.lut_address` ``(p, m)``."""
    arr = np.asarray(codes, dtype=np.int64)
    moves = cfg.n_moves
    return [(cfg.lut_address(p, m), int(arr[p, m])) for p in range(moves + 1) for m in range(moves)]
