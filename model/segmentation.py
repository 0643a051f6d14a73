"""Histogram segmentation for a constant false-alarm count (paper 001 §2, last paragraph).

``docs/arithmetic.md`` §6: on an accumulated image keep the pixels whose E is strictly
greater than the (n+1)-th largest E, i.e. the histogram threshold "the smallest level
whose count from the top does not exceed n". At most n candidates; ties at the
boundary are excluded, never broken arbitrarily. Works on float and integer images
alike, with any leading (segment, trial) axes.
"""

from __future__ import annotations

import numpy as np

__all__ = ["candidate_dtype", "count_for_rate", "threshold_level", "candidate_mask", "candidates"]


def candidate_dtype(energy_dtype) -> np.dtype:
    """One candidate point record, as the FPGA hands it to the DSP: (row, col, E, d).

    E keeps the accumulated image's dtype (``uint32`` fixed point, ``float64`` float).
    """
    return np.dtype([("row", np.uint16), ("col", np.uint16),
                     ("energy", np.dtype(energy_dtype)), ("direction", np.uint8)])


def count_for_rate(rate: float, n_pixels: int) -> int:
    """The candidate count n for a false-alarm rate: ``round(rate * n_pixels)`` (half up).

    0.2 % of 128 x 128 gives 33 (paper 001 quotes "0.2 %, i.e. 35 false points").
    """
    if not np.isfinite(rate) or not 0.0 <= rate <= 1.0:
        raise ValueError(f"false-alarm rate must be in [0, 1], got {rate!r}")
    if n_pixels < 1:
        raise ValueError(f"n_pixels must be >= 1, got {n_pixels}")
    return int(np.floor(rate * n_pixels + 0.5))


def threshold_level(image: np.ndarray, count: int) -> np.ndarray:
    """The (n+1)-th largest value of each image (``-inf`` when n >= H*W).

    Parameters
    ----------
    image : numpy.ndarray
        ``(..., H, W)`` accumulated images.
    count : int
        n, the largest number of candidates wanted per image.
    """
    flat = np.asarray(image).reshape(np.shape(image)[:-2] + (-1,))
    n_pix = flat.shape[-1]
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 0:
        raise ValueError(f"candidate count must be an integer >= 0, got {count!r}")
    if count >= n_pix:
        return np.full(flat.shape[:-1], -np.inf)
    kth = n_pix - count - 1  # ascending position of the (n+1)-th largest
    return np.partition(flat, kth, axis=-1)[..., kth]


def candidate_mask(image: np.ndarray, count: int) -> np.ndarray:
    """Boolean ``(..., H, W)``: the pixels kept by the threshold (at most ``count`` per image)."""
    level = threshold_level(image, count)
    return np.asarray(image) > level[..., None, None]


def candidates(energy: np.ndarray, direction: np.ndarray, count: int) -> np.ndarray:
    """The candidate point list of ONE accumulated image, in raster order.

    Returns
    -------
    numpy.ndarray
        Records of :func:`candidate_dtype`: (row, col, E, d).
    """
    energy = np.asarray(energy)
    if energy.ndim != 2 or np.shape(direction) != energy.shape:
        raise ValueError(
            f"energy and direction must be two images of the same shape (H, W), "
            f"got {energy.shape} and {np.shape(direction)}")
    rows, cols = np.nonzero(candidate_mask(energy, count))
    out = np.zeros(len(rows), dtype=candidate_dtype(energy.dtype))
    out["row"], out["col"] = rows, cols
    out["energy"] = energy[rows, cols]
    out["direction"] = np.asarray(direction)[rows, cols]
    return out
