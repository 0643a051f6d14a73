"""SNR loss of a detector against a reference, with its uncertainty (``dptbd compare``).

A detector's first-level Pd is measured at a grid of SNRs on the same seeded scenes as the
reference's (:mod:`dptbd.evaluation.compare`). The **SNR needed for Pd = p** is read off the
curve, and the **loss** is the difference of the two in dB:

    loss(p) = SNR_dB,detector(p) - SNR_dB,reference(p),   SNR_dB = 20 lg(SNR)

(001's SNR is an amplitude ratio, ``(TargetAmp - NoiseAmp) / sigma``, hence 20 lg).
A positive loss means the detector needs more SNR than the reference.

Reading the crossing (:func:`crossing`)
    The measured Pd is first made non-decreasing in SNR by isotonic regression (pool
    adjacent violators, weighted by the opportunities at each SNR: a noisy dip is
    averaged with its neighbours instead of producing several crossings); the crossing is
    then the linear interpolation, in Pd against SNR_dB, between the last grid point below
    ``p`` and the first at or above it. A curve already at or above ``p`` at the first
    SNR has its crossing below the grid (``-inf``); one that never reaches ``p`` above it
    (``+inf``).

Uncertainty (:func:`bootstrap_losses`)
    A paired bootstrap over trials: each resample draws the trial indices with
    replacement (the same draw for every detector and every SNR, since all of them saw the
    same scenes) and recomputes every curve, crossing and loss. The 95 % interval is the
    2.5 % and 97.5 % order statistics of the resampled losses. Pairing matters: most
    scenes give the same outcome to the fixed and the float model, so the loss is far
    better resolved than two independent Pd curves would suggest. A loss with ``+-inf``
    or undefined values in more than 2.5 % of the resamples on one side has an unbounded
    interval on that side.

Confidence intervals of proportions (:func:`clustered_wilson`)
    Wilson score intervals (:func:`dptbd.evaluation.stats.wilson_interval`) on an *effective*
    sample size ``n / deff``: ``deff`` is the design effect of clustering by trial (the
    pixels of one accumulated image are correlated, DP spreads energy over neighbours),
    estimated from the spread of the per-trial proportions, and never taken below 1.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numba import njit

from dptbd.errors import DptbdError, check_prob
from dptbd.evaluation.stats import wilson_interval

__all__ = ["snr_db", "isotonic", "crossing", "crossings", "clustered_wilson",
           "LossEstimate", "bootstrap_losses", "Z95"]

Z95 = 1.959963984540054


def snr_db(snr) -> np.ndarray:
    """001's linear SNR (an amplitude ratio) in dB: ``20 lg(SNR)``."""
    return 20.0 * np.log10(np.asarray(snr, dtype=np.float64))


@njit(cache=True)
def _isotonic(y, w):
    """Weighted pool-adjacent-violators: the non-decreasing fit of ``y`` (weights ``w`` > 0)."""
    n = y.shape[0]
    val = np.empty(n)
    wt = np.empty(n)
    size = np.empty(n, np.int64)
    k = 0
    for i in range(n):
        val[k] = y[i]
        wt[k] = w[i]
        size[k] = 1
        while k > 0 and val[k - 1] > val[k]:
            tot = wt[k - 1] + wt[k]
            val[k - 1] = (val[k - 1] * wt[k - 1] + val[k] * wt[k]) / tot
            wt[k - 1] = tot
            size[k - 1] += size[k]
            k -= 1
        k += 1
    out = np.empty(n)
    j = 0
    for b in range(k):
        for _ in range(size[b]):
            out[j] = val[b]
            j += 1
    return out


@njit(cache=True)
def _crossing(x, y, w, level):
    fit = _isotonic(y, w)
    if fit[0] >= level:
        return -np.inf
    for j in range(1, x.shape[0]):
        if fit[j] >= level:
            return x[j - 1] + (level - fit[j - 1]) * (x[j] - x[j - 1]) / (fit[j] - fit[j - 1])
    return np.inf


@njit(cache=True)
def _crossings(x, ys, ws, level):
    out = np.empty(ys.shape[0])
    for i in range(ys.shape[0]):
        out[i] = _crossing(x, ys[i], ws[i], level)
    return out


def isotonic(y, w=None) -> np.ndarray:
    """The weighted least-squares non-decreasing fit of ``y`` (pool adjacent violators)."""
    y = np.asarray(y, dtype=np.float64)
    w = np.ones_like(y) if w is None else np.asarray(w, dtype=np.float64)
    if y.ndim != 1 or w.shape != y.shape or y.size == 0:
        raise DptbdError(f"y and w must be equal-length non-empty vectors, got {y.shape}, "
                         f"{w.shape}")
    if np.any(w <= 0):
        raise DptbdError("weights must be > 0")
    return _isotonic(y, w)


def _check_grid(x) -> np.ndarray:
    x = np.asarray(x, dtype=np.float64)
    if x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)) or np.any(np.diff(x) <= 0):
        raise DptbdError(f"the SNR grid must be at least 2 finite, strictly increasing values, "
                         f"got {x}")
    return x


def crossing(x, pd, level: float, weights=None) -> float:
    """The x (SNR in dB) at which the isotonic fit of ``pd`` reaches ``level``.

    Linear interpolation between grid points; ``-inf`` if the fit is already at ``level``
    at ``x[0]``, ``+inf`` if it never gets there. ``weights``: opportunities per point.
    """
    x = _check_grid(x)
    pd = np.asarray(pd, dtype=np.float64)
    w = np.ones_like(pd) if weights is None else np.asarray(weights, dtype=np.float64)
    if pd.shape != x.shape or w.shape != x.shape:
        raise DptbdError(f"pd and weights must match the grid's shape {x.shape}")
    level = check_prob("level", level)
    return float(_crossing(x, pd, np.maximum(w, 1e-12), level))


def crossings(x, pds, level: float, weights) -> np.ndarray:
    """:func:`crossing` of every row of ``pds`` (``(N, len(x))``) with its row of ``weights``."""
    x = _check_grid(x)
    pds = np.ascontiguousarray(pds, dtype=np.float64)
    ws = np.ascontiguousarray(np.broadcast_to(weights, pds.shape), dtype=np.float64)
    return _crossings(x, pds, np.maximum(ws, 1e-12), float(level))


def clustered_wilson(successes, trials, z: float = Z95) -> tuple[float, float, float, float]:
    """Proportion and Wilson interval from per-cluster counts, allowing for clustering.

    Parameters
    ----------
    successes, trials : array_like
        Per cluster (trial): successes and trials (e.g. pixels above a threshold and
        pixels; detections and opportunities).

    Returns
    -------
    tuple
        ``(p, lo, hi, deff)``: the pooled proportion, its interval on the effective
        sample size ``n / deff``, and the design effect ``deff >= 1``: the ratio-estimator
        variance over k clusters, ``sum((n_i / nbar)**2 (p_i - p)**2) / (k (k - 1))``,
        over its binomial value ``p (1 - p) / n`` (1 with fewer than 2 clusters or ``p``
        in {0, 1}).
    """
    s = np.asarray(successes, dtype=np.float64).ravel()
    n = np.asarray(trials, dtype=np.float64).ravel()
    total_n = float(n.sum())
    if total_n <= 0:
        return (math.nan, math.nan, math.nan, math.nan)
    p = float(s.sum()) / total_n
    deff = 1.0
    keep = n > 0
    k = int(keep.sum())
    if k >= 2 and 0.0 < p < 1.0:
        # ratio-estimator variance of p over clusters (trials) against its binomial value
        share = n[keep] / (total_n / k)
        var = float(np.sum(share ** 2 * (s[keep] / n[keep] - p) ** 2)) / (k * (k - 1))
        deff = max(1.0, var * total_n / (p * (1.0 - p)))
    n_eff = total_n / deff
    lo, hi = wilson_interval(min(p * n_eff, n_eff), n_eff, z)
    return (p, lo, hi, deff)


@dataclasses.dataclass(frozen=True)
class LossEstimate:
    """SNR loss of a detector against its reference at one Pd level, in dB.

    ``loss`` is from the full sample; ``lo``, ``hi`` the 95 % paired-bootstrap interval
    (``-inf`` / ``+inf`` when unbounded, NaN when undefined). ``snr_db`` and ``ref_snr_db``
    are the two crossings (``+-inf`` outside the SNR grid).
    """

    level: float
    loss: float
    lo: float
    hi: float
    snr_db: float
    ref_snr_db: float
    undefined_fraction: float

    def within(self, tolerance_db: float) -> bool:
        """The whole interval is at or below ``tolerance_db``: shown to lose at most that."""
        return bool(np.isfinite(self.hi) and self.hi <= tolerance_db)

    def beyond(self, tolerance_db: float) -> bool:
        """The whole interval is above ``tolerance_db``: shown to lose more than that."""
        return bool(not np.isnan(self.lo) and self.lo > tolerance_db)

    def differs(self) -> bool:
        """The interval excludes 0: the detector is shown to differ from its reference."""
        return bool((not np.isnan(self.lo) and self.lo > 0) or (not np.isnan(self.hi) and self.hi < 0))

    def to_dict(self) -> dict:
        return {k: (None if isinstance(v, float) and math.isnan(v) else
                    (("inf" if v > 0 else "-inf") if isinstance(v, float) and math.isinf(v) else v))
                for k, v in dataclasses.asdict(self).items()}


def _difference(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a - b`` with inf - inf (both crossings off the same end of the grid) as NaN."""
    with np.errstate(invalid="ignore"):
        return a - b


def _bounds(samples: np.ndarray, alpha: float = 0.05) -> tuple[float, float, float]:
    """Order-statistic interval of resampled losses that may hold +-inf and NaN.

    NaN (both crossings off the same end) counts as unbounded on both sides: it moves the
    lower bound to -inf and the upper to +inf once it exceeds ``alpha / 2`` of the
    resamples together with the infinities on that side.
    """
    n = samples.size
    nan = np.isnan(samples)
    frac_nan = float(nan.mean()) if n else math.nan
    lo_vals = np.where(nan, -np.inf, samples)
    hi_vals = np.where(nan, np.inf, samples)
    lo = float(np.quantile(lo_vals, alpha / 2, method="lower"))
    hi = float(np.quantile(hi_vals, 1 - alpha / 2, method="higher"))
    return lo, hi, frac_nan


def bootstrap_losses(x, detections, opportunities, pairs, levels=(0.5, 0.8), *,
                     n_boot: int = 1000, seed: int = 0) -> list[list[LossEstimate]]:
    """SNR losses of detector ``i`` against reference ``j`` for each ``(i, j)`` in ``pairs``.

    Parameters
    ----------
    x : array_like
        The SNR grid in dB, strictly increasing, length S.
    detections : numpy.ndarray
        ``(D, S, N)``: detections of each of D detectors at each SNR in each of N trials.
    opportunities : numpy.ndarray
        ``(S, N)``: (segment, target) pairs per trial at each SNR (the same for every
        detector: they saw the same scenes).
    pairs : sequence of (int, int)
        ``(detector, reference)`` index pairs.
    levels : sequence of float
        Pd levels at which the loss is read.
    n_boot : int
        Bootstrap resamples (0: point estimates only, intervals NaN).
    seed : int
        Seed of the resampling (the result is reproducible).

    Returns
    -------
    list of list of LossEstimate
        ``[pair][level]``.
    """
    x = _check_grid(x)
    det = np.asarray(detections, dtype=np.float64)
    opp = np.asarray(opportunities, dtype=np.float64)
    if det.ndim != 3 or det.shape[1] != x.size or opp.shape != det.shape[1:]:
        raise DptbdError(f"detections must be (D, {x.size}, N) and opportunities ({x.size}, N), "
                         f"got {det.shape} and {opp.shape}")
    n_trials = det.shape[2]
    used = sorted({k for pair in pairs for k in pair})
    index = {k: i for i, k in enumerate(used)}
    d_used = det[used]
    opp_tot = opp.sum(axis=1)
    pd_full = d_used.sum(axis=2) / np.maximum(opp_tot, 1)[None]
    boot = None
    if n_boot > 0:
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(0x5EED,)))
        counts = rng.multinomial(n_trials, np.full(n_trials, 1.0 / n_trials), size=n_boot).T
        opp_b = opp @ counts                                   # (S, B)
        det_b = np.einsum("dsn,nb->dbs", d_used, counts)        # (D, B, S)
        boot = (det_b / np.maximum(opp_b.T, 1)[None], opp_b.T)  # Pd (D, B, S), weights (B, S)
    out = []
    for i, j in pairs:
        row = []
        for level in levels:
            est = crossings(x, pd_full[[index[i], index[j]]], level, opp_tot)
            loss = float(_difference(est[:1], est[1:])[0])
            lo = hi = frac = math.nan
            if boot is not None:
                pd_b, w_b = boot
                a = crossings(x, pd_b[index[i]], level, w_b)
                b = crossings(x, pd_b[index[j]], level, w_b)
                lo, hi, frac = _bounds(_difference(a, b))
            row.append(LossEstimate(float(level), loss, lo, hi, float(est[0]), float(est[1]), frac))
        out.append(row)
    return out
