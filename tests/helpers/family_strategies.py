"""Hypothesis strategies for paper 000's DP family (``docs/arithmetic.md`` §8), shared by
``tests/model/family/``: ``test_init.py``, ``test_fast.py`` and ``test_oracle.py``."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from dptbd.weights import paper_weights, plain_weights
from helpers.model_strategies import make_cfg


@st.composite
def family_configs(draw, max_k=4, recursive=None, row_independent=False):
    """A small random §8 configuration: merit LUT, penalty LUT, forgetting, schedule.

    ``row_independent`` draws weight and penalty tables whose rows are all equal (the
    transition term does not depend on the predecessor's direction: the DP is exact).
    """
    radius = draw(st.sampled_from([1, 2]))
    n_moves = (2 * radius + 1) ** 2
    input_bits = draw(st.integers(1, 4))
    energy_bits = draw(st.integers(max(input_bits, 4), 10))
    top = 1 << (energy_bits - 1)
    merit = draw(arrays(np.int64, (1 << input_bits,), elements=st.integers(-top // 2, top // 2)))
    qbits = draw(st.integers(1, min(energy_bits, 6)))
    if row_independent:
        row = draw(arrays(np.int64, (n_moves,), elements=st.integers(0, (1 << qbits) - 1)))
        penalty = np.tile(row, (n_moves + 1, 1))
        frac = draw(st.integers(0, 4))
        wrow = draw(arrays(np.int64, (n_moves,), elements=st.integers(0, 1 << frac)))
        weights = np.tile(wrow, (n_moves + 1, 1)) / (1 << frac)
    else:
        penalty = draw(arrays(np.int64, (n_moves + 1, n_moves), elements=st.integers(0, (1 << qbits) - 1)))
        frac = draw(st.integers(0, 8))
        weights = draw(st.sampled_from([paper_weights(radius), plain_weights(radius)]))
    gbits = draw(st.integers(0, 6))
    code = draw(st.integers(1, 1 << gbits))
    rec = draw(st.booleans()) if recursive is None else recursive
    return make_cfg(
        height=draw(st.integers(3, 5)), width=draw(st.integers(3, 5)), radius=radius,
        segment_frames=draw(st.integers(1, max_k)), input_bits=input_bits,
        energy_bits=energy_bits, weight_frac_bits=frac, weights=weights,
        rounding=draw(st.sampled_from(["truncate", "half_up"])), merit_codes=merit,
        penalty_codes=penalty, penalty_bits=qbits, forgetting=code / (1 << gbits),
        forgetting_bits=gbits, recursive=rec)


def family_frames(draw, cfg, n_frames=None):
    """A sequence of pixel codes for ``cfg`` (K frames, or 1…5 when recursive)."""
    if n_frames is None:
        n_frames = draw(st.integers(1, 5)) if cfg.recursive else cfg.segment_frames
    return draw(arrays(np.int64, (n_frames, cfg.height, cfg.width),
                       elements=st.integers(0, cfg.pixel_max)))
