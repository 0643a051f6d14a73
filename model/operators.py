"""One small named helper per RTL operator of ``docs/arithmetic.md`` §7.

Plain integer numpy with explicit dtypes: every function here is the software twin of
one gateware block, so that the golden model reads like the datapath.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "INVALID",
    "check_pixels",
    "lookup_weight_code",
    "shift_right_rounded",
    "scale_by_weight",
    "argmax_lowest_index",
    "saturate_unsigned",
    "add_saturating",
    "saturated_sum",
    "predecessor",
]

#: Value of an invalid (out-of-image) candidate: below every valid candidate (>= 0).
INVALID = np.int64(-1)


def check_pixels(frames: np.ndarray, input_bits: int) -> np.ndarray:
    """Return ``frames`` as ``int64`` after checking every pixel is an unsigned B_in-bit integer.

    Raises
    ------
    TypeError
        The array is not of an integer dtype (floats are never silently rounded).
    ValueError
        A pixel is negative or does not fit ``input_bits`` bits.
    """
    arr = np.asarray(frames)
    if not np.issubdtype(arr.dtype, np.integer):
        raise TypeError(
            f"pixels must be an integer array of {input_bits}-bit unsigned values, "
            f"got dtype {arr.dtype}; quantise float scenes with dptbd.scenes.synthetic.quantise")
    if arr.size:
        lo, hi = int(arr.min()), int(arr.max())
        top = (1 << input_bits) - 1
        if lo < 0 or hi > top:
            raise ValueError(
                f"pixels must be in [0, {top}] for input_bits={input_bits}, "
                f"found values in [{lo}, {hi}]")
    return arr.astype(np.int64, copy=False)


def lookup_weight_code(codes: np.ndarray, direction: np.ndarray, move: int) -> np.ndarray:
    """Weight code ``c[min(d, M), m]`` of move ``m`` for predecessor directions ``d`` (§3).

    ``codes`` is the (M+1) x M table (``DPConfig.weight_codes``). A direction code above
    M = ``START`` (B_d bits can hold one; the DP never writes it) reads the ``START`` row M,
    like the gateware's weight LUT, which clamps its read address.
    """
    codes = np.asarray(codes)
    start = codes.shape[0] - 1
    return codes[np.minimum(np.asarray(direction, dtype=np.int64), start), move]


def shift_right_rounded(product: np.ndarray, frac_bits: int, mode: str) -> np.ndarray:
    """Divide by ``2**frac_bits``: ``"truncate"`` floors, ``"half_up"`` rounds half up."""
    product = np.asarray(product, dtype=np.int64)
    if frac_bits == 0:
        return product
    if mode == "truncate":
        return product >> frac_bits
    if mode == "half_up":
        return (product + (np.int64(1) << (frac_bits - 1))) >> frac_bits
    raise ValueError(f"rounding must be 'truncate' or 'half_up', got {mode!r}")


def scale_by_weight(energy: np.ndarray, code: np.ndarray, frac_bits: int, mode: str) -> np.ndarray:
    """Weighted candidate ``C = round(E * c / 2**F)`` (``docs/arithmetic.md`` §4.3)."""
    product = np.asarray(energy, dtype=np.int64) * np.asarray(code, dtype=np.int64)
    return shift_right_rounded(product, frac_bits, mode)


def argmax_lowest_index(candidates: np.ndarray, axis: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Max and argmax along ``axis``; ties go to the lowest index (§4.4).

    Invalid candidates carry :data:`INVALID` (-1), below every valid value, so they win
    only if every candidate is invalid (which the centre move rules out).
    """
    index = np.argmax(candidates, axis=axis)  # numpy returns the first maximum
    best = np.take_along_axis(candidates, np.expand_dims(index, axis), axis=axis)
    return np.squeeze(best, axis=axis), index


def saturate_unsigned(value: np.ndarray, bits: int) -> np.ndarray:
    """Clamp a non-negative value to ``2**bits - 1`` (never wraps)."""
    return np.minimum(np.asarray(value, dtype=np.int64), np.int64((1 << bits) - 1))


def add_saturating(a: np.ndarray, b: np.ndarray, bits: int) -> np.ndarray:
    """``min(a + b, 2**bits - 1)`` computed at full width (§4.5)."""
    return saturate_unsigned(np.asarray(a, dtype=np.int64) + np.asarray(b, dtype=np.int64), bits)


def saturated_sum(a: np.ndarray, b: np.ndarray, bits: int) -> np.ndarray:
    """Whether :func:`add_saturating` clips: ``a + b > 2**bits - 1`` (``bool``), the
    accumulator's ``saturated`` flag (``docs/arithmetic.md`` §4.5)."""
    return np.asarray(a, dtype=np.int64) + np.asarray(b, dtype=np.int64) > (1 << bits) - 1


def predecessor(state: np.ndarray, dy: int, dx: int, fill) -> np.ndarray:
    """``out[..., y, x] = state[..., y - dy, x - dx]``, ``fill`` where that is outside the image."""
    state = np.asarray(state)
    out = np.full_like(state, fill)
    height, width = state.shape[-2:]
    ys, yd = (slice(0, height - dy), slice(dy, height)) if dy >= 0 else (slice(-dy, height), slice(0, height + dy))
    xs, xd = (slice(0, width - dx), slice(dx, width)) if dx >= 0 else (slice(-dx, width), slice(0, width + dx))
    out[..., yd, xd] = state[..., ys, xs]
    return out
