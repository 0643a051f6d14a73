"""Paper 000's transition terms ``Q``: the ``(M + 1, M)`` tables of the unified recursion
(25)-(26) (:mod:`dptbd.evaluation.detectors.unified`), indexed ``[predecessor arrival move,
move]`` with the START row last (``docs/detectors.md`` §1.2 for the reading of eq (22)).

* :func:`no_penalty` — ``Q = 0``, eq (15);
* :func:`velocity_log_penalty` — eq (22) on velocities, ``-lg(1 + |v_m - alpha v_p|)``;
* :func:`check_transition` — any such table, checked.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from dptbd.evaluation.detectors._checks import DetectorError, check_int, check_real
from dptbd.weights import check_move_table, move_offsets

__all__ = ["no_penalty", "velocity_log_penalty", "check_transition"]


def no_penalty(radius: int = 2) -> np.ndarray:
    """``Q = 0``: eq (15), the plain amplitude DP. Shape ``(M + 1, M)``."""
    radius = check_int("radius", radius, 1, 2)
    m = (2 * radius + 1) ** 2
    return np.zeros((m + 1, m))


def velocity_log_penalty(radius: int = 2, alpha: float = 1.0) -> np.ndarray:
    """Eq (22) read on velocities: ``Q[p, m] = -lg(1 + |v_m - alpha v_p|)``; row START is 0.

    Parameters
    ----------
    radius : int
        Window radius, 1 or 2.
    alpha : float
        The coefficient of eq (22), in [0, 1]: 1 predicts constant velocity, 0 predicts
        standing still (the move length itself is penalised).

    Returns
    -------
    numpy.ndarray
        ``(M + 1, M)`` table indexed ``[predecessor arrival move, move]``, values <= 0.
    """
    radius = check_int("radius", radius, 1, 2)
    alpha = check_real("alpha (eq (22) coefficient)", alpha, 0.0, 1.0)
    moves = move_offsets(radius).astype(np.float64)
    diff = moves[None, :, :] - alpha * moves[:, None, :]
    table = np.zeros((len(moves) + 1, len(moves)))
    table[:-1] = -np.log10(1.0 + np.sqrt((diff ** 2).sum(axis=-1)))
    return table


def check_transition(transition: Any, radius: int) -> np.ndarray:
    """A finite ``(M + 1, M)`` table of Q, rows = predecessor arrival move (START last)."""
    return check_move_table("transition", transition, radius, error=DetectorError)
