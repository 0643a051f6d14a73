"""Cell-averaging CFAR, paper 004's single-frame comparison (16 reference cells, 2 guard cells).

Square-law CA-CFAR along one axis of a map (default: the delay/range axis, rows): each
cell under test (CUT) is compared with the mean power of ``n_ref`` reference cells,
``n_ref / 2`` on each side beyond ``n_guard / 2`` guard cells on each side (the counting
convention of MATLAB's ``phased.CFARDetector``, which 004 used: 16 training and 2 guard
cells in total). A cell is declared when

    z_CUT**2 > factor * mean(z_ref**2),   factor = N (Pfa**(-1/N) - 1)

which gives exactly ``Pfa`` for exponential (Rayleigh-magnitude) noise power.

Edges (``docs/detectors.md`` §2.3): near the ends of the axis the reference window is
not truncated but *completed on the other side*: the CUT keeps its guard cells and takes
the N cells nearest to it beyond them, as evenly split as the axis allows. Every cell
therefore averages exactly N reference cells and the threshold factor is the same
everywhere. The axis must hold at least ``N + n_guard + 1`` cells.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from dptbd.evaluation.detectors._checks import DetectorError, check_frames, check_int, check_prob

__all__ = ["ca_cfar_factor", "check_axis", "reference_counts", "ca_cfar_ratio", "ca_cfar_detect"]

AXES = (-2, -1)


def ca_cfar_factor(n_ref: int, pfa: float) -> float:
    """The CA-CFAR threshold multiplier ``N (Pfa**(-1/N) - 1)`` (square law, exponential noise)."""
    n = check_int("n_ref (reference cells)", n_ref, 2)
    pfa = check_prob("pfa", pfa)
    return n * (pfa ** (-1.0 / n) - 1.0)


def check_axis(axis: Any) -> int:
    """The CFAR axis: -2 (range, rows) or -1 (Doppler, columns)."""
    if isinstance(axis, bool) or not isinstance(axis, (int, np.integer)) or axis not in AXES:
        raise DetectorError(f"axis must be -2 (range, rows) or -1 (Doppler, columns), got {axis!r}")
    return int(axis)


def _check_window(n_ref: Any, n_guard: Any, length: int) -> tuple[int, int]:
    n_ref = check_int("n_ref (reference cells)", n_ref, 2)
    n_guard = check_int("n_guard (guard cells)", n_guard, 0)
    if n_ref % 2 or n_guard % 2:
        raise DetectorError(f"n_ref and n_guard count both sides and must be even, "
                            f"got n_ref={n_ref}, n_guard={n_guard}")
    if length < n_ref + n_guard + 1:
        raise DetectorError(f"the CFAR axis has {length} cells; n_ref={n_ref} reference and "
                            f"n_guard={n_guard} guard cells need at least {n_ref + n_guard + 1}")
    return n_ref, n_guard


def reference_counts(length: int, n_ref: int = 16, n_guard: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """``(left, right)`` reference cells of each CUT along an axis of ``length`` cells.

    ``left[i] + right[i] = n_ref`` always; ``left[i] = n_ref/2`` unless the axis runs out on
    one side, in which case the other side makes up the difference.
    """
    length = check_int("length", length, 1)
    n_ref, n_guard = _check_window(n_ref, n_guard, length)
    half, g = n_ref // 2, n_guard // 2
    i = np.arange(length)
    avail_l = np.maximum(i - g, 0)
    avail_r = np.maximum(length - 1 - i - g, 0)
    left = np.minimum(avail_l, half + np.maximum(half - avail_r, 0))
    return left, n_ref - left


def ca_cfar_ratio(frames: Any, *, n_ref: int = 16, n_guard: int = 2, axis: int = -2) -> np.ndarray:
    """``z_CUT**2 / mean(z_ref**2)`` for every cell of magnitude maps ``(..., I, J)``.

    ``axis`` is -2 (rows: delay/range, the default) or -1 (columns: Doppler).
    """
    axis = check_axis(axis)
    z = check_frames(frames, min_ndim=2, nonnegative=True)
    p = np.moveaxis(z * z, axis, -1)
    length = p.shape[-1]
    left, right = reference_counts(length, n_ref, n_guard)
    g = n_guard // 2
    i = np.arange(length)
    csum = np.concatenate([np.zeros(p.shape[:-1] + (1,)), np.cumsum(p, axis=-1)], axis=-1)
    lo = np.maximum(i - g, 0)  # one past the last left reference cell
    hi = np.minimum(i + g + 1, length)  # first right reference cell
    ref = (csum[..., lo] - csum[..., lo - left]) + (csum[..., hi + right] - csum[..., hi])
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(ref > 0, p * n_ref / ref, np.where(p > 0, np.inf, 0.0))
    return np.moveaxis(ratio, -1, axis)


def ca_cfar_detect(frames: Any, pfa: float, *, n_ref: int = 16, n_guard: int = 2,
                   axis: int = -2) -> np.ndarray:
    """Boolean detections: ratio > :func:`ca_cfar_factor` ``(n_ref, pfa)``."""
    return ca_cfar_ratio(frames, n_ref=n_ref, n_guard=n_guard, axis=axis) > ca_cfar_factor(n_ref, pfa)
