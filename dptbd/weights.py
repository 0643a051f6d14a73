"""The tables indexed by move: the move offsets of the search window and the weight LUTs
built from them.

:func:`move_offsets` numbers the moves of the ``(2r+1) x (2r+1)`` window
(``docs/arithmetic.md`` §2); :func:`paper_weights` (paper 001 eq (11)) and
:func:`plain_weights` (eq (8), plain DP) build the ``(M + 1, M)`` weight LUT indexed
``[predecessor direction, move]``; :func:`check_move_table` checks any table of that shape
(the weight LUT of :class:`~dptbd.config.DPConfig`, paper 000's transition term).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from dptbd.errors import ConfigError, DptbdError, interval

__all__ = ["move_offsets", "paper_weights", "plain_weights", "check_move_table"]


def move_offsets(radius: int) -> np.ndarray:
    """The moves of the search window, in move-index order.

    Move index ``m = (dy + r) * (2r + 1) + (dx + r)``: the target moved by ``(dy, dx)``
    (rows, columns) from its predecessor at ``(y - dy, x - dx)`` to the pixel ``(y, x)``.

    Returns
    -------
    numpy.ndarray
        ``int64`` array of shape ``((2r+1)**2, 2)`` holding ``(dy, dx)`` per move.
    """
    span = np.arange(-radius, radius + 1)
    dy, dx = np.meshgrid(span, span, indexing="ij")
    return np.stack([dy.ravel(), dx.ravel()], axis=1).astype(np.int64)


def paper_weights(radius: int = 1) -> np.ndarray:
    """Paper 001 eq (11): ``w(theta) = 1`` for ``|theta| <= 90 deg``, else 0.

    ``theta`` is the angle between the predecessor's arrival move ``v1`` (its direction
    ``d``) and the candidate move ``v2``; ``|theta| <= 90 deg`` is ``v1 . v2 >= 0``.
    A zero move on either side has no angle and gets weight 1, and so does every move
    from a pixel in its segment's first frame (direction code ``START``, the last row).

    Returns
    -------
    numpy.ndarray
        ``float64`` LUT of shape ``(M + 1, M)`` indexed ``[predecessor d, move]``.
    """
    moves = move_offsets(radius)
    n_moves = len(moves)
    lut = np.ones((n_moves + 1, n_moves))
    dots = moves @ moves.T
    lut[:n_moves] = (dots >= 0).astype(np.float64)
    return lut


def plain_weights(radius: int = 1) -> np.ndarray:
    """An all-ones LUT: the direction-weighted DP becomes paper 001 eq (8), plain DP."""
    n_moves = (2 * radius + 1) ** 2
    return np.ones((n_moves + 1, n_moves))


def check_move_table(name: str, table: Any, radius: int, lo: float = -math.inf,
                     hi: float = math.inf, *, error: type[DptbdError] = ConfigError) -> np.ndarray:
    """A finite table indexed ``[predecessor direction, move]`` with values in ``[lo, hi]``.

    The shape of the weight LUT and of every table like it (paper 000's transition term):
    ``(M + 1, M)`` with ``M = (2r + 1)**2``, the last row for direction code ``START``.

    Returns
    -------
    numpy.ndarray
        The table as ``float64``.

    Raises
    ------
    ConfigError
        (or the class given as ``error``) naming ``name``, the shape or the domain.
    """
    n_moves = (2 * radius + 1) ** 2
    try:
        arr = np.asarray(table, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise error(f"{name} must be a numeric table, got {type(table).__name__}") from exc
    if arr.shape != (n_moves + 1, n_moves):
        raise error(
            f"{name} must have shape ({n_moves + 1}, {n_moves}) for radius={radius} "
            f"([predecessor direction 0..{n_moves}, move 0..{n_moves - 1}]), got {arr.shape}")
    good = np.isfinite(arr) & (arr >= lo) & (arr <= hi)
    if not np.all(good):
        raise error(f"{name} must be finite and in {interval(lo, hi)}, "
                    f"found {arr[~good].ravel()[:3].tolist()}")
    return arr
