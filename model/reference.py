"""Float reference of the direction-weighted DP (paper 001 eqs (8)-(11)).

Same recursion, move order, edges, tie-break and segments as the fixed-point model
(``docs/arithmetic.md``), in ``float64`` with the real-valued weight LUT, no weight
quantisation and no saturation.
"""

from __future__ import annotations

import numpy as np

from dptbd.config import DPConfig
from dptbd.model.operators import argmax_lowest_index, predecessor
from dptbd.model.segments import SegmentOutput, check_sequence, run_segments

__all__ = ["float_start", "float_step", "run_float"]


def _check_real(pixels: np.ndarray) -> np.ndarray:
    arr = np.asarray(pixels)
    if not (np.issubdtype(arr.dtype, np.integer) or np.issubdtype(arr.dtype, np.floating)):
        raise TypeError(f"pixels must be a real numeric array, got dtype {arr.dtype}")
    arr = arr.astype(np.float64, copy=False)
    if not np.all(np.isfinite(arr)):
        raise ValueError("pixels must be finite; found NaN or inf")
    return arr


def float_start(pixels: np.ndarray, cfg: DPConfig) -> tuple[np.ndarray, np.ndarray]:
    """State after a segment's first frame: E = x, d = START."""
    cfg.require_paper001_datapath("dptbd.model.reference")
    x = _check_real(pixels)
    return x.copy(), np.full(x.shape, cfg.start_code, dtype=np.uint8)


def float_step(energy: np.ndarray, direction: np.ndarray, pixels: np.ndarray,
               cfg: DPConfig) -> tuple[np.ndarray, np.ndarray]:
    """One frame of eq (10): max over moves of w[d(q), m] * E(q), plus the new pixel."""
    cfg.require_paper001_datapath("dptbd.model.reference")
    x = _check_real(pixels)
    weights = cfg.weight_array
    d_prev = np.asarray(direction, dtype=np.int64)
    candidates = np.empty((cfg.n_moves,) + x.shape, dtype=np.float64)
    for m, (dy, dx) in enumerate(cfg.moves):
        e_q = predecessor(np.asarray(energy, dtype=np.float64), dy, dx, fill=np.nan)
        d_q = predecessor(d_prev, dy, dx, fill=cfg.start_code)
        candidates[m] = np.where(np.isnan(e_q), -np.inf, weights[d_q, m] * np.nan_to_num(e_q))
    best, move = argmax_lowest_index(candidates, axis=0)
    return best + x, move.astype(np.uint8)


def run_float(frames: np.ndarray, cfg: DPConfig) -> SegmentOutput:
    """Accumulate a sequence ``(..., T, H, W)`` segment by segment, in float64."""
    arr = _check_real(check_sequence(frames, cfg))
    return run_segments(
        arr, cfg,
        start=lambda x: float_start(x, cfg),
        step=lambda e, d, x: float_step(e, d, x, cfg),
        energy_dtype=np.float64)
