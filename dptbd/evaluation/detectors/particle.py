"""A particle-filter track-before-detect with an existence variable (Salmond–Birch, Rutten).

The standard baseline of the TBD literature (paper 004 names it among its comparisons):
the state is a target's continuous position and velocity in cells plus a binary existence
variable; the measurement is the whole frame, and a target in cell c changes only that
cell's likelihood, so the likelihood ratio of a particle is eq (21)'s
``l(z_c) = p(z_c | target) / p(z_c | noise)`` (Rician on magnitudes, Gaussian on zero-mean
images; the amplitude from the preset SNR channel, the noise scale estimated per frame,
like the grid filters, :mod:`~dptbd.evaluation.detectors.grid_filter`).

The recursion is Rutten, Gordon & Maskell's (2005) efficient form: the existence
probability is carried analytically, the particles hold the target's state given that it
exists. Per frame k, with P = P(exists | z_1..k-1), birth probability ``birth`` and death
probability ``death``:

* **continuing** particles (N = ``particles``): near-constant velocity,
  ``v' = v + process_noise * g``, ``x' = x + v'`` (g standard normal per axis), weight
  ``l(z_c)`` of the cell ``c = rint(x')`` they fall in (0 outside the grid);
  ``I_c`` = their mean weight;
* **birth** particles (N_b = ``birth_particles``): a new target is uniform over the cells
  with a velocity uniform in ``[-max_speed, max_speed]`` per axis. **Choice**: the birth
  cells are drawn from the data, with probability proportional to ``l(z_c)``, the
  position uniform inside the cell; with a uniform prior, every such particle's
  importance weight is exactly the mean of ``l`` over the grid, so ``I_b`` =
  mean_c l(z_c) is exact (a uniform proposal would need far more particles to land on a
  faint target);
* ``M_b = birth (1 - P) I_b``, ``M_c = (1 - death) P I_c``, ``R = (1 - birth)(1 - P) + death P``;
  the new existence probability is ``(M_b + M_c) / (M_b + M_c + R)``, the statistic its
  log-odds ``log(M_b + M_c) - log R``;
* the continuing and birth particles, weighted ``M_c w_i / sum w`` and ``M_b / N_b``, are
  resampled (systematic) to the N continuing particles of the next frame; the estimate
  is the cell that holds the largest weight. Before the first frame P = 0 (only births).

**Seeded**: the random numbers of one sequence come from
``numpy.random.SeedSequence([seed, crc32 of the sequence's bytes])``: the same seed and
frames give the same result, in any batch, chunking or worker, and different sequences
get independent streams. The kernels are compiled with numba.
"""

from __future__ import annotations

import dataclasses
import math
import zlib
from typing import Any

import numba
import numpy as np

from dptbd.evaluation.detectors._checks import DetectorError, check_frames, check_int, check_prob, check_real
from dptbd.evaluation.detectors.grid_filter import (LIKELIHOODS, estimate_alpha, gaussian_log_likelihood,
                                                    rician_log_likelihood)

__all__ = ["ParticleRun", "ParticleTBD"]


@dataclasses.dataclass(frozen=True)
class ParticleRun:
    """One sequence: per frame the existence log-odds, the estimated cell and P(exists)."""

    statistic: np.ndarray  # (T,) log P(exists) - log P(no target)
    estimate: np.ndarray   # (T, 2) cell with the largest particle weight
    existence: np.ndarray  # (T,) P(exists | z_1..t)


@numba.njit(cache=True)
def _propagate(pos, vel, noise, q, ll, logw):  # pragma: no cover - compiled
    """Move the continuing particles one frame and set their log weight (log l of their cell)."""
    h, w = ll.shape
    for i in range(pos.shape[0]):
        vel[i, 0] += q * noise[i, 0]
        vel[i, 1] += q * noise[i, 1]
        pos[i, 0] += vel[i, 0]
        pos[i, 1] += vel[i, 1]
        r = int(np.rint(pos[i, 0]))
        c = int(np.rint(pos[i, 1]))
        if 0 <= r < h and 0 <= c < w:
            logw[i] = ll[r, c]
        else:
            logw[i] = -np.inf


@numba.njit(cache=True)
def _births(cum, u, sub, vu, vmax, width, pos, vel):  # pragma: no cover - compiled
    """Birth particles: cell by inverse CDF of ``cum`` at ``u``, sub-cell and velocity uniform."""
    n_cells = cum.shape[0]
    for i in range(pos.shape[0]):
        k = np.searchsorted(cum, u[i] * cum[n_cells - 1], side="right")
        if k >= n_cells:
            k = n_cells - 1
        pos[i, 0] = k // width + sub[i, 0] - 0.5
        pos[i, 1] = k % width + sub[i, 1] - 0.5
        vel[i, 0] = vmax * (2.0 * vu[i, 0] - 1.0)
        vel[i, 1] = vmax * (2.0 * vu[i, 1] - 1.0)


@numba.njit(cache=True)
def _systematic(weights, u0, n):  # pragma: no cover - compiled
    """``n`` indices by systematic resampling of normalised ``weights`` (offset ``u0`` in [0, 1))."""
    out = np.empty(n, dtype=np.int64)
    j = 0
    m = weights.shape[0]
    total = weights[0]
    for i in range(n):
        target = (i + u0) / n
        while total < target and j < m - 1:
            j += 1
            total += weights[j]
        out[i] = j
    return out


@numba.njit(cache=True)
def _heaviest_cell(pos, weights, h, w):  # pragma: no cover - compiled
    """The grid cell holding the largest summed weight (lowest row-major index on ties)."""
    mass = np.zeros((h, w))
    for i in range(pos.shape[0]):
        r = int(np.rint(pos[i, 0]))
        c = int(np.rint(pos[i, 1]))
        r = min(max(r, 0), h - 1)
        c = min(max(c, 0), w - 1)
        mass[r, c] += weights[i]
    k = np.argmax(mass)
    return k // w, k % w


def _logmeanexp(x: np.ndarray) -> float:
    top = float(np.max(x))
    if top == -math.inf:
        return -math.inf
    return top + math.log(float(np.mean(np.exp(x - top))))


class ParticleTBD:
    """The filter on one sequence ``(T, H, W)``: :meth:`run` -> :class:`ParticleRun`.

    Parameters
    ----------
    shape : pair of int
        ``(H, W)`` cells.
    snr_db : float
        Preset SNR channel of the likelihood's amplitude, in [-30, 60] dB.
    likelihood : str
        ``"rician"`` (magnitudes) or ``"gaussian"`` (zero-mean images).
    alpha : float or None
        Known noise scale, > 0; ``None``: estimated per frame.
    max_speed : float
        Birth velocities are uniform in ``[-max_speed, max_speed]`` cells/frame per axis, > 0.
    particles, birth_particles : int
        N continuing and N_b birth particles, each in [1, 10**7].
    birth, death : float
        Existence transition probabilities per frame, in (0, 1).
    process_noise : float
        Standard deviation of the velocity change per frame, cells/frame, >= 0.
    seed : int
        Base seed, >= 0.
    """

    def __init__(self, shape: tuple[int, int], *, snr_db: float = 10.0, likelihood: str = "rician",
                 alpha: float | None = None, max_speed: float = 1.0, particles: int = 3000,
                 birth_particles: int = 3000, birth: float = 0.05, death: float = 0.05,
                 process_noise: float = 0.1, seed: int = 0) -> None:
        if likelihood not in LIKELIHOODS:
            raise DetectorError(f"likelihood must be one of {LIKELIHOODS}, got {likelihood!r}")
        self.shape = (check_int("shape[0] (H)", shape[0], 1), check_int("shape[1] (W)", shape[1], 1))
        self.snr_db = check_real("snr_db (preset SNR channel)", snr_db, -30.0, 60.0)
        self.likelihood = likelihood
        self.alpha = None if alpha is None else check_real("alpha (noise scale)", alpha, 0.0, lo_open=True)
        self.max_speed = check_real("max_speed (birth velocity bound, cells/frame)", max_speed, 0.0,
                                    lo_open=True)
        self.particles = check_int("particles", particles, 1, 10**7)
        self.birth_particles = check_int("birth_particles", birth_particles, 1, 10**7)
        self.birth = check_prob("birth", birth)
        self.death = check_prob("death", death)
        self.process_noise = check_real("process_noise (velocity change, cells/frame)", process_noise, 0.0)
        self.seed = check_int("seed", seed, 0)

    def log_likelihood(self, z: np.ndarray) -> np.ndarray:
        """Eq (21) (or its Gaussian analogue) per cell of one frame, at the preset channel."""
        snr = 10.0 ** (self.snr_db / 10.0)
        if self.likelihood == "rician":
            alpha = float(estimate_alpha(z)) if self.alpha is None else self.alpha
            return rician_log_likelihood(z, alpha * math.sqrt(2.0 * snr), alpha)
        sigma = float(np.std(z)) if self.alpha is None else self.alpha
        return gaussian_log_likelihood(z, sigma * math.sqrt(snr), sigma)

    def rng(self, frames: np.ndarray) -> np.random.Generator:
        """The sequence's generator: ``SeedSequence([seed, crc32(frames as float64 bytes)])``."""
        data = np.ascontiguousarray(frames, dtype=np.float64)
        return np.random.default_rng(np.random.SeedSequence([self.seed, zlib.crc32(data.tobytes())]))

    def run(self, frames: Any) -> ParticleRun:
        z = check_frames(frames, min_ndim=3)
        if z.ndim != 3 or z.shape[1:] != self.shape:
            raise DetectorError(f"frames must be one sequence (T, {self.shape[0]}, {self.shape[1]}), "
                                f"got shape {z.shape}")
        if self.likelihood == "rician" and z.min() < 0:
            raise DetectorError("frames must be magnitudes >= 0 for the Rician likelihood")
        rng = self.rng(z)
        h, w = self.shape
        n, nb = self.particles, self.birth_particles
        pos = np.zeros((n, 2))
        vel = np.zeros((n, 2))
        bpos = np.empty((nb, 2))
        bvel = np.empty((nb, 2))
        logw = np.empty(n)
        log_p, log_q = -math.inf, 0.0  # log P(exists), log P(no target) before the first frame
        n_t = z.shape[0]
        stat = np.empty(n_t)
        est = np.empty((n_t, 2), dtype=np.int64)
        existence = np.empty(n_t)
        for t in range(n_t):
            ll = self.log_likelihood(z[t])
            noise = rng.standard_normal((n, 2))
            u, sub, vu = rng.random(nb), rng.random((nb, 2)), rng.random((nb, 2))
            u0 = float(rng.random())
            _propagate(pos, vel, noise, self.process_noise, ll, logw)
            top = float(ll.max())
            cum = np.cumsum(np.exp(ll - top).ravel())
            _births(cum, u, sub, vu, self.max_speed, w, bpos, bvel)
            log_ib = top + math.log(cum[-1] / cum.size)             # mean_c l(z_c), exact
            log_mb = math.log(self.birth) + log_q + log_ib
            log_mc = (math.log1p(-self.death) + log_p + _logmeanexp(logw)
                      if log_p > -math.inf else -math.inf)
            log_m = float(np.logaddexp(log_mb, log_mc))
            log_r = float(np.logaddexp(math.log1p(-self.birth) + log_q, math.log(self.death) + log_p))
            stat[t] = log_m - log_r
            log_total = float(np.logaddexp(log_m, log_r))
            log_p, log_q = log_m - log_total, log_r - log_total
            existence[t] = math.exp(log_p)
            # mixture weights of the continuing and birth particles, normalised
            wc = np.zeros(n)
            if log_mc > -math.inf:
                lw = logw - logw.max()
                wc = np.exp(lw) / np.exp(lw).sum() * math.exp(log_mc - log_m)
            wb = np.full(nb, math.exp(log_mb - log_m) / nb)
            allw = np.concatenate([wc, wb])
            allpos = np.concatenate([pos, bpos])
            allvel = np.concatenate([vel, bvel])
            est[t] = _heaviest_cell(allpos, allw, h, w)
            idx = _systematic(allw / allw.sum(), u0, n)
            pos, vel = allpos[idx].copy(), allvel[idx].copy()
        return ParticleRun(stat, est, existence)
