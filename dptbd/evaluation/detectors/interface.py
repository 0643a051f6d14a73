"""One interface for every detector: a per-frame decision statistic and a state estimate.

Every detector maps a batch of sequences ``(N, T, H, W)`` to :class:`Decisions`: for each
trial and frame a scalar *statistic* (larger = more target-like; ``NaN`` where the detector
makes no decision yet) and the *estimate*, the cell where it would put the target. A
detector declares a target in frame t when ``statistic > threshold``; the threshold is set
on noise-only scenes for a false-alarm probability *per decision*
(:func:`~dptbd.evaluation.detectors.scoring.calibrate`), the same for every detector, so
that all of them are compared at the same false-alarm rate. A declaration counts as a
detection when the estimate is within ``gate`` cells (Chebyshev) of the target's true cell
in that frame.

The eight detectors behind this interface, by name, are
:mod:`dptbd.evaluation.detectors.adapters`; thresholds and counts are
:mod:`dptbd.evaluation.detectors.scoring`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from dptbd.evaluation.detectors._checks import DetectorError, check_int, check_real, check_shape

__all__ = ["SceneModel", "Decisions", "Detector", "NOISE_MODELS"]


NOISE_MODELS = ("rayleigh", "gaussian")


@dataclasses.dataclass(frozen=True)
class SceneModel:
    """What a detector may know about the scenes it runs on.

    Attributes
    ----------
    shape : pair of int
        ``(H, W)`` cells, each an integer in [1, 65535].
    noise : str
        ``"rayleigh"`` (magnitudes of complex Gaussian noise, parameter ``scale``) or
        ``"gaussian"`` (real zero-mean Gaussian, standard deviation ``scale``).
    scale : float
        Noise scale, > 0.
    snr_db : float
        The preset SNR channel for detectors whose likelihood needs a target amplitude
        (info, grid-bayes, dp-likelihood).
    max_speed : int
        Largest target move in cells per frame the scene has (1 or 2): the DP window radius.
    drift : numpy.ndarray or None
        ``(W,)`` delay cells per frame for each Doppler column (range-Doppler scenes), for
        the grid filters' transition; ``None`` means 0.
    """

    shape: tuple[int, int]
    noise: str = "rayleigh"
    scale: float = 1.0
    snr_db: float = 10.0
    max_speed: int = 1
    drift: np.ndarray | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "shape", check_shape("shape", self.shape, 65535))
        if self.noise not in NOISE_MODELS:
            raise DetectorError(f"noise must be one of {NOISE_MODELS}, got {self.noise!r}")
        check_real("scale (noise)", self.scale, 0.0, lo_open=True)
        check_real("snr_db (preset SNR channel)", self.snr_db, -30.0, 60.0)
        check_int("max_speed", self.max_speed, 1, 2)

    @property
    def amplitude(self) -> float:
        """Target amplitude of the preset channel: ``sqrt(2 SNR) alpha`` (Rayleigh), ``sqrt(SNR) sigma``."""
        snr = 10.0 ** (self.snr_db / 10.0)
        return self.scale * math.sqrt((2.0 if self.noise == "rayleigh" else 1.0) * snr)


@dataclasses.dataclass(frozen=True)
class Decisions:
    """Per-frame statistic ``(N, T)`` (NaN = no decision) and estimate ``(N, T, 2)``."""

    statistic: np.ndarray
    estimate: np.ndarray


class Detector:
    """Base class: ``decide(frames (N, T, H, W)) -> Decisions``."""

    name = "detector"
    summary = ""
    #: True when the detector depends on the preset SNR channel (recalibrated per SNR when matched)
    uses_channel = False

    def __init__(self, model: SceneModel) -> None:
        if not isinstance(model, SceneModel):
            raise DetectorError(f"model must be a SceneModel, got {model!r}")
        self.model = model

    def decide(self, frames: np.ndarray) -> Decisions:  # pragma: no cover - abstract
        raise NotImplementedError

    def _check(self, frames: Any) -> np.ndarray:
        arr = np.asarray(frames)
        if arr.ndim != 4 or arr.shape[-2:] != tuple(self.model.shape):
            raise DetectorError(f"frames must be (N, T, {self.model.shape[0]}, {self.model.shape[1]}), "
                                f"got shape {arr.shape}")
        return arr

    @staticmethod
    def _argmax_cells(maps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        flat = maps.reshape(maps.shape[:-2] + (-1,))
        idx = np.argmax(flat, axis=-1)
        stat = np.take_along_axis(flat, idx[..., None], axis=-1)[..., 0].astype(np.float64)
        est = np.stack(np.unravel_index(idx, maps.shape[-2:]), axis=-1).astype(np.int64)
        return stat, est
