"""The RTL operators paper 000's DP family adds to the datapath (``docs/arithmetic.md`` §8).

Plain integer numpy, ``int64`` throughout, one helper per gateware block, beside
:mod:`dptbd.model.operators` (whose weight multiplier, max tree and predecessor window the
family reuses unchanged).
"""

from __future__ import annotations

import numpy as np

from dptbd.model.operators import lookup_weight_code, shift_right_rounded

__all__ = [
    "INVALID_SIGNED",
    "lookup_merit_code",
    "lookup_penalty_code",
    "subtract_penalty",
    "scale_by_forgetting",
    "add_clamped",
]

#: Value of an invalid (out-of-image) candidate once candidates are signed: below every
#: valid one (a valid candidate is at least ``-(2**B_Q - 1)`` >= ``-(2**32 - 1)``).
INVALID_SIGNED = np.int64(-(1 << 62))


def lookup_merit_code(merit_codes: np.ndarray, pixels: np.ndarray) -> np.ndarray:
    """Merit LUT (§8.1): ``P = merit_codes[x]``, a signed code per B_in-bit pixel code."""
    return np.asarray(merit_codes, dtype=np.int64)[np.asarray(pixels, dtype=np.int64)]


def lookup_penalty_code(penalty_codes: np.ndarray, direction: np.ndarray, move: int) -> np.ndarray:
    """Penalty LUT (§8.2): ``Qc[min(d, M), m]``, addressed exactly like the weight LUT
    (:func:`~dptbd.model.operators.lookup_weight_code`: a d above M reads the START row)."""
    return lookup_weight_code(penalty_codes, direction, move)


def subtract_penalty(weighted: np.ndarray, penalty: np.ndarray) -> np.ndarray:
    """Penalised candidate (§8.3): ``V = C - Qc``, signed and exact (``max(B_E, B_Q) + 1`` bits)."""
    return np.asarray(weighted, dtype=np.int64) - np.asarray(penalty, dtype=np.int64)


def scale_by_forgetting(value: np.ndarray, code: int, frac_bits: int, mode: str) -> np.ndarray:
    """Forgetting multiplier (§8.4): ``round(V * a / 2**G)`` on a signed V.

    ``truncate`` floors (an arithmetic right shift: towards minus infinity for a negative
    V), ``half_up`` adds ``2**(G-1)`` first. ``a = 2**G`` (alpha = 1) returns V exactly.
    """
    product = np.asarray(value, dtype=np.int64) * np.int64(code)
    return shift_right_rounded(product, frac_bits, mode)


def add_clamped(value: np.ndarray, merit: np.ndarray, bits: int) -> np.ndarray:
    """Accumulate and saturate at both ends (§8.5): ``min(max(V + P, 0), 2**bits - 1)``."""
    total = np.asarray(value, dtype=np.int64) + np.asarray(merit, dtype=np.int64)
    return np.clip(total, np.int64(0), np.int64((1 << bits) - 1))
