"""Paper 000's dynamic-programming detectors: the unified recursion (25)-(26).

Paper 000 (``../shared/seeds/000_*.txt``, Qiang, Jiao & Bao) writes both of its DP
families as one recursion with a *merit* ``P`` of the cell's measurement and a
*transition term* ``Q`` between consecutive states:

    h_1(x_1) = P(x_1)                                                      (26)
    h_k(x_k) = P(x_k) + max_{x_{k-1}} [ Q(x_k | x_{k-1}) + h_{k-1}(x_{k-1}) ]  (25)

* amplitude DP, eqs (14)-(15): ``P = z``, ``Q = 0`` (:func:`~.merits.amplitude_merit`,
  :func:`~.transitions.no_penalty`);
* amplitude DP with the transition penalty, eq (24): ``P = z``, ``Q = lg p(x_k | x_{k-1})``
  of eq (22) (:func:`~.transitions.velocity_log_penalty`);
* likelihood-difference DP, eqs (19)-(23): ``P = S(z)`` of eqs (19)-(20)
  (:func:`~.merits.likelihood_difference_merit`) with the eq (22) penalty.

The merits are :mod:`dptbd.evaluation.detectors.merits`, the transition tables
:mod:`dptbd.evaluation.detectors.transitions`; this module runs the float recursion.

Reading of eq (22) (``docs/detectors.md`` §1.2): ``lg p(x_k|x_{k-1}) = -lg|x(k) - alpha x(k-1)|``
is taken on the target's *velocity* (its move per frame, the state's arrival direction),
regularised to stay finite and non-positive::

    Q[p, m] = -lg(1 + |v_m - alpha * v_p|)

where ``v_p`` is the predecessor's own arrival move and ``v_m`` the candidate move. A
predecessor in the first frame has no arrival move (code ``START = M``): ``Q = 0``.

Because Q depends on the predecessor's arrival move, the state is really (cell, arrival
move). Two forms are provided:

* ``mode="exact"``: DP over the expanded state (cell, arrival move), M + 1 planes; the
  maximum over all paths, eq (25) exactly (checked against brute force in the tests);
* ``mode="datapath"``: the form of paper 001's gateware — one (h, d) pair per cell, d the
  arrival move of the cell's best path, Q looked up at ``[d(q), m]`` like 001's weight LUT
  (``docs/arithmetic.md`` §3-§4) but *added* instead of multiplied. It equals the exact
  form whenever Q does not depend on the predecessor's move (every row of the table the
  same, e.g. ``Q = 0``) and is otherwise a greedy lower bound of it.

Moves, their order, image edges (a predecessor outside the image is invalid) and the
tie-break (lowest move index wins) are those of ``docs/arithmetic.md`` §2 and §4.
:func:`~dptbd.evaluation.detectors.unified_fixed.run_unified_fixed` is the integer version on
that datapath: a merit LUT on the input pixel code and an additive penalty LUT.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numba
import numpy as np

from dptbd.evaluation.detectors._checks import DetectorError, check_frames, check_int
from dptbd.evaluation.detectors.merits import Merit
from dptbd.evaluation.detectors.transitions import check_transition
from dptbd.weights import move_offsets

__all__ = [
    "UnifiedResult",
    "run_unified",
    "run_unified_segments",
    "backtrack",
    "path_value",
    "MODES",
]

MODES = ("datapath", "exact")


def _check_mode(mode: str) -> str:
    if mode not in MODES:
        raise DetectorError(f"mode must be one of {MODES}, got {mode!r}")
    return mode


# ---- kernels ------------------------------------------------------------------------------

@numba.njit(cache=True)
def _datapath_step(h, d, p, q, moves):  # pragma: no cover - compiled
    n_b, height, width = h.shape
    n_m = moves.shape[0]
    h_new = np.empty_like(h)
    d_new = np.empty(d.shape, np.uint8)
    for b in range(n_b):
        for y in range(height):
            for x in range(width):
                best = 0.0
                arg = -1
                for m in range(n_m):
                    yy = y - moves[m, 0]
                    xx = x - moves[m, 1]
                    if yy < 0 or yy >= height or xx < 0 or xx >= width:
                        continue
                    c = h[b, yy, xx] + q[d[b, yy, xx], m]
                    if arg < 0 or c > best:
                        best = c
                        arg = m
                h_new[b, y, x] = p[b, y, x] + best
                d_new[b, y, x] = arg
    return h_new, d_new


@numba.njit(cache=True)
def _exact_step(h, p, q, moves, back):  # pragma: no cover - compiled
    # h: (B, M+1, H, W), -inf = unreachable; back: (B, M, H, W) uint8 (255 = none)
    n_b, n_s, height, width = h.shape
    n_m = moves.shape[0]
    h_new = np.full(h.shape, -np.inf)
    for b in range(n_b):
        for m in range(n_m):
            for y in range(height):
                yy = y - moves[m, 0]
                for x in range(width):
                    xx = x - moves[m, 1]
                    back[b, m, y, x] = 255
                    if yy < 0 or yy >= height or xx < 0 or xx >= width:
                        continue
                    best = -np.inf
                    arg = -1
                    for s in range(n_s):
                        v = h[b, s, yy, xx]
                        if v == -np.inf:
                            continue
                        c = v + q[s, m]
                        if arg < 0 or c > best:
                            best = c
                            arg = s
                    if arg >= 0:
                        h_new[b, m, y, x] = p[b, y, x] + best
                        back[b, m, y, x] = arg
    return h_new


# ---- float recursion ------------------------------------------------------------------------

@dataclasses.dataclass(frozen=True)
class UnifiedResult:
    """Output of :func:`run_unified`.

    Attributes
    ----------
    value : numpy.ndarray
        ``(..., H, W)``: ``h_T(x)``, the best path value ending at each cell (exact mode:
        maximised over the arrival move too).
    direction : numpy.ndarray
        ``(..., H, W)`` ``uint8``: the arrival move of that best path (``M`` = START when
        T = 1).
    history : numpy.ndarray or None
        For backtracking (``history=True``): datapath mode ``(T, ..., H, W)`` arrival
        moves per frame; exact mode ``(T, ..., M, H, W)`` best predecessor move per
        (arrival move, cell) per frame (255 = unreachable).
    radius, mode : int, str
    """

    value: np.ndarray
    direction: np.ndarray
    history: np.ndarray | None
    radius: int
    mode: str


def run_unified(frames: Any, merit: Merit, transition: Any, *, radius: int = 2,
                mode: str = "datapath", history: bool = False) -> UnifiedResult:
    """Eqs (25)-(26) over a whole sequence ``(..., T, H, W)`` (leading axes: trials).

    Parameters
    ----------
    frames : array_like
        Real measurements ``z``.
    merit : Merit
        ``P`` (:func:`~.merits.amplitude_merit`, :func:`~.merits.likelihood_difference_merit`).
    transition : array_like
        ``Q``, an ``(M + 1, M)`` table (:func:`~.transitions.no_penalty`,
        :func:`~.transitions.velocity_log_penalty`).
    radius : int
        Window radius (1 or 2; paper 000's target moves 2 cells per frame).
    mode : str
        ``"datapath"`` (001's per-cell (h, d) state) or ``"exact"`` (expanded state).
    history : bool
        Keep what :func:`backtrack` needs.
    """
    radius = check_int("radius", radius, 1, 2)
    mode = _check_mode(mode)
    if not isinstance(merit, Merit):
        raise DetectorError(f"merit must be a Merit (amplitude_merit(), ...), got {merit!r}")
    q = check_transition(transition, radius)
    arr = check_frames(frames)
    lead, (n_t, height, width) = arr.shape[:-3], arr.shape[-3:]
    z = arr.reshape((-1, n_t, height, width))
    moves = move_offsets(radius)
    n_m = len(moves)
    p_all = merit(z)
    if mode == "datapath":
        h = p_all[:, 0].copy()
        d = np.full(h.shape, n_m, dtype=np.uint8)
        hist = np.empty((n_t,) + h.shape, dtype=np.uint8) if history else None
        if history:
            hist[0] = d
        for t in range(1, n_t):
            h, d = _datapath_step(h, d, np.ascontiguousarray(p_all[:, t]), q, moves)
            if history:
                hist[t] = d
        value, direction = h, d
    else:
        h = np.full((z.shape[0], n_m + 1, height, width), -np.inf)
        h[:, n_m] = p_all[:, 0]
        hist = np.full((n_t, z.shape[0], n_m, height, width), 255, dtype=np.uint8) if history else None
        back = np.empty((z.shape[0], n_m, height, width), dtype=np.uint8)
        for t in range(1, n_t):
            h = _exact_step(h, np.ascontiguousarray(p_all[:, t]), q, moves, back)
            if history:
                hist[t] = back
        direction = np.argmax(h, axis=1).astype(np.uint8)
        value = np.max(h, axis=1)
    out_hist = None
    if history:
        out_hist = hist.reshape((n_t,) + lead + hist.shape[2:])
    return UnifiedResult(value.reshape(lead + (height, width)),
                         direction.reshape(lead + (height, width)), out_hist, radius, mode)


def run_unified_segments(frames: Any, merit: Merit, transition: Any, *, segment_frames: int,
                         segment_stride: int = 1, radius: int = 2,
                         mode: str = "datapath") -> tuple[np.ndarray, np.ndarray]:
    """Eqs (25)-(26) restarted every ``segment_stride`` frames over ``segment_frames`` frames.

    The segment bookkeeping of ``docs/arithmetic.md`` §5. Returns the value maps
    ``(..., S, H, W)`` and each segment's last frame index ``(S,)``.
    """
    arr = check_frames(frames)
    n_t = arr.shape[-3]
    k = check_int("segment_frames", segment_frames, 1, n_t)
    stride = check_int("segment_stride", segment_stride, 1, k)
    starts = range(0, n_t - k + 1, stride)
    maps = [run_unified(arr[..., s:s + k, :, :], merit, transition, radius=radius, mode=mode).value
            for s in starts]
    return np.stack(maps, axis=-3), np.array([s + k - 1 for s in starts], dtype=np.int64)


def backtrack(result: UnifiedResult, cell: tuple[int, int], index: tuple = ()) -> np.ndarray:
    """The best path ending at ``cell`` in the last frame, ``(T, 2)`` (row, col) per frame.

    ``index`` selects the trial when the run had leading axes.
    """
    if result.history is None:
        raise DetectorError("backtrack needs run_unified(..., history=True)")
    moves = move_offsets(result.radius)
    hist = result.history[(slice(None),) + tuple(index)]
    n_t = hist.shape[0]
    height, width = hist.shape[-2:]
    y, x = (check_int("cell row", cell[0], 0, height - 1), check_int("cell col", cell[1], 0, width - 1))
    path = np.zeros((n_t, 2), dtype=np.int64)
    if result.mode == "datapath":
        for t in range(n_t - 1, -1, -1):
            path[t] = (y, x)
            if t:
                dy, dx = moves[hist[t, y, x]]
                y, x = y - dy, x - dx
        return path
    s = int(result.direction[tuple(index)][y, x])  # arrival move of the best path
    for t in range(n_t - 1, -1, -1):
        path[t] = (y, x)
        if t:
            prev = int(hist[t, s, y, x])
            dy, dx = moves[s]
            y, x, s = y - dy, x - dx, prev
    return path


def path_value(frames: Any, path: Any, merit: Merit, transition: Any, radius: int = 2) -> float:
    """The value of one path under eqs (25)-(26): sum of P plus the Q of each move.

    ``path`` is ``(T, 2)`` cells of a single sequence ``frames (T, H, W)``; consecutive
    cells must be within the window. The brute-force oracle of the tests.
    """
    z = check_frames(frames)
    q = check_transition(transition, radius)
    path = np.asarray(path, dtype=np.int64)
    side = 2 * radius + 1
    total = float(merit(z[0, path[0, 0], path[0, 1]]))
    prev = side * side  # START
    for t in range(1, len(path)):
        dy, dx = path[t] - path[t - 1]
        if max(abs(dy), abs(dx)) > radius:
            raise DetectorError(f"path step {t} moves by ({dy}, {dx}), outside radius {radius}")
        m = int((dy + radius) * side + (dx + radius))
        total += float(q[prev, m]) + float(merit(z[t, path[t, 0], path[t, 1]]))
        prev = m
    return total
