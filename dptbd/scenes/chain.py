"""The scenes of the end-to-end chain comparison, next to the main job's scene.

The main job's scene (``dptbd run``'s built-in scenario) is paper 001's second experiment,
:func:`dptbd.scenes.synthetic.paper001_two_targets`: two straight tracks. Two more scenes
with the same frame size, length, noise (mean 30, variance 3) and SNR convention (001's
linear SNR, default 2.0) test what straight tracks do not:

* :func:`manoeuvring_scene` — one target that turns and changes speed
  (:data:`MANOEUVRING`): right at 0.9 px/frame, a right turn (-90 degrees) at frame 30 (down
  at 0.9), a turn and slow-down at frame 55 (down-left at (0.45, -0.45)), a turn and speed-up
  at frame 75 (up-left at (-0.3, -0.9)). It passes (20, 20), (20, 47) at frame 30,
  (42.5, 47) at 55, (51.5, 38) at 75 and (44.3, 16.4) at 99.
* :func:`crossing_scene` — two targets whose tracks cross mid-sequence
  (:data:`CROSSING`): from (24, 24) at (0.8, 0.8) and from (104, 24) at (-0.8, 0.8), both at
  (64, 64) in frame 50 (the same pixel: their amplitudes add there), apart again after it.

Every frame-to-frame pixel step of every target stays within the DP's move set of radius 1
(001's 3 x 3 window): each scene is checked by :func:`dptbd.scenes.reach.check_reach` when
it is built (``radius``), so a scene that left the reach would be refused, not drawn.
Both scenes are seeded exactly like :func:`dptbd.scenes.synthetic.make_scene` (the noise
depends only on ``seed``).
"""

from __future__ import annotations

from typing import Any

from dptbd.scenes._checks import _check_int, _check_real
from dptbd.scenes.reach import check_reach
from dptbd.scenes.snr import amplitude_from_snr
from dptbd.scenes.synthetic import TABLE1_MU, TABLE1_SIGMA, Scene, make_scene
from dptbd.scenes.targets import Target, Turn

__all__ = ["SIZE", "FRAMES", "MANOEUVRING", "CROSSING", "manoeuvring_targets",
           "crossing_targets", "manoeuvring_scene", "crossing_scene"]

#: Frame size and length of both scenes: those of the main job's scene.
SIZE = (128, 128)
FRAMES = 100

#: The manoeuvring target: (start, velocity, turns), (row, col) in pixels and pixels/frame.
MANOEUVRING = (
    ((20.0, 20.0), (0.0, 0.9), (Turn(30, degrees=-90.0), Turn(55, velocity=(0.45, -0.45)),
                                Turn(75, velocity=(-0.3, -0.9)))),
)
#: The two crossing targets: (start, velocity, turns); both at (64, 64) in frame 50.
CROSSING = (
    ((24.0, 24.0), (0.8, 0.8), ()),
    ((104.0, 24.0), (-0.8, 0.8), ()),
)


def _targets(motions, snr: Any) -> list[Target]:
    amplitude = amplitude_from_snr(_check_real("snr", snr, positive=True), TABLE1_SIGMA)
    return [Target(start, velocity, amplitude, turns=turns) for start, velocity, turns in motions]


def manoeuvring_targets(snr: float = 2.0) -> list[Target]:
    """The target of :func:`manoeuvring_scene` (amplitude ``snr * sigma``, ``snr`` > 0)."""
    return _targets(MANOEUVRING, snr)


def crossing_targets(snr: float = 2.0) -> list[Target]:
    """The targets of :func:`crossing_scene` (amplitude ``snr * sigma``, ``snr`` > 0)."""
    return _targets(CROSSING, snr)


def _scene(targets: list[Target], name: str, snr: float, seed: Any, radius: Any,
           kwargs: dict) -> Scene:
    check_reach(targets, SIZE, FRAMES, _check_int("radius", radius, 1))
    scene = make_scene(SIZE, FRAMES, targets, mu=TABLE1_MU, sigma=TABLE1_SIGMA, seed=seed,
                       **kwargs)
    scene.params.update(scenario=name, snr=float(snr))
    return scene


def manoeuvring_scene(snr: float = 2.0, *, seed: Any = 0, radius: int = 1,
                       **kwargs: Any) -> Scene:
    """128 x 128, 100 frames, noise mean 30 / variance 3, one manoeuvring target at ``snr``.

    The target is :data:`MANOEUVRING`; the scene is refused (:class:`~dptbd.scenes.SceneError`)
    if a step leaves the move set of ``radius`` (it does not for radius >= 1). Further
    keywords (``trials``, ``first_trial``, ``dtype``, ``noise``) go to
    :func:`~dptbd.scenes.synthetic.make_scene`.
    """
    return _scene(manoeuvring_targets(snr), "manoeuvring", snr, seed, radius, kwargs)


def crossing_scene(snr: float = 2.0, *, seed: Any = 0, radius: int = 1,
                           **kwargs: Any) -> Scene:
    """128 x 128, 100 frames, noise mean 30 / variance 3, two crossing targets at ``snr``.

    The targets are :data:`CROSSING` (the same pixel in frame 50); checked against the
    move set of ``radius`` like :func:`manoeuvring_scene`, same keywords.
    """
    return _scene(crossing_targets(snr), "crossing", snr, seed, radius, kwargs)

