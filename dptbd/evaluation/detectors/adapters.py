"""The eight detectors behind :mod:`~dptbd.evaluation.detectors.interface`'s protocol, and
the registry that builds them by name.

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
``pf-tbd``          particle-filter TBD with existence (Salmond-Birch/Rutten)  log-odds
==================  =========================================================  ==========

The DPs of 000 run in the datapath form (:mod:`dptbd.evaluation.detectors.unified`) over
sliding segments like 001's, so that every DP decides every frame from frame K-1 on.
"""

from __future__ import annotations

import inspect
from typing import Any

import numpy as np

from dptbd.config import DPConfig, non_saturating_energy_bits
from dptbd.evaluation.detectors import cfar, grid, merits, particle, transitions, unified
from dptbd.evaluation.detectors._checks import DetectorError, check_bool, check_int, check_real
from dptbd.evaluation.detectors.interface import Decisions, Detector, SceneModel

__all__ = [
    "DirectionWeightedDP",
    "AmplitudeDP",
    "PenaltyDP",
    "LikelihoodDP",
    "InfoDetector",
    "GridBayesDetector",
    "CACFARDetector",
    "ParticleDetector",
    "DETECTORS",
    "DEFAULT_DETECTORS",
    "make_detector",
    "parse_detectors",
    "detector_parameters",
]


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
            self.merit = merits.likelihood_difference_merit(model.amplitude, epsilon, sigma,
                                                             noise_sigma=model.scale)
        else:
            self.merit = merits.amplitude_merit()
            check_real("epsilon (printed alpha in 000 §5.2)", epsilon, 0.0, 1.0, lo_open=True, hi_open=True)
            check_real("sigma (printed delta in 000 §5.2)", sigma, 0.0, lo_open=True)
        check_real("alpha (eq (22) coefficient)", alpha, 0.0, 1.0)  # also where unused (eq (15))
        self.q = (transitions.no_penalty(self.radius) if self.variant == "plain"
                  else transitions.velocity_log_penalty(self.radius, alpha))

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


class ParticleDetector(Detector):
    """The particle-filter TBD (:mod:`~dptbd.evaluation.detectors.particle`) on each sequence;
    birth velocities bounded by the scene's ``max_speed``, the preset SNR channel as the grid
    filters'."""

    name = "pf-tbd"
    summary = "particle-filter TBD with existence (Salmond-Birch / Rutten), seeded"
    uses_channel = True

    def __init__(self, model: SceneModel, *, particles: int = 3000, birth_particles: int = 3000,
                 birth: float = 0.05, death: float = 0.05, process_noise: float = 0.1,
                 seed: int = 0, known_noise: bool = False) -> None:
        super().__init__(model)
        known_noise = check_bool("known_noise", known_noise)
        self.filter = particle.ParticleTBD(
            tuple(model.shape), snr_db=model.snr_db,
            likelihood="rician" if model.noise == "rayleigh" else "gaussian",
            alpha=model.scale if known_noise else None, max_speed=float(model.max_speed),
            particles=particles, birth_particles=birth_particles, birth=birth, death=death,
            process_noise=process_noise, seed=seed)

    def decide(self, frames: np.ndarray) -> Decisions:
        arr = self._check(frames)
        runs = [self.filter.run(seq) for seq in arr]
        return Decisions(np.stack([r.statistic for r in runs]), np.stack([r.estimate for r in runs]))


DETECTORS = {cls.name: cls for cls in (DirectionWeightedDP, AmplitudeDP, PenaltyDP, LikelihoodDP,
                                       InfoDetector, GridBayesDetector, CACFARDetector,
                                       ParticleDetector)}
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
