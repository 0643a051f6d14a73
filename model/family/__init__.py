"""Bit-accurate golden model of paper 000's DP family on 001's datapath (``docs/arithmetic.md`` §8).

One pixel update, operator by operator (§8.7)::

    P    = merit[x]                                   merit LUT            (000 eq (25): P)
    C_m  = round_F(E(q_m) * c[d(q_m), m])              weight multiplier    (001 eq (10))
    V_m  = C_m - Qc[d(q_m), m]                          penalty subtractor   (000 eqs (22), (24): Q)
    V, d = max / lowest argmax over valid m             max tree
    E    = clamp(round_G(a * V) + P, 0, E_max)          forgetting, adder, clamp

and a segment's (or the recursion's) first frame is ``E = clamp(P, 0, E_max)``, d = START
(000 eq (26)). With the §8 fields at their defaults this is :mod:`dptbd.model.fixed` bit
for bit (tested). :mod:`dptbd.model.family.fast` is its numba kernel.
"""

from __future__ import annotations

import numpy as np

from dptbd.config import DPConfig
from dptbd.model.family.operators import (
    INVALID_SIGNED,
    add_clamped,
    lookup_merit_code,
    lookup_penalty_code,
    scale_by_forgetting,
    subtract_penalty,
)
from dptbd.model.fixed import DIRECTION_DTYPE, ENERGY_DTYPE
from dptbd.model.operators import (
    argmax_lowest_index,
    check_pixels,
    lookup_weight_code,
    predecessor,
    scale_by_weight,
)
from dptbd.model.schedule import run_schedule
from dptbd.model.segments import SegmentOutput, check_sequence

__all__ = ["family_start", "family_step", "run_family_fixed", "check_family_sequence"]


def check_family_sequence(frames: np.ndarray, cfg: DPConfig) -> np.ndarray:
    """Shape check of a sequence ``(..., T, H, W)``: K frames at least, or one when recursive."""
    return check_sequence(frames, cfg.replace(segment_frames=1) if cfg.recursive else cfg)


def family_start(pixels: np.ndarray, cfg: DPConfig) -> tuple[np.ndarray, np.ndarray]:
    """First frame of a segment or of the recursion: ``E = clamp(P, 0, E_max)``, d = START."""
    x = check_pixels(pixels, cfg.input_bits)
    merit = lookup_merit_code(cfg.merit_code_array, x)
    energy = add_clamped(0, merit, cfg.energy_bits).astype(ENERGY_DTYPE)
    return energy, np.full(x.shape, cfg.start_code, dtype=DIRECTION_DTYPE)


def family_step(energy: np.ndarray, direction: np.ndarray, pixels: np.ndarray,
                cfg: DPConfig) -> tuple[np.ndarray, np.ndarray]:
    """One frame of §8.7 on arrays ``(..., H, W)``; returns the new (E, d), ``uint32``/``uint8``."""
    x = check_pixels(pixels, cfg.input_bits)
    merit = lookup_merit_code(cfg.merit_code_array, x)
    weights = cfg.weight_codes.astype(np.int64)
    penalties = cfg.penalty_code_array
    e_prev = np.asarray(energy, dtype=np.int64)
    d_prev = np.asarray(direction, dtype=np.int64)
    candidates = np.empty((cfg.n_moves,) + x.shape, dtype=np.int64)
    for m, (dy, dx) in enumerate(cfg.moves):
        e_q = predecessor(e_prev, dy, dx, fill=-1)
        d_q = predecessor(d_prev, dy, dx, fill=cfg.start_code)
        weighted = scale_by_weight(np.maximum(e_q, 0), lookup_weight_code(weights, d_q, m),
                                   cfg.weight_frac_bits, cfg.rounding)
        value = subtract_penalty(weighted, lookup_penalty_code(penalties, d_q, m))
        candidates[m] = np.where(e_q < 0, INVALID_SIGNED, value)
    best, move = argmax_lowest_index(candidates, axis=0)
    faded = scale_by_forgetting(best, cfg.forgetting_code, cfg.forgetting_bits, cfg.rounding)
    new_energy = add_clamped(faded, merit, cfg.energy_bits).astype(ENERGY_DTYPE)
    return new_energy, move.astype(DIRECTION_DTYPE)


def run_family_fixed(frames: np.ndarray, cfg: DPConfig) -> SegmentOutput:
    """The family over a sequence ``(..., T, H, W)``: K-frame segments, or every frame when
    ``cfg.recursive`` (:func:`~dptbd.model.schedule.run_schedule`)."""
    arr = check_family_sequence(frames, cfg)
    check_pixels(arr, cfg.input_bits)
    return run_schedule(arr, cfg, start=lambda x: family_start(x, cfg),
                        step=lambda e, d, x: family_step(e, d, x, cfg), energy_dtype=ENERGY_DTYPE)
