"""Whether a scene's targets stay within the DP's move set (a refusal, not a correction).

The DP follows a target only when its pixel moves at most r rows and r columns from one
frame to the next: the (2r + 1)**2 moves of the search window, radius r
(``docs/arithmetic.md`` §2). A target that jumps farther between two frames in which it is
visible — faster than r pixels per frame on an axis, or after a turn or speed change that
makes it so, or by the rounding of a sub-pixel speed above r — cannot be accumulated along
its path; :func:`check_reach` refuses such a scene, naming the target, the frames and the
allowed steps. Frames in which a target is not visible (not yet born, dead, outside the
image) are not moves.
"""

from __future__ import annotations

from typing import Iterable

import numpy as np

from dptbd.scenes._checks import SceneError, _check_int, _check_shape
from dptbd.scenes.targets import Target, target_truth

__all__ = ["check_reach"]


def check_reach(targets: Iterable[Target], shape: tuple[int, int], frames: int, radius: int) -> None:
    """Refuse (:class:`~dptbd.scenes.SceneError`) a target whose pixel moves more than
    ``radius`` rows or columns between two consecutive frames in which it is visible.

    Targets are numbered from 1 in the message, as scenario files list them.
    """
    radius = _check_int("radius", radius, 1)
    shape = _check_shape(shape)
    frames = _check_int("frames", frames, 1)
    for i, target in enumerate(targets, 1):
        truth = target_truth(target, shape, frames)
        steps = np.diff(truth.pixel, axis=0)
        moving = truth.visible[1:] & truth.visible[:-1]
        bad = np.flatnonzero(moving & (np.abs(steps).max(axis=1) > radius))
        if bad.size:
            t = int(bad[0])
            dr, dc = (int(v) for v in steps[t])
            raise SceneError(
                f"target {i} moves ({dr}, {dc}) pixels from frame {t} to frame {t + 1}, beyond the "
                f"move set's reach: its row and column steps must be integers in "
                f"[-{radius}, {radius}] (radius={radius})")
