"""Paper 004's grid detectors: information accumulation (its Table 1) and the grid Bayes filter.

Both run the recursive Bayes filter on the range-Doppler grid of
:mod:`~dptbd.evaluation.detectors.grid_filter` (transition eqs (16)-(18), likelihood eq
(21), posterior eq (25), entropy eq (26)) and differ in the state and the decision:

* information accumulation (:class:`InfoAccumulation`): the entropy eq (26)
  ``H_k = -sum w log2 w``; target declared when ``H_k < H_thr``, state estimate at the
  maximum of ``w`` (Table 1).
* :class:`GridBayes` is the comparison method of 004 §4.1 (its ref. [16]): the same grid plus
  a "no target" state, birth probability 0.9 and death probability 0.1 as 004 sets them;
  it declares a target when the existence probability is high.

The names of :mod:`~dptbd.evaluation.detectors.grid_filter` (``Transition``,
``gaussian_kernel``, the likelihoods, ``entropy_bits``, ``GridRun``, ...) are importable from
here too.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from dptbd.evaluation.detectors._checks import DetectorError, check_prob, check_real
from dptbd.evaluation.detectors import grid_filter
from dptbd.evaluation.detectors.grid_filter import (
    LIKELIHOODS, GridRun, Transition, _GridFilter, _update, check_kernel, entropy_bits,
    estimate_alpha, gaussian_kernel, gaussian_log_likelihood, log_i0, rician_log_likelihood)

# the shared machinery stays importable from here (it lived in this module before the split)
__all__ = [*grid_filter.__all__, "InfoAccumulation", "GridBayes"]


class InfoAccumulation(_GridFilter):
    """Paper 004 Table 1: grid Bayes filter without an existence state, entropy test.

    Parameters
    ----------
    transition : Transition
        Eqs (16)-(18).
    snr_db : float
        The preset SNR channel that sets eq (21)'s amplitude A (004 §4.1 scenario 3).
    alpha : float or None
        Noise Rayleigh parameter; ``None`` estimates it per frame (:func:`estimate_alpha`,
        "first estimate the noise", 004 §4.1 scenario 3).
    likelihood : str
        ``"rician"`` (eq (21)) or ``"gaussian"`` (its analogue for real Gaussian images).
    entropy_threshold : float or None
        ``H_thr`` in bits, in (0, log2(IJ)]; only for :meth:`detect`.
    """

    def __init__(self, transition: Transition, *, snr_db: float = 10.0, alpha: float | None = None,
                 likelihood: str = "rician", entropy_threshold: float | None = None) -> None:
        super().__init__(transition, snr_db=snr_db, alpha=alpha, likelihood=likelihood)
        h0 = math.log2(self.shape[0] * self.shape[1])
        self.entropy_threshold = (None if entropy_threshold is None else
                                  check_real("entropy_threshold (H_thr)", entropy_threshold, 0.0, h0,
                                             lo_open=True))

    def run(self, frames: Any) -> GridRun:
        """Table 1 over a sequence ``(T, I, J)``, from the uniform prior (``H_0 = log2(IJ)``)."""
        z = self._frames(frames)
        n_t = z.shape[0]
        w = np.full(self.shape, 1.0 / (self.shape[0] * self.shape[1]))
        h = np.empty(n_t)
        est = np.empty((n_t, 2), dtype=np.int64)
        for t in range(n_t):
            pred = self.transition.predict(w)                                # (17)-(18)
            amp, scale = self._channel(z[t])
            w = np.empty(self.shape)
            _, h[t], est[t, 0], est[t, 1] = _update(pred, z[t], amp, scale,  # (21), (24)-(26)
                                                    self.likelihood == "rician", w)
        return GridRun(-h, est, h, w)

    def detect(self, frames: Any) -> tuple[np.ndarray, np.ndarray]:
        """Table 1's decision per frame: ``(H_k < H_thr, argmax w)``."""
        if self.entropy_threshold is None:
            raise DetectorError("entropy_threshold (H_thr) must be set to detect")
        run = self.run(frames)
        return run.entropy < self.entropy_threshold, run.estimate


class GridBayes(_GridFilter):
    """The discrete-grid Bayes filter with a target-existence state (004's comparison, ref. [16]).

    State: "no target" or a target in one of the IJ cells. Predict: no target -> target
    with probability ``birth`` (uniform over the cells); target -> no target with
    probability ``death``, else it moves by :class:`Transition`. Update with eq (21)
    (the "no target" likelihood ratio is 1). Decision statistic: the log-odds of
    existence, ``log P(target) - log P(no target)``.

    Parameters
    ----------
    transition, snr_db, alpha, likelihood
        As :class:`InfoAccumulation`.
    birth, death : float
        Probabilities in (0, 1); 004 sets 0.9 and 0.1.
    initial_existence : float
        ``P(target)`` before the first frame, in (0, 1) (004 does not say; 0.5).
    """

    def __init__(self, transition: Transition, *, snr_db: float = 10.0, alpha: float | None = None,
                 likelihood: str = "rician", birth: float = 0.9, death: float = 0.1,
                 initial_existence: float = 0.5) -> None:
        super().__init__(transition, snr_db=snr_db, alpha=alpha, likelihood=likelihood)
        self.birth = check_prob("birth", birth)
        self.death = check_prob("death", death)
        self.initial_existence = check_prob("initial_existence", initial_existence)

    def run(self, frames: Any) -> GridRun:
        z = self._frames(frames)
        n_t = z.shape[0]
        n_cells = self.shape[0] * self.shape[1]
        w = np.full(self.shape, 1.0 / n_cells)  # target-present posterior (sums to 1)
        log_exist, log_none = math.log(self.initial_existence), math.log1p(-self.initial_existence)
        stat = np.empty(n_t)
        h = np.empty(n_t)
        est = np.empty((n_t, 2), dtype=np.int64)
        for t in range(n_t):
            # predicted probabilities: no target, and target in each cell (sums to 1)
            p_exist = math.exp(log_exist)
            p_none = (1.0 - self.birth) * math.exp(log_none) + self.death * p_exist
            moved = self.transition.predict(w)
            cells = (1.0 - self.death) * p_exist * moved + self.birth * math.exp(log_none) / n_cells
            amp, scale = self._channel(z[t])
            w = np.empty(self.shape)
            log_mass, h[t], est[t, 0], est[t, 1] = _update(cells, z[t], amp, scale,
                                                           self.likelihood == "rician", w)
            total = np.logaddexp(log_mass, math.log(p_none))
            log_exist, log_none = log_mass - total, math.log(p_none) - total
            stat[t] = log_exist - log_none
        return GridRun(stat, est, h, w)
