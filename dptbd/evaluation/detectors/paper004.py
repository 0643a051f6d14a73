"""Paper 004's simulations reproduced: scenario 1 (Pfa vs entropy threshold), scenario 2
(Pd vs SNR at equal Pfa), and the single-frame run times of its Table 2.

All on 004's 200 x 500 range-Doppler grid (:class:`~dptbd.scenes.range_doppler.PassiveRadar`)
with the near-constant-velocity transition: the range drift implied by each Doppler cell
plus a 3 x 3 Gaussian diffusion kernel (sigma 0.5 cell).
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any, Callable, Iterable

import numpy as np

from dptbd.evaluation.detectors import cfar, grid, merits, transitions, unified
from dptbd.evaluation.detectors._checks import DetectorError, check_int, check_shape
from dptbd.scenes import range_doppler as rd_scenes

__all__ = ["default_transition", "scenario1", "Scenario1Result", "time_one_frame", "TABLE2"]

#: 004 Table 2: single-frame run time (s), MATLAB R2018b on an i7-8750H.
TABLE2 = {"info": 0.016, "grid-bayes": 0.018, "dp": 1.200, "particle filter": 1.102, "ca-cfar": 0.003}


def default_transition(radar: rd_scenes.PassiveRadar | None = None, sigma: float = 0.5) -> grid.Transition:
    """Drift from Doppler (constant velocity) plus a 3 x 3 Gaussian diffusion kernel."""
    radar = rd_scenes.PassiveRadar() if radar is None else radar
    return grid.Transition(radar.shape, grid.gaussian_kernel(sigma, sigma, 1), drift=radar.range_drift())


@dataclasses.dataclass(frozen=True)
class Scenario1Result:
    """Entropy of information accumulation on noise only, every frame of every run."""

    entropy: np.ndarray  # (runs, frames) H_k in bits
    burn_in: int
    preset_snr_db: float

    def pfa(self, thresholds: Iterable[float]) -> np.ndarray:
        """Fraction of frames (after burn-in) with ``H_k < H_thr``, per threshold."""
        h = self.entropy[:, self.burn_in:].ravel()
        return np.array([np.mean(h < t) for t in thresholds])


def scenario1(runs: int = 10, frames: int = 500, *, preset_snr_db: float = 10.0, burn_in: int = 0,
              seed: int = 404, shape: tuple[int, int] | None = None,
              progress: Callable[[Iterable], Iterable] | None = None) -> Scenario1Result:
    """004 scenario 1: information accumulation on ``runs`` noise-only sequences.

    004 uses 200 runs x 2000 frames; the default here is 10 x 500 (a few minutes).
    """
    runs = check_int("runs", runs, 1)
    frames = check_int("frames", frames, 1)
    radar = rd_scenes.PassiveRadar()
    if shape is not None:
        radar = dataclasses.replace(radar, range_cells=shape[0], doppler_cells=shape[1])
    filt = grid.InfoAccumulation(default_transition(radar), snr_db=preset_snr_db)
    out = np.empty((runs, frames))
    it: Iterable = range(runs)
    if progress is not None:
        it = progress(it)
    chunk = 50
    for r in it:
        # run in chunks of frames, carrying the posterior (bounded memory)
        w = None
        for lo in range(0, frames, chunk):
            n = min(chunk, frames - lo)
            z = rd_scenes.rd_scene(radar.shape, n, None, seed=seed, first_trial=r * 100000 + lo).frames
            h, w = _info_chunk(filt, z, w)
            out[r, lo:lo + n] = h
    return Scenario1Result(out, burn_in, preset_snr_db)


def _info_chunk(filt: grid.InfoAccumulation, z: np.ndarray, w: np.ndarray | None):
    """Table 1 on frames ``z`` starting from posterior ``w`` (uniform if None)."""
    if w is None:
        w = np.full(filt.shape, 1.0 / (filt.shape[0] * filt.shape[1]))
    h = np.empty(z.shape[0])
    for t in range(z.shape[0]):
        pred = filt.transition.predict(w)
        amp, scale = filt._channel(z[t])
        w = np.empty(filt.shape)
        _, h[t], _, _ = grid._update(pred, z[t].astype(np.float64), amp, scale, True, w)
    return h, w


def _best_of(fn: Callable[[], Any], repeats: int) -> float:
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def time_one_frame(repeats: int = 5, frames: int = 10, *, shape: tuple[int, int] | None = None) -> dict:
    """Seconds per frame on the 200 x 500 grid (best of ``repeats`` runs of ``frames`` frames).

    Parameters
    ----------
    repeats : int
        Runs timed per algorithm, >= 1; the best is kept.
    frames : int
        Frames per run, >= 3.
    shape : pair of int or None
        ``(I, J)`` grid, each side >= 19 (CA-CFAR 16/2 needs 19 range cells); ``None``: 004's
        200 x 500 with scenario 2's target. A smaller grid (for a quick check) has a
        target on a straight track from its centre instead.

    Returns
    -------
    dict
        Seconds per frame for ``info``, ``grid-bayes``, ``ca-cfar`` (16/2, one frame),
        ``dw-dp`` (paper 001 fixed point, one DP step; the fused kernel on one thread if
        :mod:`dptbd.model.fast` is there), ``dw-dp golden`` (the plain numpy golden model),
        ``dp-000 datapath`` (paper 000 unified recursion, radius 2, float, one step) and
        ``dp-000 exact`` (expanded state).
    """
    from dptbd.config import DPConfig
    from dptbd.model.fixed import run_fixed

    repeats = check_int("repeats", repeats, 1)
    frames = check_int("frames", frames, 3)
    radar = rd_scenes.PassiveRadar()
    if shape is None:
        track = rd_scenes.scenario2_track(frames=frames)
    else:
        n_i, n_j = check_shape("shape", shape, 65535)
        if min(n_i, n_j) < 19:
            raise DetectorError(f"shape must be at least 19 x 19 cells (CA-CFAR 16/2), got {(n_i, n_j)}")
        radar = dataclasses.replace(radar, range_cells=n_i, doppler_cells=n_j)
        track = rd_scenes.straight_track((n_i / 2, n_j / 2), (0.1, 0.0), frames)
    tr = default_transition(radar)
    scene = rd_scenes.rd_scene(radar.shape, frames, track, snr_db=10.0, seed=1)
    z = scene.frames.astype(np.float64)
    info = grid.InfoAccumulation(tr, snr_db=10.0)
    bayes = grid.GridBayes(tr, snr_db=10.0)
    info.run(z[:2])
    bayes.run(z[:2])
    out = {
        "info": _best_of(lambda: info.run(z), repeats) / frames,
        "grid-bayes": _best_of(lambda: bayes.run(z), repeats) / frames,
        "ca-cfar": _best_of(lambda: cfar.ca_cfar_detect(z, 1e-5), repeats) / frames,
    }
    codes = np.clip(np.rint(z * 32), 0, 1023).astype(np.uint16)
    cfg = DPConfig(width=radar.shape[1], height=radar.shape[0], segment_frames=frames, input_bits=10, energy_bits=16, radius=1)
    try:
        from dptbd.model.fast import run_fixed_fast
        run_fixed_fast(codes[:2], cfg.replace(segment_frames=2), threads=1)
        out["dw-dp"] = _best_of(lambda: run_fixed_fast(codes, cfg, threads=1), repeats) / frames
    except ImportError:  # pragma: no cover
        pass
    out["dw-dp golden"] = _best_of(lambda: run_fixed(codes[:3], cfg.replace(segment_frames=3)), 1) / 3
    merit, q = merits.amplitude_merit(), transitions.velocity_log_penalty(2, 1.0)
    unified.run_unified(z[:2], merit, q)
    out["dp-000 datapath"] = _best_of(lambda: unified.run_unified(z, merit, q), repeats) / frames
    unified.run_unified(z[:2, :8, :8], merit, q, mode="exact")
    out["dp-000 exact"] = _best_of(lambda: unified.run_unified(z[:3], merit, q, mode="exact"), 1) / 3
    return out
