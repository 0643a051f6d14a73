"""Paper 000's dynamic-programming detectors: the unified recursion (25)-(26).

Paper 000 (``../shared/seeds/000_*.txt``, Qiang, Jiao & Bao) writes both of its DP
families as one recursion with a *merit* ``P`` of the cell's measurement and a
*transition term* ``Q`` between consecutive states:

    h_1(x_1) = P(x_1)                                                      (26)
    h_k(x_k) = P(x_k) + max_{x_{k-1}} [ Q(x_k | x_{k-1}) + h_{k-1}(x_{k-1}) ]  (25)

* amplitude DP, eqs (14)-(15): ``P = z``, ``Q = 0`` (:func:`amplitude_merit`, :func:`no_penalty`);
* amplitude DP with the transition penalty, eq (24): ``P = z``, ``Q = lg p(x_k | x_{k-1})``
  of eq (22) (:func:`velocity_log_penalty`);
* likelihood-difference DP, eqs (19)-(23): ``P = S(z)`` of eqs (19)-(20)
  (:func:`likelihood_difference_merit`) with the eq (22) penalty.

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
:func:`run_unified_fixed` is the integer version on that datapath: a merit LUT on the
input pixel code and an additive penalty LUT.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Callable

import numba
import numpy as np

from dptbd.weights import check_move_table, move_offsets
from dptbd.evaluation.detectors._checks import (
    DetectorError, check_frames, check_int, check_real)

__all__ = [
    "Merit",
    "amplitude_merit",
    "likelihood_difference_merit",
    "no_penalty",
    "velocity_log_penalty",
    "check_transition",
    "UnifiedResult",
    "run_unified",
    "run_unified_segments",
    "backtrack",
    "path_value",
    "FixedUnified",
    "quantise_unified",
    "run_unified_fixed",
    "MODES",
]

MODES = ("datapath", "exact")


# ---- merits P -----------------------------------------------------------------------------

@dataclasses.dataclass(frozen=True)
class Merit:
    """A merit ``P(z)`` of one cell's measurement: the stage index of eq (25)."""

    name: str
    function: Callable[[np.ndarray], np.ndarray]
    params: dict

    def __call__(self, z: np.ndarray) -> np.ndarray:
        return np.asarray(self.function(np.asarray(z, dtype=np.float64)), dtype=np.float64)


def amplitude_merit() -> Merit:
    """Eq (14)-(15), (24): the measured amplitude itself, ``P(z) = z``."""
    return Merit("amplitude", lambda z: z, {})


def likelihood_difference_merit(amplitude: float, epsilon: float, sigma: float,
                                noise_sigma: float = 1.0) -> Merit:
    """Eqs (19)-(20): ``S(z) = exp(-(z - eps a)**2 / (2 sigma**2)) - p(z | H0)``.

    ``p(z | H0)`` is eq (18)'s unit-variance Gaussian density; measurements are divided by
    ``noise_sigma`` first (eq (18) assumes unit noise). Eq (20) states ``0 < eps < 1``
    and ``sigma > 1``; 000 §5.2 runs ``sigma`` (printed ``delta``) = 1, so any
    ``sigma > 0`` is accepted (``docs/detectors.md`` §1.2).

    Parameters
    ----------
    amplitude : float
        The expected target amplitude ``a`` (> 0), in the units of the measurements.
    epsilon : float
        Fraction of ``a`` at which S peaks, in (0, 1) (000 §5.2: 0.85 at 6 dB, 0.55 at 3 dB).
    sigma : float
        Width of the bump, > 0 (in noise standard deviations).
    noise_sigma : float
        Noise standard deviation of the measurements, > 0.
    """
    a = check_real("amplitude (a)", amplitude, 0.0, lo_open=True)
    eps = check_real("epsilon (printed alpha in 000 §5.2)", epsilon, 0.0, 1.0, lo_open=True, hi_open=True)
    sig = check_real("sigma (printed delta in 000 §5.2)", sigma, 0.0, lo_open=True)
    ns = check_real("noise_sigma", noise_sigma, 0.0, lo_open=True)
    centre = eps * a / ns

    def s(z: np.ndarray) -> np.ndarray:
        u = z / ns
        return np.exp(-(u - centre) ** 2 / (2.0 * sig * sig)) - np.exp(-0.5 * u * u) / math.sqrt(2 * math.pi)

    return Merit("likelihood-difference", s,
                 dict(amplitude=a, epsilon=eps, sigma=sig, noise_sigma=ns))


# ---- transition terms Q -----------------------------------------------------------------

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
        ``P`` (:func:`amplitude_merit`, :func:`likelihood_difference_merit`).
    transition : array_like
        ``Q``, an ``(M + 1, M)`` table (:func:`no_penalty`, :func:`velocity_log_penalty`).
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


# ---- fixed point on 001's datapath --------------------------------------------------------

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
