"""Point targets: the papers' motion conventions, manoeuvres and per-frame ground truth.

Coordinates are ``(row, col) = (y, x)``, row 0 first, as in ``docs/arithmetic.md`` §1.
Velocities are ``(row velocity, col velocity)`` in pixels/frame. The papers' own
conventions are mapped by :func:`paper001_motion` and :func:`paper000_motion`.

A :class:`Target` moves at constant velocity between its :class:`Turn` points;
:func:`target_truth` gives its true position, the pixel it hits, and when it is alive and
visible in frames of a given size (:class:`TargetTruth`).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Sequence

import numpy as np

from dptbd.scenes._checks import (_MAX_FRAMES, SceneError, _check_int, _check_pair, _check_real,
                                  _check_shape)

__all__ = [
    "Turn",
    "Target",
    "TargetTruth",
    "paper001_motion",
    "paper000_motion",
    "target_truth",
]

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
        :func:`dptbd.scenes.snr.amplitude_from_snr`; 000:
        :func:`dptbd.scenes.snr.amplitude_from_snr_db`). Finite; a
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
