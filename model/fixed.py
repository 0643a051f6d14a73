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
    saturated_sum,
    scale_by_weight,
)
from dptbd.model.segments import SegmentOutput, check_sequence, run_segments
from dptbd.model.settings import Schedule, check_schedule, settings_of_segment

__all__ = ["segment_start", "dp_step", "dp_step_saturated", "run_fixed", "frame_segments",
           "saturation_counts"]

ENERGY_DTYPE = np.uint32
DIRECTION_DTYPE = np.uint8


def segment_start(pixels: np.ndarray, cfg: DPConfig) -> tuple[np.ndarray, np.ndarray]:
    """State after a segment's first frame: E = x, d = START (§5)."""
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
    new_energy, move, _ = dp_step_saturated(energy, direction, pixels, cfg)
    return new_energy, move


def dp_step_saturated(energy: np.ndarray, direction: np.ndarray, pixels: np.ndarray,
                      cfg: DPConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`dp_step` and, third, where the accumulator clipped E at E_max (``bool``): the
    gateware's ``saturated`` event for each word (§4.5, ``saturated_sum``)."""
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
    return new_energy, move.astype(DIRECTION_DTYPE), saturated_sum(best, x, cfg.energy_bits)


def run_fixed(frames: np.ndarray, cfg: DPConfig, schedule: Schedule | None = None
              ) -> SegmentOutput:
    """Accumulate a sequence ``(..., T, H, W)`` segment by segment (§5).

    Leading axes are independent trials (batches). Returns the accumulated image and
    direction map of every whole segment. ``schedule``: run-time settings per segment
    (:mod:`dptbd.model.settings`; only K matters here), consecutive segments of K_j frames.
    """
    arr = check_sequence(frames, cfg, schedule)
    check_pixels(arr, cfg.input_bits)
    return run_segments(
        arr, cfg,
        start=lambda x: segment_start(x, cfg),
        step=lambda e, d, x: dp_step(e, d, x, cfg),
        energy_dtype=ENERGY_DTYPE, schedule=schedule)


def frame_segments(cfg: DPConfig, n_frames: int, schedule: Schedule | None = None
                   ) -> np.ndarray:
    """``(T, 2)`` ``int64``: for each frame as the gateware counts it from reset, its
    segment (from 0) and its frame within that segment; segments are consecutive, K_j
    frames each (the last may be partial)."""
    entries = check_schedule(cfg, schedule)
    out = np.zeros((n_frames, 2), dtype=np.int64)
    segment = k = 0
    for t in range(n_frames):
        out[t] = segment, k
        k += 1
        if k == settings_of_segment(entries, segment).segment_frames:
            segment, k = segment + 1, 0
    return out


def saturation_counts(frames: np.ndarray, cfg: DPConfig, schedule: Schedule | None = None
                      ) -> np.ndarray:
    """How many state words the accumulator clipped at E_max in each frame, ``(..., T)``
    ``int64``: what the gateware's ``saturated`` event counts per frame. Every frame counts,
    also those of a trailing partial segment (the DP outputs them too); a segment's first
    frame never saturates (E = x <= 2**B_in - 1 <= E_max)."""
    arr = check_sequence(frames, cfg, schedule)
    check_pixels(arr, cfg.input_bits)
    where = frame_segments(cfg, arr.shape[-3], schedule)
    counts = np.zeros(arr.shape[:-2], dtype=np.int64)
    energy = direction = None
    for t, (_, k) in enumerate(where):
        if k == 0:
            energy, direction = segment_start(arr[..., t, :, :], cfg)
            continue
        energy, direction, clipped = dp_step_saturated(energy, direction, arr[..., t, :, :], cfg)
        counts[..., t] = clipped.sum(axis=(-2, -1))
    return counts
