"""The integer form of paper 000's unified recursion (25)-(26) on paper 001's datapath.

``E_k = min(max_m [E_{k-1}(q_m) - penalty[d(q_m), m]] + merit[x], E_max)``: a merit LUT on
the input pixel code and an additive (subtracted) penalty LUT in place of 001's weight
multiplier (:func:`quantise_unified` builds them from a float merit and transition table;
:func:`run_unified_fixed` runs them). It is the independent reference the tests hold the
golden model's §8 family (``dptbd.model.family.fast``) and the family gateware against
(``docs/arithmetic.md`` §8.9, ``docs/detectors.md`` §1.3); the float recursion is
:mod:`dptbd.evaluation.detectors.unified`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numba
import numpy as np

from dptbd.evaluation.detectors._checks import DetectorError, check_int, check_real
from dptbd.evaluation.detectors.merits import Merit
from dptbd.evaluation.detectors.transitions import check_transition
from dptbd.weights import move_offsets

__all__ = ["FixedUnified", "quantise_unified", "run_unified_fixed"]


@numba.njit(cache=True)
def _fixed_step(e, d, pc, qc, moves, e_max):  # pragma: no cover - compiled
    n_b, height, width = e.shape
    n_m = moves.shape[0]
    e_new = np.empty_like(e)
    d_new = np.empty(d.shape, np.uint8)
    for b in range(n_b):
        for y in range(height):
            for x in range(width):
                best = np.int64(0)
                arg = -1
                for m in range(n_m):
                    yy = y - moves[m, 0]
                    xx = x - moves[m, 1]
                    if yy < 0 or yy >= height or xx < 0 or xx >= width:
                        continue
                    c = e[b, yy, xx] - qc[d[b, yy, xx], m]
                    if arg < 0 or c > best:
                        best = c
                        arg = m
                v = best + pc[b, y, x]
                e_new[b, y, x] = e_max if v > e_max else v
                d_new[b, y, x] = arg
    return e_new, d_new


@dataclasses.dataclass(frozen=True)
class FixedUnified:
    """Integer LUTs of the unified recursion on paper 001's datapath.

    ``E_k = min(max_m [E_{k-1}(q_m) - penalty[d(q_m), m]] + merit[x], E_max)``: a merit
    LUT indexed by the B_in-bit pixel code and an additive (subtracted) penalty LUT in
    place of 001's weight multiplier. Both are unsigned; ``merit.min() >= penalty.max()``
    so that no candidate is ever negative (no sign bit in the datapath).

    Attributes
    ----------
    merit_codes : numpy.ndarray
        ``int64 (2**B_in,)``: ``round(scale * (P(z(x)) + bias))``.
    penalty_codes : numpy.ndarray
        ``int64 (M + 1, M)``: ``round(scale * (max Q - Q))``.
    scale, bias, q_max : float
        ``E_k ≈ scale * (h_k + (k + 1) * bias - k * q_max)`` (k = frame index from 0),
        exact when the scaled merits and penalties are integers and nothing saturates.
    input_bits, energy_bits, radius : int
    """

    merit_codes: np.ndarray
    penalty_codes: np.ndarray
    scale: float
    bias: float
    q_max: float
    input_bits: int
    energy_bits: int
    radius: int

    def threshold_code(self, v_t: float, n_frames: int) -> int:
        """The integer threshold equivalent to ``h > v_t`` after ``n_frames`` frames (floor).

        Parameters
        ----------
        v_t : float
            The threshold V_T on the float scale of h, a finite real number.
        n_frames : int
            Frames accumulated, >= 1.
        """
        v_t = check_real("v_t (threshold V_T)", v_t)
        k = check_int("n_frames", n_frames, 1) - 1
        return int(math.floor(self.scale * (v_t + (k + 1) * self.bias - k * self.q_max)))

    def to_float(self, energy: np.ndarray, n_frames: int) -> np.ndarray:
        """Map accumulated codes back to the float scale of h (``n_frames >= 1``)."""
        k = check_int("n_frames", n_frames, 1) - 1
        return np.asarray(energy, dtype=np.float64) / self.scale - (k + 1) * self.bias + k * self.q_max


def quantise_unified(merit: Merit, transition: Any, *, radius: int = 2, input_bits: int = 8,
                     gain: float = 1.0, offset: float = 0.0, scale: float = 1.0,
                     energy_bits: int = 16) -> FixedUnified:
    """Build the integer LUTs for a merit and transition table.

    A pixel code ``x`` stands for the measurement ``z = (x - offset) / gain`` (the inverse
    of :func:`dptbd.scenes.synthetic.quantise`). Merit and penalty are scaled by ``scale``
    and rounded half up.
    """
    bits = check_int("input_bits", input_bits, 1, 16)
    ebits = check_int("energy_bits", energy_bits, bits, 32)
    gain = check_real("gain", gain, 0.0, lo_open=True)
    offset = check_real("offset", offset)
    scale = check_real("scale", scale, 0.0, lo_open=True)
    radius = check_int("radius", radius, 1, 2)
    q = check_transition(transition, radius)
    z = (np.arange(1 << bits, dtype=np.float64) - offset) / gain
    p = merit(z)
    q_max = float(q.max())
    penalty = q_max - q
    bias = float(penalty.max() - p.min())
    merit_codes = np.floor(scale * (p + bias) + 0.5).astype(np.int64)
    penalty_codes = np.floor(scale * penalty + 0.5).astype(np.int64)
    if merit_codes.max() >= (1 << ebits):
        raise DetectorError(f"energy_bits={ebits} cannot hold a merit code of {merit_codes.max()}")
    # rounding can break merit >= penalty by one code; lift the merit LUT if so
    lift = max(0, int(penalty_codes.max() - merit_codes.min()))
    merit_codes += lift
    return FixedUnified(merit_codes, penalty_codes, scale, bias + lift / scale, q_max, bits, ebits, radius)


def run_unified_fixed(codes: Any, luts: FixedUnified) -> tuple[np.ndarray, np.ndarray]:
    """The integer datapath form of eqs (25)-(26) on pixel codes ``(..., T, H, W)``.

    Returns the accumulated codes ``E`` (``int64``) and arrival moves ``d`` (``uint8``),
    each ``(..., H, W)``. Saturates at ``2**energy_bits - 1``.
    """
    arr = np.asarray(codes)
    if not np.issubdtype(arr.dtype, np.integer):
        raise DetectorError(f"codes must be integer pixel codes, got dtype {arr.dtype}")
    if arr.ndim < 3:
        raise DetectorError(f"codes must have shape (..., T, H, W), got shape {arr.shape}")
    top = (1 << luts.input_bits) - 1
    if arr.size and (arr.min() < 0 or arr.max() > top):
        raise DetectorError(f"codes must be in [0, {top}] for input_bits={luts.input_bits}, "
                            f"found [{arr.min()}, {arr.max()}]")
    lead, (n_t, height, width) = arr.shape[:-3], arr.shape[-3:]
    x = arr.reshape((-1, n_t, height, width)).astype(np.int64)
    moves = move_offsets(luts.radius)
    e_max = np.int64((1 << luts.energy_bits) - 1)
    pc = luts.merit_codes[x]
    e = np.minimum(pc[:, 0], e_max)
    d = np.full(e.shape, len(moves), dtype=np.uint8)
    for t in range(1, n_t):
        e, d = _fixed_step(e, d, np.ascontiguousarray(pc[:, t]), luts.penalty_codes, moves, e_max)
    return e.reshape(lead + (height, width)), d.reshape(lead + (height, width))
