"""Paper 004's grid filter: the pieces both grid detectors share (:mod:`.grid`).

Paper 004 (``../shared/seeds/004_*.txt``) discretises the target state to the
range-Doppler cells, eq (12), and runs a recursive Bayes filter on the grid:

* predict, eqs (17)-(18): ``w_{k|k-1} = T^T w_{k-1|k-1}`` with a row-stochastic
  transition (eq (16)). Here T is never a dense IJ x IJ matrix: it is the composition of
  a *drift* (each Doppler cell moves its mass along the delay axis by the delay rate that
  Doppler implies, :meth:`PassiveRadar.range_drift`: the constant-velocity part) and a
  small *diffusion kernel* (the "near": process noise), both mass-conserving
  (:class:`Transition`);
* update, eqs (21)-(25): the likelihood of "the target is in cell c" is the product over
  cells, eq (22), in which only cell c differs from noise, so it is eq (21)'s
  ``l(z_c) = exp(-A**2 / (2 alpha**2)) I0(A z_c / alpha**2)`` (Rician over Rayleigh) at c;
  the posterior is normalised, eq (25); the entropy eq (26) ``H_k = -sum w log2 w``
  (:func:`entropy_bits`) and the maximum of ``w`` come out of the same fused pass.

The detectors built on it, :class:`~dptbd.evaluation.detectors.grid.InfoAccumulation` and
:class:`~dptbd.evaluation.detectors.grid.GridBayes`, are in :mod:`.grid`, which re-exports
every name here.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numba
import numpy as np

from dptbd.evaluation.detectors._checks import (
    DetectorError, check_int, check_real, check_sequence, check_shape)

__all__ = [
    "log_i0",
    "rician_log_likelihood",
    "gaussian_log_likelihood",
    "estimate_alpha",
    "gaussian_kernel",
    "check_kernel",
    "Transition",
    "entropy_bits",
    "GridRun",
    "LIKELIHOODS",
]

LIKELIHOODS = ("rician", "gaussian")

# Abramowitz & Stegun 9.8.1 and 9.8.2 (relative error < 2e-7)
_SMALL = np.array([1.0, 3.5156229, 3.0899424, 1.2067492, 0.2659732, 0.0360768, 0.0045813])
_LARGE = np.array([0.39894228, 0.01328592, 0.00225319, -0.00157565, 0.00916281,
                   -0.02057706, 0.02635537, -0.01647633, 0.00392377])


def log_i0(x: Any) -> np.ndarray:
    """``log I0(x)`` for ``x >= 0`` without overflow (A&S 9.8.1-9.8.2, relative error < 2e-7)."""
    x = np.asarray(x, dtype=np.float64)
    if np.any(x < 0) or not np.all(np.isfinite(x)):
        raise DetectorError("log_i0 needs finite x >= 0")
    out = np.empty_like(x)
    small = x <= 3.75
    t = (x[small] / 3.75) ** 2
    out[small] = np.log(np.polyval(_SMALL[::-1], t))
    xl = x[~small]
    out[~small] = xl - 0.5 * np.log(xl) + np.log(np.polyval(_LARGE[::-1], 3.75 / xl))
    return out


def rician_log_likelihood(z: Any, amplitude: float, alpha: Any) -> np.ndarray:
    """Eq (21): ``log l = -A**2 / (2 alpha**2) + log I0(A z / alpha**2)`` (Rician over Rayleigh)."""
    a = check_real("amplitude (A)", amplitude, 0.0)
    alpha = np.asarray(alpha, dtype=np.float64)
    if np.any(alpha <= 0):
        raise DetectorError("alpha (noise scale) must be > 0")
    z = np.asarray(z, dtype=np.float64)
    return -a * a / (2.0 * alpha * alpha) + log_i0(a * z / (alpha * alpha))


def gaussian_log_likelihood(z: Any, amplitude: float, sigma: Any) -> np.ndarray:
    """The eq (21) analogue for real Gaussian noise: ``log l = (A z - A**2 / 2) / sigma**2``."""
    a = check_real("amplitude (A)", amplitude, 0.0)
    sigma = np.asarray(sigma, dtype=np.float64)
    return (a * np.asarray(z, dtype=np.float64) - 0.5 * a * a) / (sigma * sigma)


def estimate_alpha(z: Any) -> np.ndarray:
    """Per-frame ML Rayleigh parameter ``sqrt(mean(z**2) / 2)`` over the last two axes."""
    z = np.asarray(z, dtype=np.float64)
    return np.sqrt(np.mean(z * z, axis=(-2, -1)) / 2.0)


def gaussian_kernel(sigma_range: float = 0.5, sigma_doppler: float = 0.5, radius: int = 1) -> np.ndarray:
    """A separable discretised Gaussian diffusion kernel, ``(2r+1, 2r+1)``, summing to 1."""
    sr = check_real("sigma_range", sigma_range, 0.0)
    sd = check_real("sigma_doppler", sigma_doppler, 0.0)
    r = check_int("kernel radius", radius, 0, 10)
    k = np.arange(-r, r + 1, dtype=np.float64)

    def taps(s: float) -> np.ndarray:
        if s == 0.0:
            return (k == 0).astype(np.float64)
        g = np.exp(-0.5 * (k / s) ** 2)
        return g / g.sum()

    out = np.outer(taps(sr), taps(sd))
    return out / out.sum()


def check_kernel(kernel: Any, *, atol: float = 1e-9) -> np.ndarray:
    """A 2-D kernel with odd sides, finite, non-negative, summing to 1 (eq (16))."""
    try:
        k = np.asarray(kernel, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise DetectorError("kernel must be a numeric 2-D array") from exc
    if k.ndim != 2 or k.shape[0] % 2 == 0 or k.shape[1] % 2 == 0:
        raise DetectorError(f"kernel must be 2-D with odd sides (centred), got shape {k.shape}")
    if not np.all(np.isfinite(k)) or k.min() < 0:
        raise DetectorError("kernel must be finite and non-negative (transition probabilities)")
    total = float(k.sum())
    if abs(total - 1.0) > atol:
        raise DetectorError(f"kernel must sum to 1 (eq (16), a row-stochastic transition), sums to {total!r}")
    return k


@numba.njit(cache=True)
def _drift(w, drift, out):  # pragma: no cover - compiled
    # move the mass of Doppler column j by drift[j] delay cells, linear split, clamped at edges
    n_i, n_j = w.shape
    out[:] = 0.0
    for j in range(n_j):
        s = drift[j]
        base = math.floor(s)
        f = s - base
        for i in range(n_i):
            v = w[i, j]
            if v == 0.0:
                continue
            a = i + int(base)
            b = a + 1
            a = min(max(a, 0), n_i - 1)
            b = min(max(b, 0), n_i - 1)
            out[a, j] += (1.0 - f) * v
            out[b, j] += f * v
    return out


@numba.njit(cache=True)
def _spread(w, kernel, inv_norm, out):  # pragma: no cover - compiled
    # out[i + a, j + b] += K[a, b] * w[i, j] / norm[i, j]: T rows renormalised at the edges
    n_i, n_j = w.shape
    ri = kernel.shape[0] // 2
    rj = kernel.shape[1] // 2
    out[:] = 0.0
    for i in range(n_i):
        for j in range(n_j):
            v = w[i, j] * inv_norm[i, j]
            if v == 0.0:
                continue
            for a in range(kernel.shape[0]):
                ii = i + a - ri
                if ii < 0 or ii >= n_i:
                    continue
                for b in range(kernel.shape[1]):
                    jj = j + b - rj
                    if jj < 0 or jj >= n_j:
                        continue
                    out[ii, jj] += kernel[a, b] * v
    return out


@dataclasses.dataclass(frozen=True)
class Transition:
    """The grid transition T of eqs (16)-(18) as a drift and a small kernel.

    ``T^{(m,n) -> (i,j)}``: first the mass of cell (m, n) moves ``drift[n]`` delay cells
    (split linearly between the two nearest cells, clamped at the grid edge), then it is
    spread by ``kernel`` centred on where it landed, renormalised over the kernel taps
    inside the grid. Every row of T sums to 1 (eq (16)), so total probability is kept.

    Parameters
    ----------
    shape : pair of int
        ``(I, J)``.
    kernel : array_like
        Odd-sided 2-D kernel (delay x Doppler), non-negative, summing to 1.
    drift : array_like or None
        ``(J,)`` delay cells per frame for each Doppler cell
        (:meth:`~dptbd.scenes.range_doppler.PassiveRadar.range_drift`); ``None``: 0.
    """

    shape: tuple[int, int]
    kernel: np.ndarray
    drift: np.ndarray | None = None

    def __post_init__(self) -> None:
        shape = check_shape("grid shape", self.shape, 65535, axes=("I", "J"))
        object.__setattr__(self, "shape", shape)
        object.__setattr__(self, "kernel", check_kernel(self.kernel))
        if self.drift is not None:
            d = np.asarray(self.drift, dtype=np.float64)
            if d.shape != (shape[1],) or not np.all(np.isfinite(d)):
                raise DetectorError(f"drift must be a finite ({shape[1]},) array (one per Doppler cell), "
                                    f"got shape {d.shape}")
            object.__setattr__(self, "drift", None if not np.any(d) else d)
        # mass of the kernel that lands inside the grid, per source cell
        ones = np.ones(shape)
        inside = _spread(ones, self.kernel[::-1, ::-1].copy(), ones, np.empty(shape))
        object.__setattr__(self, "_inv_norm", 1.0 / inside)

    def predict(self, w: np.ndarray) -> np.ndarray:
        """Eq (18): ``w_{k|k-1}[i, j] = sum_{m,n} T^{(m,n)->(i,j)} w_{k-1|k-1}[m, n]``."""
        w = np.ascontiguousarray(w, dtype=np.float64)
        if w.shape != self.shape:
            raise DetectorError(f"weights have shape {w.shape}, the grid is {self.shape}")
        if self.drift is not None:
            w = _drift(w, self.drift, np.empty(self.shape))
        return _spread(w, self.kernel, self._inv_norm, np.empty(self.shape))

    def dense(self) -> np.ndarray:
        """The ``(IJ, IJ)`` matrix T, row (m, n) -> column (i, j), raster order. Tests only."""
        n_i, n_j = self.shape
        if n_i * n_j > 4096:
            raise DetectorError("dense() is for tiny grids (at most 4096 cells)")
        out = np.empty((n_i * n_j, n_i * n_j))
        for c in range(n_i * n_j):
            e = np.zeros(self.shape)
            e.flat[c] = 1.0
            out[c] = self.predict(e).ravel()
        return out


def entropy_bits(w: Any) -> np.ndarray:
    """Eq (26): ``H = -sum w log2 w`` over the last two axes, with ``0 log 0 = 0``."""
    w = np.asarray(w, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = np.where(w > 0, w * np.log2(np.where(w > 0, w, 1.0)), 0.0)
    return -terms.sum(axis=(-2, -1))


@dataclasses.dataclass(frozen=True)
class GridRun:
    """Per-frame output of a grid filter on one sequence.

    Attributes
    ----------
    statistic : numpy.ndarray
        ``(T,)`` the decision statistic (larger = more target-like): ``-H_k`` for
        information accumulation, the existence log-odds for grid Bayes.
    estimate : numpy.ndarray
        ``(T, 2)`` int: ``argmax w`` (Table 1's state estimate).
    entropy : numpy.ndarray
        ``(T,)`` ``H_k`` in bits (eq (26)) of the (target-present) posterior.
    posterior : numpy.ndarray
        ``(I, J)`` the last posterior.
    """

    statistic: np.ndarray
    estimate: np.ndarray
    entropy: np.ndarray
    posterior: np.ndarray


class _GridFilter:
    """Shared set-up: grid, transition, likelihood and its amplitude channel."""

    def __init__(self, transition: Transition, *, snr_db: float = 10.0, alpha: float | None = None,
                 likelihood: str = "rician") -> None:
        if not isinstance(transition, Transition):
            raise DetectorError(f"transition must be a Transition, got {transition!r}")
        if likelihood not in LIKELIHOODS:
            raise DetectorError(f"likelihood must be one of {LIKELIHOODS}, got {likelihood!r}")
        self.transition = transition
        self.shape = transition.shape
        self.snr_db = check_real("snr_db (preset SNR channel)", snr_db, -30.0, 60.0)
        self.alpha = None if alpha is None else check_real("alpha (noise scale)", alpha, 0.0, lo_open=True)
        self.likelihood = likelihood

    def _channel(self, z: np.ndarray) -> tuple[float, float]:
        """``(A, noise scale)`` of eq (21) for one frame: the preset SNR channel.

        Rician: ``A = alpha sqrt(2 SNR)`` (mean target power ``P = 2 alpha**2 SNR``, 004 §4.1
        scenario 3: "estimate the noise, then the amplitude from the preset SNR channel").
        Gaussian: ``A = sigma sqrt(SNR)``.
        """
        snr = 10.0 ** (self.snr_db / 10.0)
        if self.likelihood == "rician":
            alpha = float(estimate_alpha(z)) if self.alpha is None else self.alpha
            return alpha * math.sqrt(2.0 * snr), alpha
        sigma = float(np.std(z)) if self.alpha is None else self.alpha
        return sigma * math.sqrt(snr), sigma

    def log_likelihood(self, z: Any) -> np.ndarray:
        """Eq (21) (or its Gaussian analogue) per cell for one frame ``(I, J)``: log l(z_c)."""
        amp, scale = self._channel(np.asarray(z, dtype=np.float64))
        if self.likelihood == "rician":
            return rician_log_likelihood(z, amp, scale)
        return gaussian_log_likelihood(z, amp, scale)

    def _frames(self, frames: Any) -> np.ndarray:
        return check_sequence(frames, self.shape, self.likelihood)


@numba.njit(cache=True)
def _i0_scaled(x):  # pragma: no cover - compiled
    """``I0(x) exp(-x)`` for x >= 0, the polynomials of :func:`log_i0`."""
    if x <= 3.75:
        t = (x / 3.75) ** 2
        acc = 1.0 + t * (3.5156229 + t * (3.0899424 + t * (1.2067492 + t * (
            0.2659732 + t * (0.0360768 + t * 0.0045813)))))
        return acc * math.exp(-x)
    t = 3.75 / x
    acc = 0.39894228 + t * (0.01328592 + t * (0.00225319 + t * (-0.00157565 + t * (
        0.00916281 + t * (-0.02057706 + t * (0.02635537 + t * (-0.01647633 + t * 0.00392377)))))))
    return acc / math.sqrt(x)


@numba.njit(cache=True)
def _update(pred, z, amp, scale, rician, out):  # pragma: no cover - compiled
    """Eqs (21), (24)-(26) fused: posterior into ``out``; returns (log mass, H, argmax row, col).

    ``w_c ∝ pred_c l(z_c)`` with ``l = exp(-A²/2α²) I0(x)``, ``x = A z_c / α²``, evaluated
    as ``exp(x - x_max) [I0(x) e^-x]`` so nothing overflows (the Gaussian analogue:
    ``exp(x - x_max)``); log mass = ``log sum pred_c l(z_c)``.
    """
    n_i, n_j = pred.shape
    c0 = -amp * amp / (2.0 * scale * scale)
    c1 = amp / (scale * scale)
    zmax = -np.inf
    for i in range(n_i):
        for j in range(n_j):
            if z[i, j] > zmax:
                zmax = z[i, j]
    xmax = c1 * zmax
    total = 0.0
    for i in range(n_i):
        for j in range(n_j):
            p = pred[i, j]
            if p <= 0.0:
                out[i, j] = 0.0
                continue
            x = c1 * z[i, j]
            v = p * math.exp(x - xmax)
            if rician:
                v *= _i0_scaled(x)
            out[i, j] = v
            total += v
    h = 0.0
    best = -1.0
    bi = 0
    bj = 0
    inv = 1.0 / total
    for i in range(n_i):
        for j in range(n_j):
            w = out[i, j] * inv
            out[i, j] = w
            if w > 0.0:
                h -= w * math.log2(w)
            if w > best:
                best = w
                bi = i
                bj = j
    return math.log(total) + xmax + c0, h, bi, bj
