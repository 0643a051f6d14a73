"""Input words for the RTL: pixels packed with the gateware's layout, LUT writes at
``DPConfig.lut_address``."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.hw.layouts import pack_pixel
from dptbd.sim.stimulus import lut_writes, pack_pixels, pixel_words


def test_pixel_words_are_the_layout_s_words_with_first_on_every_frame_start():
    cfg = DPConfig(width=4, height=3, input_bits=6)
    frames = np.random.default_rng(0).integers(0, 64, size=(2, 3, 4))
    words = pixel_words(cfg, frames)
    assert words.dtype == np.uint64 and words.shape == (24,)
    want = [pack_pixel(cfg, int(v), i % 12 == 0) for i, v in enumerate(frames.ravel())]
    assert words.tolist() == want == pack_pixels(cfg, frames)


def test_pixel_words_refuse_a_pixel_wider_than_the_input():
    cfg = DPConfig(width=4, height=3, input_bits=6)
    with pytest.raises(ValueError, match=r"^pixel=64 does not fit 6 unsigned bits$"):
        pixel_words(cfg, np.full((1, 3, 4), 64))


def test_lut_writes_cover_the_table_at_lut_address():
    cfg = DPConfig(radius=1)
    codes = np.arange(cfg.lut_entries).reshape(cfg.n_moves + 1, cfg.n_moves)
    writes = lut_writes(cfg, codes)
    assert len(writes) == cfg.lut_entries
    assert writes == [(cfg.lut_address(p, m), int(codes[p, m]))
                      for p in range(cfg.n_moves + 1) for m in range(cfg.n_moves)]
    assert [a for a, _ in writes] == list(range(cfg.lut_entries))
