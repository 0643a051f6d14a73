"""Synthetic image sequences for DP-TBD: noise, point targets, ground truth, ADC quantisation.

One generator serves both papers' scene models:

* **Paper 001 §4** (``../shared/seeds/001_*.txt``): i.i.d. Gaussian noise of mean ``mu``
  and standard deviation ``sigma`` (Table 1: ``mu = 30``, variance 3.0, so
  ``sigma = sqrt(3)``); with ``SNR = (TargetAmp - NoiseAmp) / sigma`` a target pixel is
  ``Noise + SNR * sigma`` and a non-target pixel is ``Noise``. We read "Noise" as the
  *noisy* background sample of that pixel: the target adds ``SNR * sigma`` on top of a
  draw of ``N(mu, sigma**2)``, so its expected value is ``mu + SNR * sigma`` (the
  target level replaces the noise-free background level ``mu``). Amplitude:
  :func:`amplitude_from_snr`.
* **Paper 000 §3 eq (8)** (``../shared/seeds/000_*.txt``): zero-mean noise of standard
  deviation ``sigma`` and ``SNR_dB = 10 lg(A**2 / mean(n**2))``. We use the expected
  noise power ``sigma**2`` for ``mean(n**2)``, so ``A = sigma * 10**(SNR_dB / 20)``
  (:func:`amplitude_from_snr_db`; 4.08 dB gives 000 §5.1's ``A = 1.6``).

Both become a :class:`Target` with an ``amplitude`` added to the noisy background.

Coordinates are ``(row, col) = (y, x)``, row 0 first, as in ``docs/arithmetic.md`` §1.
Velocities are ``(row velocity, col velocity)`` in pixels/frame. The papers' own
conventions are mapped by :func:`paper001_motion` and :func:`paper000_motion`.

Noise and targets are separable: the noise of trial ``i`` depends only on ``(seed, i)``
(:func:`make_noise`), never on the targets, so a scene minus the noise-only frames of
the same seed is the target signal, and ``noise=False`` gives the exact noise-free
scene (background ``mu`` plus amplitudes).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import Any, Iterable, Sequence

import numpy as np

from dptbd.errors import DptbdError, check_bool, check_int, check_real, check_shape

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

#: Paper 001's sensor: a 12-bit ADC with 16 LSB per grey level, so the paper's grey levels
#: (mean 30, sigma 1.73) become mean 480, sigma 27.7 LSB. An 8-bit ADC at 1 LSB per grey
#: level (sigma < 2 LSB) makes so many pixels tie at the threshold that the
#: constant-count rule (docs/arithmetic.md §6) keeps far fewer than 0.2 %.
INPUT_BITS = 12
ADC_GAIN = 16.0

_MAX_SIZE = 65535
_MAX_FRAMES = 10**7
_MAX_TRIALS = 10**7
_FLOAT_DTYPES = (np.dtype(np.float32), np.dtype(np.float64))
_QUANTISE_CHUNK = 1 << 22  # elements per chunk: bounds the float temporaries of quantise


class SceneError(DptbdError):
    """A scene parameter is invalid; the message names it and its allowed range."""


# ---- validation helpers -------------------------------------------------------------------

_check_int = functools.partial(check_int, error=SceneError)


def _check_real(name: str, value: Any, *, positive: bool = False) -> float:
    """A finite real number (``> 0`` when ``positive``), else :class:`SceneError`."""
    return check_real(name, value, 0.0 if positive else -math.inf, lo_open=positive,
                      error=SceneError)


def _check_pair(name: str, value: Any) -> tuple[float, float]:
    """A pair of finite reals ``(row, col)``, else :class:`SceneError`."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise SceneError(f"{name} must be a (row, col) pair of finite reals, got {value!r}") from exc
    if arr.shape != (2,):
        raise SceneError(f"{name} must be a (row, col) pair of shape (2,), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise SceneError(f"{name} must be finite (no NaN or inf), got {value!r}")
    return float(arr[0]), float(arr[1])


def _check_shape(shape: Any) -> tuple[int, int]:
    """Frame size ``(height, width)``, each in ``[1, 65535]``."""
    return check_shape("shape", shape, _MAX_SIZE, axes=("height", "width"), error=SceneError)


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


# ---- SNR and amplitude -------------------------------------------------------------------

def amplitude_from_snr(snr: float, sigma: float) -> float:
    """Paper 001 §4: target amplitude above the background, ``SNR * sigma``.

    ``SNR = (TargetAmp - NoiseAmp) / sigma`` with TargetAmp and NoiseAmp the target and
    noise means.

    Parameters
    ----------
    snr : float
        Linear SNR, finite.
    sigma : float
        Noise standard deviation, > 0.

    Returns
    -------
    float
        The amplitude added to the background.
    """
    return _check_real("snr", snr) * _check_real("sigma", sigma, positive=True)


def snr_from_amplitude(amplitude: float, sigma: float) -> float:
    """Inverse of :func:`amplitude_from_snr`: ``amplitude / sigma``."""
    return _check_real("amplitude", amplitude) / _check_real("sigma", sigma, positive=True)


def amplitude_from_snr_db(snr_db: float, sigma: float) -> float:
    """Paper 000 eq (8): ``SNR_dB = 10 lg(A**2 / mean(n**2))``, so ``A = sigma * 10**(SNR_dB / 20)``.

    ``mean(n**2)`` is taken as the expected power ``sigma**2`` of zero-mean noise, not
    the power of one realised frame.

    Parameters
    ----------
    snr_db : float
        SNR in dB, finite.
    sigma : float
        Noise standard deviation, > 0.

    Returns
    -------
    float
        The target amplitude A (> 0).
    """
    snr_db = _check_real("snr_db", snr_db)
    return _check_real("sigma", sigma, positive=True) * 10.0 ** (snr_db / 20.0)


def snr_db_from_amplitude(amplitude: float, sigma: float) -> float:
    """Inverse of :func:`amplitude_from_snr_db`: ``20 lg(|A| / sigma)``; amplitude must be != 0."""
    amplitude = _check_real("amplitude", amplitude)
    sigma = _check_real("sigma", sigma, positive=True)
    if amplitude == 0.0:
        raise SceneError("amplitude must be non-zero to have an SNR in dB, got 0.0")
    return 20.0 * math.log10(abs(amplitude) / sigma)


# ---- the papers' coordinate conventions ----------------------------------------------------

def paper001_motion(start: Sequence[float], velocity: Sequence[float]
                    ) -> tuple[tuple[float, float], tuple[float, float]]:
    """Map paper 001's start ``(a, b)`` and ``(Vx, Vy)`` to ``(row, col)`` start and velocity.

    Paper 001 gives starts such as ``(30, 100)`` and velocities "Vx, Vy" without saying
    which is the row. We read the start as ``(row=a, col=b)`` and ``(Vx, Vy)`` as
    ``(row velocity, col velocity)``: the first component moves along rows. This is the
    reading that keeps every target of 001's experiments inside the 128 x 128 image
    for all 100 frames (e.g. ``(30, 100)`` at ``(0.8, -0.4)`` ends at ``(109.2, 60.4)``);
    pairing the start with ``(Vy, Vx)`` instead would take that target out of the top
    edge near frame 76. The mapping is therefore the identity.

    Returns
    -------
    tuple
        ``((row, col), (row velocity, col velocity))`` as floats.
    """
    return _check_pair("start", start), _check_pair("velocity", velocity)


def paper000_motion(start: Sequence[float], vx: float, vy: float
                    ) -> tuple[tuple[float, float], tuple[float, float]]:
    """Map paper 000's start ``(a, b)`` and ``v_x, v_y`` to ``(row, col)`` start and velocity.

    Paper 000 §5 starts a target at ``(12, 52)`` with ``v_x = -2``, ``v_y = 2`` cells/frame
    in a 64 x 64 image for 20 frames. We read the start as the matrix index
    ``(i, j) = (row, col)`` (000 eq (6) indexes cells ``z_ij``) and ``v_x`` as the column
    (x) velocity, ``v_y`` as the row (y) velocity: row velocity ``v_y``, col velocity
    ``v_x``. Only this pairing keeps that target in the image: ``(12, 52)`` moves to
    ``(50, 14)`` by frame 19, whereas applying ``(v_x, v_y)`` as ``(row, col)`` velocity
    leaves through the top edge at frame 7. Note this differs from
    :func:`paper001_motion`, where the first velocity component moves along rows.

    Returns
    -------
    tuple
        ``((row, col), (v_y, v_x))`` as floats.
    """
    vx = _check_real("vx", vx)
    vy = _check_real("vy", vy)
    return _check_pair("start", start), (vy, vx)


# ---- targets -----------------------------------------------------------------------------

@dataclasses.dataclass(frozen=True)
class Turn:
    """A manoeuvre: at ``frame`` the velocity changes, from then on the target moves anew.

    Exactly one of ``degrees`` and ``velocity`` is given.

    Parameters
    ----------
    frame : int
        Frame of the turn point, > the target's ``birth``. Positions up to and including
        ``frame`` use the old velocity; position at ``t > frame`` is
        ``p(frame) + v_new * (t - frame)``.
    degrees : float or None
        Rotate the current velocity by this angle. Positive turns counter-clockwise as the
        image is displayed (row 0 at the top): a target moving right (+col) turned by +90
        moves up (-row). The speed is kept.
    velocity : pair of float or None
        The new ``(row, col)`` velocity in pixels/frame.
    """

    frame: int
    degrees: float | None = None
    velocity: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "frame", _check_int("turn frame", self.frame, 1))
        if (self.degrees is None) == (self.velocity is None):
            raise SceneError("a Turn needs exactly one of degrees or velocity, "
                             f"got degrees={self.degrees!r}, velocity={self.velocity!r}")
        if self.degrees is not None:
            object.__setattr__(self, "degrees", _check_real("turn degrees", self.degrees))
        else:
            object.__setattr__(self, "velocity", _check_pair("turn velocity", self.velocity))

    def apply(self, velocity: tuple[float, float]) -> tuple[float, float]:
        """The velocity after this turn, given the velocity before it."""
        if self.velocity is not None:
            return self.velocity
        return _rotate(velocity, self.degrees)


def _rotate(velocity: tuple[float, float], degrees: float) -> tuple[float, float]:
    """Rotate a ``(row, col)`` vector counter-clockwise as displayed (row axis points down)."""
    vr, vc = velocity
    theta = math.radians(degrees)
    cos, sin = math.cos(theta), math.sin(theta)
    # In (x = col, y_up = -row) the rotation is the usual one; expressed back in (row, col):
    return (vr * cos - vc * sin, vc * cos + vr * sin)


@dataclasses.dataclass(frozen=True)
class Target:
    """A point target moving at constant velocity, with optional turns.

    Parameters
    ----------
    start : pair of float
        ``(row, col)`` position at frame ``birth``, in pixels; sub-pixel allowed.
    velocity : pair of float
        ``(row, col)`` velocity in pixels/frame; sub-pixel speeds allowed.
    amplitude : float
        Added to the noisy background at the target's pixel (001: ``SNR * sigma``,
        :func:`amplitude_from_snr`; 000: :func:`amplitude_from_snr_db`). Finite; a
        negative value makes a dark target.
    birth : int
        First frame in which the target is present, >= 0.
    death : int or None
        First frame in which it is gone, > ``birth``; ``None`` means never. The target is
        present for ``birth <= t < death``.
    turns : Turn or sequence of Turn
        Manoeuvres, in strictly increasing frame order, each after ``birth``.
    """

    start: tuple[float, float]
    velocity: tuple[float, float]
    amplitude: float
    birth: int = 0
    death: int | None = None
    turns: tuple[Turn, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", _check_pair("start", self.start))
        object.__setattr__(self, "velocity", _check_pair("velocity", self.velocity))
        object.__setattr__(self, "amplitude", _check_real("amplitude", self.amplitude))
        birth = _check_int("birth", self.birth, 0)
        object.__setattr__(self, "birth", birth)
        if self.death is not None:
            object.__setattr__(self, "death", _check_int("death", self.death, birth + 1))
        object.__setattr__(self, "turns", _check_turns(self.turns, birth))

    def velocities(self) -> list[tuple[int, tuple[float, float]]]:
        """``(from_frame, velocity)`` for each piece of the trajectory, starting at ``birth``."""
        pieces = [(self.birth, self.velocity)]
        for turn in self.turns:
            pieces.append((turn.frame, turn.apply(pieces[-1][1])))
        return pieces

    def positions(self, n_frames: int) -> np.ndarray:
        """True float ``(row, col)`` position at frames ``0 .. n_frames - 1``.

        The trajectory is defined at every frame, including before ``birth`` (extrapolated
        back with the initial velocity) and after ``death``; presence is a separate flag
        (:func:`target_truth`).

        Returns
        -------
        numpy.ndarray
            ``float64`` array of shape ``(n_frames, 2)``.
        """
        n_frames = _check_int("frames", n_frames, 1, _MAX_FRAMES)
        t = np.arange(n_frames, dtype=np.float64)
        pos = np.tile(np.asarray(self.start, dtype=np.float64), (n_frames, 1))
        pieces = self.velocities()
        for k, (t0, vel) in enumerate(pieces):
            t1 = pieces[k + 1][0] if k + 1 < len(pieces) else np.inf
            lo = -np.inf if k == 0 else 0.0  # only the first piece extrapolates backwards
            dt = np.clip(t - t0, lo, t1 - t0)
            pos += dt[:, None] * np.asarray(vel, dtype=np.float64)
        return pos


def _check_turns(turns: Any, birth: int) -> tuple[Turn, ...]:
    if isinstance(turns, Turn):
        turns = (turns,)
    try:
        turns = tuple(turns)
    except TypeError as exc:
        raise SceneError(f"turns must be a Turn or a sequence of Turn, got {turns!r}") from exc
    last = birth
    for turn in turns:
        if not isinstance(turn, Turn):
            raise SceneError(f"turns must contain Turn objects, got {turn!r}")
        if turn.frame <= last:
            raise SceneError(f"turn frame must be an integer in [{last + 1}, inf) (after birth={birth} "
                             f"and after the previous turn), got {turn.frame}")
        last = turn.frame
    return turns


@dataclasses.dataclass(frozen=True)
class TargetTruth:
    """Ground truth of one target over a sequence of frames.

    Attributes
    ----------
    position : numpy.ndarray
        ``float64 (T, 2)``: true ``(row, col)`` at every frame (see :meth:`Target.positions`).
    pixel : numpy.ndarray
        ``int64 (T, 2)``: the pixel hit, ``np.rint(position)`` (nearest pixel; exact halves
        go to the even pixel).
    alive : numpy.ndarray
        ``bool (T,)``: ``birth <= t < death``.
    visible : numpy.ndarray
        ``bool (T,)``: alive and ``pixel`` inside the image; only visible frames are drawn.
    amplitude : float
        The target's amplitude.
    """

    position: np.ndarray
    pixel: np.ndarray
    alive: np.ndarray
    visible: np.ndarray
    amplitude: float


def target_truth(target: Target, shape: tuple[int, int], n_frames: int) -> TargetTruth:
    """Ground truth of ``target`` in frames of size ``shape = (height, width)``.

    Parameters
    ----------
    target : Target
        The target.
    shape : pair of int
        ``(height, width)`` of a frame.
    n_frames : int
        Number of frames T, >= 1.

    Returns
    -------
    TargetTruth
        Position, rounded pixel, presence and visibility per frame.
    """
    if not isinstance(target, Target):
        raise SceneError(f"targets must contain Target objects, got {target!r}")
    height, width = _check_shape(shape)
    position = target.positions(n_frames)
    pixel = np.rint(position).astype(np.int64)
    t = np.arange(n_frames)
    death = n_frames if target.death is None else target.death
    alive = (t >= target.birth) & (t < death)
    inside = ((pixel[:, 0] >= 0) & (pixel[:, 0] < height)
              & (pixel[:, 1] >= 0) & (pixel[:, 1] < width))
    for arr in (position, pixel, alive):
        arr.flags.writeable = False
    visible = alive & inside
    visible.flags.writeable = False
    return TargetTruth(position, pixel, alive, visible, target.amplitude)


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


# ---- ADC --------------------------------------------------------------------------------

def quantise(frames: Any, input_bits: int, *, gain: float = 1.0, offset: float = 0.0) -> np.ndarray:
    """Float frames to unsigned ``input_bits``-bit codes, like an ADC.

    ``code = clip(rint(gain * x + offset), 0, 2**input_bits - 1)``: rounded to the nearest
    integer (``np.rint``: exact halves to even), then clipped (saturated) to the code
    range. The result satisfies ``docs/arithmetic.md`` §1 and can be fed to the models.

    Parameters
    ----------
    frames : array_like
        Real frames of any shape, finite (NaN and inf are refused, never clipped).
    input_bits : int
        B_in in [1, 16].
    gain, offset : float
        Finite ADC gain and offset applied before rounding; e.g. paper 000's zero-mean
        scenes need an offset to keep negative noise off the bottom of the range.

    Returns
    -------
    numpy.ndarray
        ``uint16`` codes of the same shape.
    """
    bits = _check_int("input_bits", input_bits, 1, 16)
    gain = _check_real("gain", gain)
    offset = _check_real("offset", offset)
    arr = np.asarray(frames)
    if arr.dtype.kind not in "biuf":
        raise SceneError(f"frames must be a real numeric array, got dtype {arr.dtype}")
    top = float((1 << bits) - 1)
    out = np.empty(arr.shape, dtype=np.uint16)
    src, dst = arr.reshape(-1), out.reshape(-1)
    for lo in range(0, src.size, _QUANTISE_CHUNK):
        x = src[lo:lo + _QUANTISE_CHUNK].astype(np.float64)
        if not np.all(np.isfinite(x)):
            raise SceneError("frames must be finite: found NaN or inf")
        x *= gain
        x += offset
        np.rint(x, out=x)
        np.clip(x, 0.0, top, out=x)
        dst[lo:lo + _QUANTISE_CHUNK] = x
    return out


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
