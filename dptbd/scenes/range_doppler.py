"""Range-Doppler scenes for paper 004's detectors: Swerling I point target in complex noise.

Paper 004 (``../shared/seeds/004_*.txt``, Li, Cen & Tang) observes the magnitude of a
cross-ambiguity (range-Doppler) map, eq (11): ``z = |A + n|`` per cell, with ``n``
zero-mean complex Gaussian noise and ``A`` the target's complex amplitude in its cell.

* **Noise.** ``n = alpha * (g1 + j g2)``, ``g`` standard normal: ``|n|`` is Rayleigh with
  parameter ``alpha`` (eq (19), "alpha**2 is the noise variance" read as the variance per
  quadrature component), ``E|n|**2 = 2 alpha**2``.
* **Target.** Swerling I (004 §4.1 scenario 2: "RCS fluctuates as Swerling I"): the
  complex amplitude is ``sqrt(P/2) * (g1 + j g2)``, so ``|A|**2`` is exponential with mean
  ``P`` and the phase uniform, drawn independently in every frame (scan to scan), constant
  within a frame. The ambiguity function is taken as an ideal thumbtack (004 Fig. 2 is
  "close to a thumbtack"): all of the target's energy is in the cell nearest its true
  (delay, Doppler) position, ``np.rint`` as in :mod:`dptbd.scenes.synthetic`.
* **SNR** is the average per-cell SNR of the map, ``P / E|n|**2 = P / (2 alpha**2)``.

:class:`PassiveRadar` computes a target's (delay, Doppler) track from 004's geometry,
eqs (3)-(4) and (8)-(9), for scenario 2 (:func:`scenario2_track`), and the range drift
per Doppler cell that the near-constant-velocity transition uses.

Coordinates are ``(row, col) = (delay cell i, Doppler cell j)``.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import Any

import numpy as np

from dptbd import errors
from dptbd.scenes._checks import SceneError

__all__ = [
    "PassiveRadar",
    "SCENARIO2",
    "scenario2_track",
    "straight_track",
    "swerling1_amplitudes",
    "mean_power_from_snr_db",
    "RDScene",
    "rd_scene",
]

_check_int = functools.partial(errors.check_int, error=SceneError)
_check_real = functools.partial(errors.check_real, error=SceneError)

C_LIGHT = 299_792_458.0


@dataclasses.dataclass(frozen=True)
class PassiveRadar:
    """Paper 004 §4.1: FM emitter at 97.4 MHz, f_s = 200 kHz, T = 0.5 s, I = 200, J = 500.

    Delay cell ``i``: ``t_i = t0 + i / f_s`` (eq (8)); Doppler cell ``j``:
    ``f_j = f0 + j / T`` (eq (9)), ``f0 = -500 Hz``.
    """

    emitter: tuple[float, float, float] = (0.0, -75e3, 300.0)
    receiver: tuple[float, float, float] = (0.0, 0.0, 70.0)
    carrier_hz: float = 97.4e6
    sample_rate_hz: float = 200e3
    frame_s: float = 0.5
    range_cells: int = 200
    doppler_cells: int = 500
    t0: float = 0.0
    f0: float = -500.0

    @property
    def shape(self) -> tuple[int, int]:
        """``(I, J)``."""
        return self.range_cells, self.doppler_cells

    def delay_doppler(self, position: np.ndarray, velocity: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Eqs (3)-(4): bistatic delay ``tau`` (s) and Doppler ``f_d`` (Hz), as written in 004."""
        x = np.asarray(position, dtype=np.float64)
        v = np.asarray(velocity, dtype=np.float64)
        to_e = x - np.asarray(self.emitter)
        to_r = x - np.asarray(self.receiver)
        de = np.linalg.norm(to_e, axis=-1)
        dr = np.linalg.norm(to_r, axis=-1)
        tau = (de + dr) / C_LIGHT
        fd = self.carrier_hz / C_LIGHT * np.sum(v * (to_e / de[..., None] + to_r / dr[..., None]), axis=-1)
        return tau, fd

    def cells(self, position: np.ndarray, velocity: np.ndarray) -> np.ndarray:
        """Float ``(i, j)`` cell coordinates of targets at ``position`` moving at ``velocity``."""
        tau, fd = self.delay_doppler(position, velocity)
        return np.stack([(tau - self.t0) * self.sample_rate_hz, (fd - self.f0) * self.frame_s], axis=-1)

    def range_drift(self) -> np.ndarray:
        """Delay cells per frame implied by each Doppler cell: ``f_j T f_s / f_c``, shape ``(J,)``.

        By eq (4) ``f_d = (dR/dt) / lambda``, so a target in Doppler cell ``j`` changes its
        delay by ``f_j * lambda * T / c`` seconds per frame: the constant-velocity part of
        the transition (:class:`dptbd.evaluation.detectors.grid.Transition`).
        """
        f = self.f0 + np.arange(self.doppler_cells) / self.frame_s
        return f * self.frame_s * self.sample_rate_hz / self.carrier_hz


#: Paper 004 §4.1 scenario 2: start (50, 60, 1) km, v = (-180, -120, -2) m/s, 50 frames.
SCENARIO2 = dict(start=(50e3, 60e3, 1e3), velocity=(-180.0, -120.0, -2.0), frames=50)


def scenario2_track(radar: PassiveRadar | None = None, frames: int = 50) -> np.ndarray:
    """Float ``(T, 2)`` (delay cell, Doppler cell) of scenario 2's target, frame by frame."""
    radar = PassiveRadar() if radar is None else radar
    frames = _check_int("frames", frames, 1)
    t = np.arange(frames)[:, None] * radar.frame_s
    v = np.asarray(SCENARIO2["velocity"])
    pos = np.asarray(SCENARIO2["start"]) + t * v
    return radar.cells(pos, np.broadcast_to(v, pos.shape))


def straight_track(start: tuple[float, float], velocity: tuple[float, float], frames: int) -> np.ndarray:
    """Float ``(T, 2)`` cells of a target moving ``velocity`` cells per frame from ``start``."""
    frames = _check_int("frames", frames, 1)
    s = np.array([_check_real("start[0]", start[0]), _check_real("start[1]", start[1])])
    v = np.array([_check_real("velocity[0]", velocity[0]), _check_real("velocity[1]", velocity[1])])
    return s + np.arange(frames)[:, None] * v


def mean_power_from_snr_db(snr_db: float, alpha: float = 1.0) -> float:
    """Mean target power ``P = 2 alpha**2 10**(SNR/10)`` for an average per-cell SNR in dB."""
    snr_db = _check_real("snr_db", snr_db)
    alpha = _check_real("alpha (noise scale)", alpha, 0.0, lo_open=True)
    return 2.0 * alpha * alpha * 10.0 ** (snr_db / 10.0)


def swerling1_amplitudes(rng: np.random.Generator, mean_power: float, size: Any) -> np.ndarray:
    """Complex Swerling I amplitudes: ``|A|**2 ~ Exp(mean_power)``, uniform phase."""
    p = _check_real("mean_power", mean_power, 0.0)
    shape = (int(size),) if isinstance(size, (int, np.integer)) else tuple(int(s) for s in size)
    g = rng.standard_normal(shape + (2,))
    return math.sqrt(p / 2.0) * (g[..., 0] + 1j * g[..., 1])


@dataclasses.dataclass(frozen=True)
class RDScene:
    """Magnitude range-Doppler frames with ground truth.

    Attributes
    ----------
    frames : numpy.ndarray
        ``(T, I, J)`` or ``(N, T, I, J)`` magnitudes ``|A + n|``.
    track : numpy.ndarray or None
        ``(T, 2)`` float true (delay, Doppler) cell; ``None`` for noise only.
    pixel : numpy.ndarray or None
        ``(T, 2)`` int, ``np.rint(track)``.
    visible : numpy.ndarray
        ``(T,)`` bool: a target is drawn in that frame (inside the grid).
    params : dict
        ``snr_db``, ``alpha``, ``seed``, ``trials``, ``first_trial``, ``shape``.
    """

    frames: np.ndarray
    track: np.ndarray | None
    pixel: np.ndarray | None
    visible: np.ndarray
    params: dict

    @property
    def n_frames(self) -> int:
        return self.frames.shape[-3]


def rd_scene(shape: tuple[int, int] = (200, 500), frames: int = 50, track: Any = None, *,
             snr_db: float = 10.0, alpha: float = 1.0, seed: int = 0, trials: int | None = None,
             first_trial: int = 0, dtype: Any = np.float32) -> RDScene:
    """Generate magnitude range-Doppler frames.

    Trial ``k`` (``first_trial + i``) draws its noise from ``SeedSequence(seed,
    spawn_key=(k, 0))`` and its target amplitudes from ``spawn_key=(k, 1)``: the noise is
    the same with or without a target and whatever the batch size.

    Parameters
    ----------
    shape : pair of int
        ``(I, J)`` delay x Doppler cells, each in [1, 65535].
    frames : int
        T >= 1.
    track : array_like or None
        ``(T, 2)`` float target cells (:func:`scenario2_track`, :func:`straight_track`),
        or ``None`` for noise only.
    snr_db : float
        Average per-cell SNR of the target, ``P / (2 alpha**2)`` in dB.
    alpha : float
        Rayleigh parameter of the noise magnitude (> 0).
    seed : int
        Root seed, >= 0.
    trials : int or None
        N for a batch ``(N, T, I, J)``; ``None`` for one sequence ``(T, I, J)``.
    first_trial : int
        Index of the first trial.
    dtype : float32 or float64
    """
    n_i, n_j = errors.check_shape("shape", shape, 65535, axes=("delay cells", "Doppler cells"),
                                  error=SceneError)
    n_t = _check_int("frames", frames, 1)
    alpha = _check_real("alpha (noise scale)", alpha, 0.0, lo_open=True)
    power = mean_power_from_snr_db(snr_db, alpha)
    seed = _check_int("seed", seed, 0)
    first_trial = _check_int("first_trial", first_trial, 0)
    n = 1 if trials is None else _check_int("trials", trials, 1)
    dt = np.dtype(dtype)
    if dt not in (np.dtype(np.float32), np.dtype(np.float64)):
        raise SceneError(f"dtype must be float32 or float64, got {dt}")
    if track is None:
        trk = pix = None
        visible = np.zeros(n_t, dtype=bool)
    else:
        trk = np.asarray(track, dtype=np.float64)
        if trk.shape != (n_t, 2) or not np.all(np.isfinite(trk)):
            raise SceneError(f"track must be a finite ({n_t}, 2) array of cells, got shape {trk.shape}")
        pix = np.rint(trk).astype(np.int64)
        visible = (pix[:, 0] >= 0) & (pix[:, 0] < n_i) & (pix[:, 1] >= 0) & (pix[:, 1] < n_j)
    out = np.empty((n, n_t, n_i, n_j), dtype=dt)
    tv = np.flatnonzero(visible)
    for b in range(n):
        k = first_trial + b
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(k, 0)))
        re = rng.standard_normal((n_t, n_i, n_j), dtype=dt)
        im = rng.standard_normal((n_t, n_i, n_j), dtype=dt)
        re *= dt.type(alpha)
        im *= dt.type(alpha)
        if pix is not None and tv.size:
            amp = swerling1_amplitudes(np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(k, 1))),
                                       power, n_t)
            re[tv, pix[tv, 0], pix[tv, 1]] += amp[tv].real.astype(dt)
            im[tv, pix[tv, 0], pix[tv, 1]] += amp[tv].imag.astype(dt)
        np.hypot(re, im, out=out[b])
    params = dict(snr_db=float(snr_db), alpha=alpha, seed=seed, trials=trials,
                  first_trial=first_trial, shape=(n_i, n_j))
    return RDScene(out[0] if trials is None else out, trk, pix, visible, params)
