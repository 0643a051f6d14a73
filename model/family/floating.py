"""Float counterpart of paper 000's DP family (``docs/arithmetic.md`` §8), in ``float64``.

Same recursion, moves, edges, tie-break and schedule as :mod:`dptbd.model.family`, with the
real weight LUT, the real forgetting factor alpha (not its code), no rounding and no
saturation (no clamp at either end)::

    h_1 = P(x),   h_k = P(x) + alpha * max_m [ w[d(q), m] * h_{k-1}(q_m) - Q[d(q), m] ]

``merit`` (a real table over the pixel codes) and ``penalty`` (a real ``(M + 1, M)`` table)
default to the configuration's codes read as reals; paper 000's unquantised variants pass
their own (e.g. ``dptbd.evaluation.detectors.unified`` merits on the codes' measurements).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from dptbd.config import DPConfig
from dptbd.weights import check_move_table
from dptbd.model.family import check_family_sequence
from dptbd.model.operators import argmax_lowest_index, predecessor
from dptbd.model.schedule import run_schedule
from dptbd.model.segments import SegmentOutput

__all__ = ["FloatFamily", "float_family_tables", "run_family_float"]

FloatFamily = tuple[np.ndarray, np.ndarray]


def float_family_tables(cfg: DPConfig, merit: Any = None, penalty: Any = None) -> FloatFamily:
    """The real merit table ``(2**B_in,)`` and penalty table ``(M + 1, M)`` of a run."""
    entries = 1 << cfg.input_bits
    p = cfg.merit_code_array.astype(np.float64) if merit is None else np.asarray(merit, dtype=np.float64)
    if p.shape != (entries,) or not np.all(np.isfinite(p)):
        raise ValueError(f"merit must be {entries} finite reals (one per {cfg.input_bits}-bit "
                         f"pixel code), got shape {p.shape}")
    q = cfg.penalty_code_array.astype(np.float64) if penalty is None else check_move_table(
        "penalty", penalty, cfg.radius)
    return p, q


def _start(x: np.ndarray, cfg: DPConfig, tables: FloatFamily):
    return tables[0][x], np.full(x.shape, cfg.start_code, dtype=np.uint8)


def _step(energy, direction, x, cfg: DPConfig, tables: FloatFamily):
    merit, penalty = tables
    weights = cfg.weight_array
    d_prev = np.asarray(direction, dtype=np.int64)
    candidates = np.empty((cfg.n_moves,) + x.shape, dtype=np.float64)
    for m, (dy, dx) in enumerate(cfg.moves):
        e_q = predecessor(np.asarray(energy, dtype=np.float64), dy, dx, fill=np.nan)
        d_q = np.minimum(predecessor(d_prev, dy, dx, fill=cfg.start_code), cfg.start_code)
        value = weights[d_q, m] * np.nan_to_num(e_q) - penalty[d_q, m]
        candidates[m] = np.where(np.isnan(e_q), -np.inf, value)
    best, move = argmax_lowest_index(candidates, axis=0)
    return merit[x] + cfg.forgetting * best, move.astype(np.uint8)


def run_family_float(frames: np.ndarray, cfg: DPConfig, merit: Any = None,
                     penalty: Any = None) -> SegmentOutput:
    """The family in float64 over pixel codes ``(..., T, H, W)`` (segments or recursive)."""
    arr = check_family_sequence(frames, cfg)
    if not np.issubdtype(arr.dtype, np.integer) or (arr.size and (arr.min() < 0 or arr.max() > cfg.pixel_max)):
        raise ValueError(f"frames must be pixel codes in [0, {cfg.pixel_max}] (integers)")
    x = arr.astype(np.int64)
    tables = float_family_tables(cfg, merit, penalty)
    return run_schedule(x, cfg, start=lambda f: _start(f, cfg, tables),
                        step=lambda e, d, f: _step(e, d, f, cfg, tables), energy_dtype=np.float64)
