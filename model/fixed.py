"""Bit-accurate fixed-point golden model of the direction-weighted DP (paper 001 eqs (8)-(11)).

Implements ``docs/arithmetic.md`` exactly; the gateware in ``dptbd.hw`` is scoreboarded
against it. This is the readable reference: plain integer numpy, one named operator per
RTL block (``dptbd.model.operators``). ``dptbd.model.fast`` holds a fused compiled kernel
checked against it bit for bit.
"""

from __future__ import annotations

import numpy as np

from dptbd.config import DPConfig
from dptbd.model.operators import (
    INVALID,
    add_saturating,
    argmax_lowest_index,
    check_pixels,
    lookup_weight_code,
    predecessor,
    scale_by_weight,
)
from dptbd.model.segments import SegmentOutput, check_sequence, run_segments

__all__ = ["segment_start", "dp_step", "run_fixed"]

ENERGY_DTYPE = np.uint32
DIRECTION_DTYPE = np.uint8


def segment_start(pixels: np.ndarray, cfg: DPConfig) -> tuple[np.ndarray, np.ndarray]:
    """State after a segment's first frame: E = x, d = START (§5)."""
    cfg.require_paper001_datapath("dptbd.model.fixed")
    x = check_pixels(pixels, cfg.input_bits)
    energy = add_saturating(0, x, cfg.energy_bits).astype(ENERGY_DTYPE)
    direction = np.full(x.shape, cfg.start_code, dtype=DIRECTION_DTYPE)
    return energy, direction


def dp_step(energy: np.ndarray, direction: np.ndarray, pixels: np.ndarray,
            cfg: DPConfig) -> tuple[np.ndarray, np.ndarray]:
    """One frame of eq (10) in fixed point (§4), on arrays of shape ``(..., H, W)``.

    Parameters
    ----------
    energy, direction : numpy.ndarray
        The previous frame's state (E, d). A d above M = ``START`` (only from a corrupted
        state) weighs like ``START`` (:func:`~dptbd.model.operators.lookup_weight_code`).
    pixels : numpy.ndarray
        The new frame, unsigned ``input_bits``-bit integers.

    Returns
    -------
    tuple of numpy.ndarray
        The new (E, d), ``uint32`` and ``uint8``.
    """
    cfg.require_paper001_datapath("dptbd.model.fixed")
    x = check_pixels(pixels, cfg.input_bits)
    codes = cfg.weight_codes.astype(np.int64)
    e_prev = np.asarray(energy, dtype=np.int64)
    d_prev = np.asarray(direction, dtype=np.int64)
    candidates = np.empty((cfg.n_moves,) + x.shape, dtype=np.int64)
    for m, (dy, dx) in enumerate(cfg.moves):
        e_q = predecessor(e_prev, dy, dx, fill=-1)
        d_q = predecessor(d_prev, dy, dx, fill=cfg.start_code)
        code = lookup_weight_code(codes, d_q, m)
        weighted = scale_by_weight(np.maximum(e_q, 0), code, cfg.weight_frac_bits, cfg.rounding)
        candidates[m] = np.where(e_q < 0, INVALID, weighted)
    best, move = argmax_lowest_index(candidates, axis=0)
    new_energy = add_saturating(best, x, cfg.energy_bits).astype(ENERGY_DTYPE)
    return new_energy, move.astype(DIRECTION_DTYPE)


def run_fixed(frames: np.ndarray, cfg: DPConfig) -> SegmentOutput:
    """Accumulate a sequence ``(..., T, H, W)`` segment by segment (§5).

    Leading axes are independent trials (batches). Returns the accumulated image and
    direction map of every whole segment.
    """
    arr = check_sequence(frames, cfg)
    check_pixels(arr, cfg.input_bits)
    return run_segments(
        arr, cfg,
        start=lambda x: segment_start(x, cfg),
        step=lambda e, d, x: dp_step(e, d, x, cfg),
        energy_dtype=ENERGY_DTYPE)
