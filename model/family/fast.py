"""Numba kernel of paper 000's DP family (``docs/arithmetic.md`` §8), bit-exact with
:mod:`dptbd.model.family` (checked by ``tests/model/family/test_fast.py``).

One compiled loop per frame over every trial, pixel and move, with the same integer
operations in the same order as the readable model: weighted candidate, penalty, max with
the lowest index on ties, forgetting, clamp at both ends. Public functions mirror the model:
:func:`fast_family_start`, :func:`fast_family_step`, :func:`run_family_fast`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from dptbd.config import DPConfig
from dptbd.model.family import check_family_sequence, family_start
from dptbd.model.fixed import DIRECTION_DTYPE, ENERGY_DTYPE
from dptbd.model.operators import check_pixels
from dptbd.model.schedule import run_schedule
from dptbd.model.segments import SegmentOutput

__all__ = ["fast_family_start", "fast_family_step", "run_family_fast"]

fast_family_start = family_start  # one table look-up and a clamp per pixel: numpy is fast


@njit(nogil=True, cache=True)
def _round_shift(p, bits, half_up):  # pragma: no cover - compiled
    if bits == 0:
        return p
    if half_up:
        p += np.int64(1) << (bits - 1)
    return p >> bits


@njit(nogil=True, cache=True)
def _family_kernel(e, d, x, merit, weights, penalties, moves, frac, alpha, alpha_bits,
                   half_up, e_max, start):  # pragma: no cover - compiled
    n_b, height, width = e.shape
    n_m = moves.shape[0]
    e_new = np.empty(e.shape, np.uint32)
    d_new = np.empty(e.shape, np.uint8)
    for b in range(n_b):
        for y in range(height):
            for xx in range(width):
                best = np.int64(0)
                arg = -1
                for m in range(n_m):
                    qy = y - moves[m, 0]
                    qx = xx - moves[m, 1]
                    if qy < 0 or qy >= height or qx < 0 or qx >= width:
                        continue
                    dq = min(np.int64(d[b, qy, qx]), start)
                    c = _round_shift(np.int64(e[b, qy, qx]) * weights[dq, m], frac, half_up)
                    v = c - penalties[dq, m]
                    if arg < 0 or v > best:
                        best = v
                        arg = m
                total = _round_shift(best * alpha, alpha_bits, half_up) + merit[x[b, y, xx]]
                if total < 0:
                    total = 0
                elif total > e_max:
                    total = e_max
                e_new[b, y, xx] = total
                d_new[b, y, xx] = arg
    return e_new, d_new


def fast_family_step(energy: np.ndarray, direction: np.ndarray, pixels: np.ndarray,
                     cfg: DPConfig) -> tuple[np.ndarray, np.ndarray]:
    """One frame of §8.7 (same arguments, results and errors as
    :func:`dptbd.model.family.family_step`)."""
    x = check_pixels(pixels, cfg.input_bits)
    shape = x.shape
    flat = (-1,) + shape[-2:]
    e = np.ascontiguousarray(np.broadcast_to(energy, shape), dtype=ENERGY_DTYPE).reshape(flat)
    d = np.ascontiguousarray(np.broadcast_to(direction, shape), dtype=DIRECTION_DTYPE).reshape(flat)
    e_new, d_new = _family_kernel(
        e, d, np.ascontiguousarray(x.reshape(flat)), cfg.merit_code_array,
        cfg.weight_codes.astype(np.int64), cfg.penalty_code_array, cfg.moves,
        cfg.weight_frac_bits, np.int64(cfg.forgetting_code), cfg.forgetting_bits,
        cfg.rounding == "half_up", np.int64(cfg.e_max), np.int64(cfg.start_code))
    return e_new.reshape(shape), d_new.reshape(shape)


def run_family_fast(frames: np.ndarray, cfg: DPConfig) -> SegmentOutput:
    """:func:`dptbd.model.family.run_family_fixed`, compiled."""
    arr = check_family_sequence(frames, cfg)
    check_pixels(arr, cfg.input_bits)
    return run_schedule(arr, cfg, start=lambda x: fast_family_start(x, cfg),
                        step=lambda e, d, x: fast_family_step(e, d, x, cfg),
                        energy_dtype=ENERGY_DTYPE)
