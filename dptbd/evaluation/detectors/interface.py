"""One interface for every detector: a per-frame decision statistic and a state estimate.

Every detector maps a batch of sequences ``(N, T, H, W)`` to :class:`Decisions`: for each
trial and frame a scalar *statistic* (larger = more target-like; ``NaN`` where the
detector makes no decision yet) and the *estimate*, the cell where it would put the
target. A detector declares a target in frame t when ``statistic > threshold``; the
threshold is set on noise-only scenes for a false-alarm probability *per decision*
(:func:`calibrate`), the same for every detector, so that all of them are compared at
the same false-alarm rate. A declaration counts as a detection when the estimate is
within ``gate`` cells (Chebyshev) of the target's true cell in that frame.

==================  =========================================================  ==========
name                detector                                                   statistic
==================  =========================================================  ==========
``dw-dp``           paper 001 direction-weighted DP, fixed point (golden       max E of the
                    model), sliding K-frame segments (stride 1)                segment
``dp-amplitude``    paper 000 eq (15): amplitude DP, no penalty                max h
``dp-penalty``      paper 000 eq (24): amplitude DP + eq (22) penalty          max h
``dp-likelihood``   paper 000 eqs (19)-(23): likelihood-difference DP          max h
``info``            paper 004 Table 1: information accumulation                -H_k
``grid-bayes``      paper 004's grid Bayes filter with existence state         log-odds
``ca-cfar``         CA-CFAR, 16 reference + 2 guard cells, single frame        max ratio
==================  =========================================================  ==========

The DPs of 000 run in the datapath form (:mod:`dptbd.evaluation.detectors.unified`) over
sliding segments like 001's, so that every DP decides every frame from frame K-1 on.
"""

from __future__ import annotations

import dataclasses
import inspect
import math
from typing import Any

import numpy as np

from dptbd.config import DPConfig, non_saturating_energy_bits
from dptbd.evaluation.detectors import cfar, grid, unified
from dptbd.evaluation.detectors._checks import (
    DetectorError, check_bool, check_int, check_prob, check_real, check_shape)

__all__ = [
    "SceneModel",
    "Decisions",
    "Detector",
    "DETECTORS",
    "DEFAULT_DETECTORS",
    "make_detector",
    "parse_detectors",
    "detector_parameters",
    "calibrate",
    "Counts",
    "count_detections",
    "count_false_alarms",
]

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


def _windowed(n_t: int, k: int) -> np.ndarray:
    return np.arange(k - 1, n_t)


class DirectionWeightedDP(Detector):
    """Paper 001's direction-weighted DP in the bit-accurate fixed-point model.

    The frames are quantised like an ADC (``input_bits``, ``gain`` LSB per noise scale,
    Gaussian scenes offset to mid-range), accumulated over sliding K-frame segments
    (stride 1) and the largest E of each segment is the statistic of its last frame.
    """

    name = "dw-dp"
    summary = "paper 001 direction-weighted DP (fixed point, sliding K-frame segments)"

    def __init__(self, model: SceneModel, *, segment_frames: int = 8, input_bits: int = 10,
                 lsb_per_scale: float = 32.0, radius: int | None = None) -> None:
        super().__init__(model)
        self.k = check_int("segment_frames", segment_frames, 1, 64)
        self.bits = check_int("input_bits", input_bits, 4, 16)
        self.lsb = check_real("lsb_per_scale", lsb_per_scale, 0.0, lo_open=True)
        r = model.max_speed if radius is None else check_int("radius", radius, 1, 2)
        h, w = model.shape
        energy = max(16, non_saturating_energy_bits(self.bits, self.k))
        self.cfg = DPConfig(width=w, height=h, segment_frames=self.k, segment_stride=1,
                            input_bits=self.bits, energy_bits=min(32, energy), radius=r)

    def codes(self, frames: np.ndarray) -> np.ndarray:
        from dptbd.scenes.synthetic import quantise
        offset = 0.0 if self.model.noise == "rayleigh" else float(1 << (self.bits - 1))
        return quantise(frames, self.bits, gain=self.lsb / self.model.scale, offset=offset)

    def decide(self, frames: np.ndarray) -> Decisions:
        arr = self._check(frames)
        n, n_t = arr.shape[:2]
        if n_t < self.k:
            raise DetectorError(f"sequences of {n_t} frames are shorter than segment_frames={self.k}")
        try:
            from dptbd.model.fast import run_fixed_fast as run
        except ImportError:
            from dptbd.model.fixed import run_fixed as run
        out = run(self.codes(arr), self.cfg)
        stat = np.full((n, n_t), np.nan)
        est = np.zeros((n, n_t, 2), dtype=np.int64)
        s, e = self._argmax_cells(out.energy)
        stat[:, out.end_frames] = s
        est[:, out.end_frames] = e
        return Decisions(stat, est)


class UnifiedDP(Detector):
    """Paper 000's recursion (25)-(26), float, datapath form, sliding K-frame segments."""

    variant = "amplitude"

    def __init__(self, model: SceneModel, *, segment_frames: int = 8, radius: int | None = None,
                 alpha: float = 1.0, epsilon: float = 0.85, sigma: float = 1.0) -> None:
        super().__init__(model)
        self.k = check_int("segment_frames", segment_frames, 1, 64)
        self.radius = model.max_speed if radius is None else check_int("radius", radius, 1, 2)
        if self.variant == "likelihood":
            self.merit = unified.likelihood_difference_merit(model.amplitude, epsilon, sigma,
                                                             noise_sigma=model.scale)
        else:
            self.merit = unified.amplitude_merit()
            check_real("epsilon (printed alpha in 000 §5.2)", epsilon, 0.0, 1.0, lo_open=True, hi_open=True)
            check_real("sigma (printed delta in 000 §5.2)", sigma, 0.0, lo_open=True)
        check_real("alpha (eq (22) coefficient)", alpha, 0.0, 1.0)  # also where unused (eq (15))
        self.q = (unified.no_penalty(self.radius) if self.variant == "plain"
                  else unified.velocity_log_penalty(self.radius, alpha))

    def decide(self, frames: np.ndarray) -> Decisions:
        arr = self._check(frames)
        n, n_t = arr.shape[:2]
        if n_t < self.k:
            raise DetectorError(f"sequences of {n_t} frames are shorter than segment_frames={self.k}")
        z = arr / (self.model.scale if self.merit.name == "amplitude" else 1.0)
        maps, ends = unified.run_unified_segments(z, self.merit, self.q, segment_frames=self.k,
                                                  segment_stride=1, radius=self.radius)
        stat = np.full((n, n_t), np.nan)
        est = np.zeros((n, n_t, 2), dtype=np.int64)
        s, e = self._argmax_cells(maps)
        stat[:, ends] = s
        est[:, ends] = e
        return Decisions(stat, est)


class AmplitudeDP(UnifiedDP):
    name = "dp-amplitude"
    summary = "paper 000 eq (15): amplitude DP, radius 2 (float, datapath form)"
    variant = "plain"


class PenaltyDP(UnifiedDP):
    name = "dp-penalty"
    summary = "paper 000 eq (24): amplitude DP with the eq (22) velocity penalty"
    variant = "penalty"


class LikelihoodDP(UnifiedDP):
    name = "dp-likelihood"
    summary = "paper 000 eqs (19)-(23): likelihood-difference DP with the eq (22) penalty"
    variant = "likelihood"
    uses_channel = True


class _GridDetector(Detector):
    """Shared set-up of ``info`` and ``grid-bayes``: the transition and the noise scale.

    Parameters
    ----------
    model : SceneModel
        The scenes.
    kernel : array_like or None
        Diffusion kernel (odd sides, non-negative, summing to 1); ``None``: from
        ``sigma_kernel``, else the default of the scene's ``max_speed``.
    sigma_kernel : float or None
        Standard deviation (cells, >= 0) of a Gaussian kernel of radius ``max_speed``, for
        both axes; not together with ``kernel``.
    known_noise : bool
        ``True``: the likelihood uses the model's noise scale; ``False``: estimated per frame.
    """

    uses_channel = True

    def __init__(self, model: SceneModel, *, kernel: Any = None, sigma_kernel: float | None = None,
                 known_noise: bool = False) -> None:
        super().__init__(model)
        known_noise = check_bool("known_noise", known_noise)
        if sigma_kernel is not None:
            if kernel is not None:
                raise DetectorError("give kernel or sigma_kernel, not both")
            sigma_kernel = check_real("sigma_kernel (kernel standard deviation, cells)", sigma_kernel, 0.0)
            kernel = grid.gaussian_kernel(sigma_kernel, sigma_kernel, radius=model.max_speed)
        elif kernel is None and model.max_speed == 1:
            kernel = grid.gaussian_kernel(0.5, 0.5, radius=1)
        elif kernel is None:  # a fast target, no velocity state: flat over the DP's window
            side = 2 * model.max_speed + 1
            kernel = np.full((side, side), 1.0 / (side * side))
        self.transition = grid.Transition(tuple(model.shape), kernel, drift=model.drift)
        self.likelihood = "rician" if model.noise == "rayleigh" else "gaussian"
        self.alpha = model.scale if known_noise else None

    def decide(self, frames: np.ndarray) -> Decisions:
        """Run the subclass's ``filter`` on each sequence: its statistic and estimate per frame."""
        arr = self._check(frames)
        runs = [self.filter.run(seq) for seq in arr]
        return Decisions(np.stack([r.statistic for r in runs]), np.stack([r.estimate for r in runs]))


class InfoDetector(_GridDetector):
    name = "info"
    summary = "paper 004 Table 1: information accumulation, entropy test"

    def __init__(self, model: SceneModel, **kw: Any) -> None:
        super().__init__(model, **kw)
        self.filter = grid.InfoAccumulation(self.transition, snr_db=model.snr_db, alpha=self.alpha,
                                            likelihood=self.likelihood)


class GridBayesDetector(_GridDetector):
    name = "grid-bayes"
    summary = "paper 004's comparison: grid Bayes filter with existence (birth 0.9, death 0.1)"

    def __init__(self, model: SceneModel, *, birth: float = 0.9, death: float = 0.1, **kw: Any) -> None:
        super().__init__(model, **kw)
        self.filter = grid.GridBayes(self.transition, snr_db=model.snr_db, alpha=self.alpha,
                                     likelihood=self.likelihood, birth=birth, death=death)


class CACFARDetector(Detector):
    name = "ca-cfar"
    summary = "CA-CFAR on each frame: 16 reference, 2 guard cells along the range axis"

    def __init__(self, model: SceneModel, *, n_ref: int = 16, n_guard: int = 2, axis: int = -2) -> None:
        super().__init__(model)
        self.axis = cfar.check_axis(axis)  # before indexing the shape with it
        self.n_ref, self.n_guard = cfar._check_window(n_ref, n_guard, model.shape[self.axis])

    def decide(self, frames: np.ndarray) -> Decisions:
        arr = self._check(frames).astype(np.float64)
        if self.model.noise == "gaussian":
            # zero-mean images: square law on the magnitude, one-sided (a bright target)
            ratio = cfar.ca_cfar_ratio(np.abs(arr), n_ref=self.n_ref, n_guard=self.n_guard, axis=self.axis)
            ratio = np.where(arr > 0, ratio, 0.0)
        else:
            ratio = cfar.ca_cfar_ratio(arr, n_ref=self.n_ref, n_guard=self.n_guard, axis=self.axis)
        stat, est = self._argmax_cells(ratio)
        return Decisions(stat, est)


DETECTORS = {cls.name: cls for cls in (DirectionWeightedDP, AmplitudeDP, PenaltyDP, LikelihoodDP,
                                       InfoDetector, GridBayesDetector, CACFARDetector)}
DEFAULT_DETECTORS = tuple(DETECTORS)


def parse_detectors(names: Any) -> tuple[str, ...]:
    """Detector names from a list or a comma-separated string; unknown names are refused."""
    if isinstance(names, str):
        names = [n for n in names.split(",") if n.strip()]
    out = []
    for n in names:
        n = str(n).strip()
        if n not in DETECTORS:
            raise DetectorError(f"unknown detector {n!r}; known: {', '.join(DETECTORS)}")
        if n not in out:
            out.append(n)
    if not out:
        raise DetectorError(f"detectors must name at least one of {', '.join(DETECTORS)}")
    return tuple(out)


def detector_parameters(name: str) -> tuple[str, ...]:
    """The keyword parameters a detector's constructor accepts (its own and its bases')."""
    (name,) = parse_detectors([name])
    out: list[str] = []
    for klass in DETECTORS[name].__mro__:
        init = klass.__dict__.get("__init__")
        if init is None or klass is object:
            continue
        for p in inspect.signature(init).parameters.values():
            if p.kind is inspect.Parameter.KEYWORD_ONLY and p.name not in out:
                out.append(p.name)
    return tuple(out)


def make_detector(name: str, model: SceneModel, **params: Any) -> Detector:
    """Build a detector by name (:data:`DETECTORS`); unknown names and parameters are refused."""
    (name,) = parse_detectors([name])
    allowed = detector_parameters(name)
    for key in params:
        if key not in allowed:
            raise DetectorError(f"detector {name!r} has no parameter {key!r}; it has: {', '.join(allowed)}")
    return DETECTORS[name](model, **params)


def calibrate(statistics: np.ndarray, false_alarm_rate: float) -> float:
    """The threshold with at most ``false_alarm_rate`` of the noise-only decisions above it.

    Like ``docs/arithmetic.md`` §6: with n = floor(rate * decisions), the threshold is the
    (n+1)-th largest statistic, and a decision is a false alarm when ``statistic >
    threshold`` (ties never count). NaN entries (no decision) are ignored.
    """
    rate = check_prob("false_alarm_rate", false_alarm_rate)
    s = np.asarray(statistics, dtype=np.float64)
    s = s[~np.isnan(s)]
    n = int(math.floor(rate * s.size))
    if n < 1:
        raise DetectorError(
            f"false_alarm_rate={rate:g} needs at least {math.ceil(1 / rate)} noise-only decisions "
            f"to set a threshold, got {s.size}; raise the noise trials or the rate")
    return float(np.partition(s, s.size - n - 1)[s.size - n - 1])


@dataclasses.dataclass(frozen=True)
class Counts:
    """Successes out of trials (detections of opportunities, or false alarms of decisions)."""

    hits: int
    total: int

    @property
    def rate(self) -> float:
        return self.hits / self.total if self.total else float("nan")


def count_detections(dec: Decisions, threshold: float, pixel: np.ndarray, visible: np.ndarray,
                     *, first_frame: int = 0, gate: int = 1) -> Counts:
    """Decisions above threshold whose estimate is within ``gate`` of the true cell.

    Opportunities: every (trial, frame >= first_frame) with a decision and a visible target.
    """
    gate = check_int("gate", gate, 0)
    stat, est = dec.statistic, dec.estimate
    n_t = stat.shape[1]
    frames = np.arange(n_t)
    use = (frames >= first_frame) & np.asarray(visible, dtype=bool)
    ok = ~np.isnan(stat) & use[None, :]
    near = np.max(np.abs(est - np.asarray(pixel)[None, :, :]), axis=-1) <= gate
    with np.errstate(invalid="ignore"):
        hit = ok & near & (stat > threshold)
    return Counts(int(hit.sum()), int(ok.sum()))


def count_false_alarms(dec: Decisions, threshold: float, *, first_frame: int = 0) -> Counts:
    """Noise-only decisions above threshold, of all decisions from ``first_frame`` on."""
    stat = dec.statistic[:, first_frame:]
    ok = ~np.isnan(stat)
    with np.errstate(invalid="ignore"):
        return Counts(int((ok & (stat > threshold)).sum()), int(ok.sum()))
