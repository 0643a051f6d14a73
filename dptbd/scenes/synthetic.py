"""Synthetic image sequences for DP-TBD: noise plus point targets, and the papers' scenarios.

One generator serves both papers' scene models (paper 001 §4 and paper 000 §3/§5): i.i.d.
Gaussian noise of mean ``mu`` and standard deviation ``sigma`` (:func:`make_noise`) plus
point targets (:mod:`dptbd.scenes.targets`) whose amplitude follows from an SNR
(:mod:`dptbd.scenes.snr`); :func:`make_scene` returns the frames with their ground truth
(:class:`Scene`), and the built-in scenarios are the papers' experiments. The ADC that
turns a scene into integer frames is :mod:`dptbd.scenes.adc` (also :meth:`Scene.quantised`).

Noise and targets are separable: the noise of trial ``i`` depends only on ``(seed, i)``
(:func:`make_noise`), never on the targets, so a scene minus the noise-only frames of
the same seed is the target signal, and ``noise=False`` gives the exact noise-free
scene (background ``mu`` plus amplitudes).

The names of the sibling modules (``Target``, ``Turn``, ``TargetTruth``, ``target_truth``,
the motion and SNR conversions, ``quantise``, ``INPUT_BITS``, ``ADC_GAIN``, ``SceneError``)
are importable from here too.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Iterable, Sequence

import numpy as np

from dptbd.errors import check_bool
from dptbd.scenes._checks import (_MAX_FRAMES, _MAX_SIZE, SceneError, _check_int, _check_pair,
                                  _check_real, _check_shape)
from dptbd.scenes.adc import ADC_GAIN, INPUT_BITS, quantise
from dptbd.scenes.snr import (amplitude_from_snr, amplitude_from_snr_db, snr_db_from_amplitude,
                              snr_from_amplitude)
from dptbd.scenes.targets import (Target, TargetTruth, Turn, paper000_motion, paper001_motion,
                                  target_truth)

__all__ = [
    "SceneError",
    "Turn",
    "Target",
    "TargetTruth",
    "Scene",
    "amplitude_from_snr",
    "snr_from_amplitude",
    "amplitude_from_snr_db",
    "snr_db_from_amplitude",
    "paper001_motion",
    "paper000_motion",
    "target_truth",
    "make_noise",
    "make_scene",
    "quantise",
    "table1_scenario",
    "paper001_one_target",
    "paper001_two_targets",
    "paper000_scenario",
    "TABLE1_MU",
    "TABLE1_SIGMA",
    "INPUT_BITS",
    "ADC_GAIN",
]

#: Paper 001 Table 1 noise: mean 30, "variance 3.0".
TABLE1_MU = 30.0
TABLE1_SIGMA = math.sqrt(3.0)

_MAX_TRIALS = 10**7
_FLOAT_DTYPES = (np.dtype(np.float32), np.dtype(np.float64))


def _check_dtype(dtype: Any) -> np.dtype:
    try:
        dt = np.dtype(dtype)
    except TypeError as exc:
        raise SceneError(f"dtype must be float32 or float64, got {dtype!r}") from exc
    if dt not in _FLOAT_DTYPES:
        raise SceneError(f"dtype must be float32 or float64, got {dt}")
    return dt


def _check_trials(trials: Any) -> int | None:
    return None if trials is None else _check_int("trials", trials, 1, _MAX_TRIALS)


def _seed_entropy(seed: Any) -> int:
    """The root entropy of a seed: a non-negative int, or fresh entropy for ``None``."""
    if seed is None:
        return int(np.random.SeedSequence().entropy)
    if isinstance(seed, np.random.SeedSequence):
        if seed.spawn_key:
            raise SceneError("seed must be a root SeedSequence (empty spawn_key) or an int")
        return int(seed.entropy)
    return _check_int("seed", seed, 0)


# ---- scenes ------------------------------------------------------------------------------

@dataclasses.dataclass(frozen=True)
class Scene:
    """A generated image sequence with its ground truth.

    Attributes
    ----------
    frames : numpy.ndarray
        Float frames, shape ``(T, H, W)``, or ``(N, T, H, W)`` for a batch of N trials
        (independent noise, the same targets).
    truth : tuple of TargetTruth
        One entry per target, in the order given (the same for every trial).
    targets : tuple of Target
        The targets.
    params : dict
        Generation parameters: ``shape``, ``frames``, ``mu``, ``sigma``, ``seed`` (root
        entropy; reproduces the scene), ``trials``, ``first_trial``, ``dtype``, ``noise``,
        plus ``scenario`` and paper parameters for the built-in scenarios.
    """

    frames: np.ndarray
    truth: tuple[TargetTruth, ...]
    targets: tuple[Target, ...]
    params: dict

    @property
    def n_frames(self) -> int:
        """T, the number of frames per trial."""
        return self.frames.shape[-3]

    @property
    def shape(self) -> tuple[int, int]:
        """``(height, width)`` of a frame."""
        return self.frames.shape[-2], self.frames.shape[-1]

    @property
    def trials(self) -> int | None:
        """N for a batch, ``None`` for a single sequence."""
        return self.params["trials"]

    def quantised(self, input_bits: int, *, gain: float = 1.0, offset: float = 0.0) -> np.ndarray:
        """The frames as ``input_bits``-bit ADC codes (:func:`quantise`), ``uint16``."""
        return quantise(self.frames, input_bits, gain=gain, offset=offset)

    def target_mask(self) -> np.ndarray:
        """``bool (T, H, W)``: True at every visible target pixel of every frame."""
        mask = np.zeros((self.n_frames,) + self.shape, dtype=bool)
        for tr in self.truth:
            t = np.flatnonzero(tr.visible)
            mask[t, tr.pixel[t, 0], tr.pixel[t, 1]] = True
        return mask


def make_noise(shape: tuple[int, int], frames: int, *, mu: float = 0.0, sigma: float = 1.0,
               seed: int | np.random.SeedSequence | None = 0, trials: int | None = None,
               first_trial: int = 0, dtype: Any = np.float64) -> np.ndarray:
    """I.i.d. Gaussian noise ``N(mu, sigma**2)`` frames, reproducible per trial.

    Trial ``i`` draws from its own generator, ``default_rng(SeedSequence(seed,
    spawn_key=(first_trial + i,)))`` (the ``first_trial + i``-th child of the seed), so
    trial ``k`` of a batch is the same whatever the batch size, and a long run can be
    generated in chunks with ``first_trial``. A single sequence (``trials=None``) is trial
    ``first_trial``.

    Parameters
    ----------
    shape : pair of int
        ``(height, width)``, each in [1, 65535].
    frames : int
        T, frames per trial, >= 1.
    mu, sigma : float
        Noise mean (finite) and standard deviation (> 0).
    seed : int >= 0, root SeedSequence or None
        ``None`` draws fresh entropy (not reproducible unless read back from a scene's
        ``params["seed"]``).
    trials : int or None
        N >= 1 for a batch of shape ``(N, T, H, W)``; ``None`` for ``(T, H, W)``.
    first_trial : int
        Index of the first trial, >= 0.
    dtype : float32 or float64
        float32 halves the memory (50 x 100 x 128 x 128 trials: 330 MB instead of 655 MB).

    Returns
    -------
    numpy.ndarray
        The noise frames.
    """
    out, _ = _noise(shape, frames, mu, sigma, seed, trials, first_trial, dtype)
    return out


def _noise(shape, frames, mu, sigma, seed, trials, first_trial, dtype):
    """Validated noise generation; also returns the root entropy."""
    height, width = _check_shape(shape)
    frames = _check_int("frames", frames, 1, _MAX_FRAMES)
    mu = _check_real("mu", mu)
    sigma = _check_real("sigma", sigma, positive=True)
    trials = _check_trials(trials)
    first_trial = _check_int("first_trial", first_trial, 0)
    dt = _check_dtype(dtype)
    entropy = _seed_entropy(seed)
    n = 1 if trials is None else trials
    out = np.empty((n, frames, height, width), dtype=dt)
    for i in range(n):
        seq = np.random.SeedSequence(entropy, spawn_key=(first_trial + i,))
        rng = np.random.default_rng(seq)
        rng.standard_normal(out=out[i], dtype=dt)
        out[i] *= dt.type(sigma)
        out[i] += dt.type(mu)
    return (out[0] if trials is None else out), entropy


def make_scene(shape: tuple[int, int], frames: int, targets: Iterable[Target] = (), *,
               mu: float = 0.0, sigma: float = 1.0,
               seed: int | np.random.SeedSequence | None = 0, trials: int | None = None,
               first_trial: int = 0, dtype: Any = np.float64, noise: bool = True) -> Scene:
    """Noise plus point targets, with ground truth.

    Each pixel is a draw of ``N(mu, sigma**2)`` (:func:`make_noise`, same seed scheme);
    each target adds its ``amplitude`` at its pixel ``np.rint(position)`` in every frame
    where it is visible (alive and inside the image; a target outside the image is simply
    not drawn). Targets on the same pixel add up. The noise does not depend on the targets.

    Parameters
    ----------
    shape : pair of int
        ``(height, width)``, each in [1, 65535].
    frames : int
        T >= 1.
    targets : iterable of Target
        The targets (may be empty).
    mu, sigma : float
        Background mean and noise standard deviation (> 0).
    seed, trials, first_trial, dtype
        As in :func:`make_noise`.
    noise : bool
        ``False`` replaces the noise by the constant background ``mu`` (exact noise-free
        scene, for tests and figures); ``sigma`` is then only recorded.

    Returns
    -------
    Scene
        Frames ``(T, H, W)`` or ``(N, T, H, W)``, truth, targets and parameters.
    """
    try:
        targets = tuple(targets)
    except TypeError as exc:
        raise SceneError(f"targets must be an iterable of Target, got {targets!r}") from exc
    noise = check_bool("noise", noise, error=SceneError)
    if noise:
        out, entropy = _noise(shape, frames, mu, sigma, seed, trials, first_trial, dtype)
    else:
        out, entropy = _flat(shape, frames, mu, sigma, seed, trials, first_trial, dtype)
    truth = tuple(target_truth(tg, shape, frames) for tg in targets)
    for tr in truth:
        _draw(out, tr)
    params = dict(shape=tuple(out.shape[-2:]), frames=int(frames), mu=float(mu),
                  sigma=float(sigma), seed=entropy, trials=trials, first_trial=int(first_trial),
                  dtype=str(out.dtype), noise=noise)
    return Scene(out, truth, targets, params)


def _flat(shape, frames, mu, sigma, seed, trials, first_trial, dtype):
    """The noise-free background, validated like :func:`_noise`."""
    height, width = _check_shape(shape)
    frames = _check_int("frames", frames, 1, _MAX_FRAMES)
    _check_real("sigma", sigma, positive=True)
    _check_int("first_trial", first_trial, 0)
    trials = _check_trials(trials)
    dt = _check_dtype(dtype)
    entropy = _seed_entropy(seed)
    lead = () if trials is None else (trials,)
    return np.full(lead + (frames, height, width), _check_real("mu", mu), dtype=dt), entropy


def _draw(frames: np.ndarray, truth: TargetTruth) -> None:
    """Add a target's amplitude at its visible pixels, in place, in every trial."""
    t = np.flatnonzero(truth.visible)
    if t.size:
        frames[..., t, truth.pixel[t, 0], truth.pixel[t, 1]] += frames.dtype.type(truth.amplitude)


# ---- built-in scenarios -----------------------------------------------------------------

def _centred_start(shape: tuple[int, int], velocity: tuple[float, float],
                   n_frames: int) -> tuple[float, float]:
    """Integer start that centres a straight trajectory of ``n_frames`` frames in the image."""
    return tuple(float(np.rint((size - 1) / 2.0 - v * (n_frames - 1) / 2.0))
                 for size, v in zip(shape, velocity))


def table1_scenario(snr: float = 2.3, velocity: Sequence[float] = (1.0, 1.0), *,
                    start: Sequence[float] | None = None, frames: int = 100, size: int = 128,
                    mu: float = TABLE1_MU, sigma: float = TABLE1_SIGMA, seed: Any = 0,
                    trials: int | None = None, first_trial: int = 0,
                    dtype: Any = np.float64, noise: bool = True) -> Scene:
    """Paper 001 Table 1: one target, 128 x 128, 100 frames, noise mean 30 and variance 3.

    Parameters
    ----------
    snr : float
        001's linear SNR (Table 1: 2.0 or 2.3); amplitude ``snr * sigma``.
    velocity : pair of float
        001's ``(Vx, Vy)`` (Table 1: ``(1, 1)``, ``(0.8, -0.4)``, ``(0.4, 0.6)``), mapped
        to ``(row, col)`` by :func:`paper001_motion`.
    start : pair of float or None
        001's start, mapped likewise. Table 1 gives none; ``None`` centres the trajectory
        in the image and rounds the start to a pixel: ``round((size - 1)/2 - v (frames -
        1)/2)`` per axis. For ``(1, 1)`` that is ``(14, 14)``, ending at ``(113, 113)``;
        for ``(0.8, -0.4)`` ``(24, 83)``; for ``(0.4, 0.6)`` ``(44, 34)``. 001's figure
        experiments start ``(0.8, -0.4)`` at ``(30, 100)`` and ``(0.4, 0.6)`` at
        ``(54, 40)`` (pass them to reproduce those).
    frames, size, mu, sigma
        Sequence length, square frame size, noise mean and standard deviation
        (``sqrt(3)``).
    seed, trials, first_trial, dtype, noise
        As in :func:`make_scene`.

    Returns
    -------
    Scene
    """
    vel = _check_pair("velocity", velocity)
    n = _check_int("frames", frames, 1, _MAX_FRAMES)
    size = _check_int("size", size, 1, _MAX_SIZE)
    start = _centred_start((size, size), vel, n) if start is None else start
    start_rc, vel_rc = paper001_motion(start, vel)
    target = Target(start_rc, vel_rc, amplitude_from_snr(snr, sigma))
    scene = make_scene((size, size), n, [target], mu=mu, sigma=sigma, seed=seed, trials=trials,
                       first_trial=first_trial, dtype=dtype, noise=noise)
    scene.params.update(scenario="paper001_table1", snr=float(snr))
    return scene


def paper001_one_target(snr: float = 2.0, **kwargs: Any) -> Scene:
    """Paper 001 §4 first figure experiment: 128 x 128, 100 frames, SNR 2.0, one target.

    Start ``(30, 100)``, ``V_x = 0.8``, ``V_y = -0.4`` (:func:`paper001_motion`).
    Keyword arguments (``seed``, ``trials``, ``dtype``, ``noise``, ...) go to
    :func:`table1_scenario`.
    """
    scene = table1_scenario(snr, (0.8, -0.4), start=(30.0, 100.0), **kwargs)
    scene.params["scenario"] = "paper001_one_target"
    return scene


def paper001_two_targets(snr: float = 2.0, *, seed: Any = 0, trials: int | None = None,
                         first_trial: int = 0, dtype: Any = np.float64,
                         noise: bool = True) -> Scene:
    """Paper 001 §4 second figure experiment: 128 x 128, 100 frames, SNR 2.0, two targets.

    Target 1 starts at ``(30, 100)`` with ``V_x = 0.8, V_y = -0.4``; target 2 at
    ``(54, 40)`` with ``V_x = 0.4, V_y = 0.6`` (:func:`paper001_motion`). Noise mean 30,
    variance 3.

    Returns
    -------
    Scene
    """
    amp = amplitude_from_snr(snr, TABLE1_SIGMA)
    targets = [Target(*paper001_motion((30.0, 100.0), (0.8, -0.4)), amp),
               Target(*paper001_motion((54.0, 40.0), (0.4, 0.6)), amp)]
    scene = make_scene((128, 128), 100, targets, mu=TABLE1_MU, sigma=TABLE1_SIGMA, seed=seed,
                       trials=trials, first_trial=first_trial, dtype=dtype, noise=noise)
    scene.params.update(scenario="paper001_two_targets", snr=float(snr))
    return scene


def paper000_scenario(snr_db: float = 4.08, *, size: int = 64, frames: int = 20,
                      sigma: float = 1.0, seed: Any = 0, trials: int | None = None,
                      first_trial: int = 0, dtype: Any = np.float64,
                      noise: bool = True) -> Scene:
    """Paper 000 §5.1: 64 x 64, 20 frames, zero-mean Gaussian noise, SNR 4.08 dB (A = 1.6).

    000 §5.1 gives 20 frames, SNR 4.08 dB, start ``(12, 52)``, ``v_x = -2``, ``v_y = 2``
    cells/frame and ``A = 1.6``; the size 64 x 64 comes from the identical set-up of §5.2.
    Eq (7) gives zero-mean Gaussian noise; ``A = 1.6`` at 4.08 dB means ``sigma = 1``
    (``10**(4.08/20) = 1.5996``). The motion is mapped by :func:`paper000_motion`:
    start ``(row 12, col 52)``, velocity ``(+2, -2)`` (row, col), ending at ``(50, 14)``.
    The frames are zero-mean: quantise with an ``offset`` (and ``gain``).

    Returns
    -------
    Scene
    """
    start, vel = paper000_motion((12.0, 52.0), vx=-2.0, vy=2.0)
    target = Target(start, vel, amplitude_from_snr_db(snr_db, sigma))
    scene = make_scene((size, size), frames, [target], mu=0.0, sigma=sigma, seed=seed,
                       trials=trials, first_trial=first_trial, dtype=dtype, noise=noise)
    scene.params.update(scenario="paper000_5.1", snr_db=float(snr_db))
    return scene
