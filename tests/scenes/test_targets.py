"""Point targets of ``dptbd.scenes.targets``: motion conventions, turns, ground truth."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd.scenes import SceneError
from dptbd.scenes.targets import Target, Turn, paper000_motion, paper001_motion, target_truth
from helpers.refusals import whole


def _one(start=(5.0, 5.0), velocity=(0.0, 0.0), amplitude=10.0, **kw):
    return Target(start, velocity, amplitude, **kw)


# ---- motion and turns -----------------------------------------------------------------

def test_subpixel_motion_rounds_to_nearest_pixel():
    target = _one(start=(30.0, 100.0), velocity=(0.8, -0.4))
    tr = target_truth(target, (128, 128), 100)
    t = np.arange(100)
    np.testing.assert_allclose(tr.position[:, 0], 30.0 + 0.8 * t, atol=1e-9)
    np.testing.assert_allclose(tr.position[:, 1], 100.0 - 0.4 * t, atol=1e-9)
    assert np.array_equal(tr.pixel, np.rint(tr.position).astype(np.int64))
    assert tr.pixel.dtype == np.int64
    # frame 1: (30.8, 99.6) -> (31, 100); frame 2: (31.6, 99.2) -> (32, 99)
    assert tr.pixel[1].tolist() == [31, 100]
    assert tr.pixel[2].tolist() == [32, 99]
    assert tr.visible.all()
    # the target stays on a pixel some frames (0.4 px/frame)
    assert np.any(np.diff(tr.pixel[:, 1]) == 0)


def test_turn_by_angle():
    target = _one(start=(10.0, 2.0), velocity=(0.0, 1.0), turns=Turn(frame=4, degrees=90.0))
    tr = target_truth(target, (20, 20), 8)
    # moves right until frame 4, then up (counter-clockwise as displayed)
    assert tr.pixel[:5].tolist() == [[10, 2], [10, 3], [10, 4], [10, 5], [10, 6]]
    assert tr.pixel[5:].tolist() == [[9, 6], [8, 6], [7, 6]]
    np.testing.assert_allclose(tr.position[7], [7.0, 6.0], atol=1e-12)


def test_turn_to_new_velocity_and_two_turns():
    turns = (Turn(frame=3, velocity=(1.0, 0.0)), Turn(frame=5, degrees=-90.0))
    target = _one(start=(0.0, 0.0), velocity=(0.0, 1.0), turns=turns)
    tr = target_truth(target, (20, 20), 8)
    # right to (0, 3), down to (2, 3), then turned clockwise
    assert tr.pixel[3].tolist() == [0, 3]
    assert tr.pixel[5].tolist() == [2, 3]
    # down = (+1, 0); turning it by -90 (clockwise as displayed) points left (0, -1)
    assert tr.pixel[7].tolist() == [2, 1]


def test_rotation_keeps_speed():
    target = _one(velocity=(0.8, -0.4), turns=Turn(frame=1, degrees=37.0))
    v_after = target.velocities()[1][1]
    assert math.hypot(*v_after) == pytest.approx(math.hypot(0.8, -0.4))


def test_paper_motion_helpers():
    assert paper001_motion((30, 100), (0.8, -0.4)) == ((30.0, 100.0), (0.8, -0.4))
    assert paper000_motion((12, 52), vx=-2, vy=2) == ((12.0, 52.0), (2.0, -2.0))


# ---- bad input ------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, message", [
    (dict(start=(np.nan, 1.0)), "start must be finite (no NaN or inf), got (nan, 1.0)"),
    (dict(start=(1.0, 2.0, 3.0)), "start must be a (row, col) pair of shape (2,), got shape (3,)"),
    (dict(velocity=(np.inf, 0.0)), "velocity must be finite (no NaN or inf), got (inf, 0.0)"),
    (dict(velocity="fast"), "velocity must be a (row, col) pair of finite reals, got 'fast'"),
    (dict(amplitude=np.nan), "amplitude must be a finite real number in (-inf, inf), got nan"),
    (dict(birth=-1), "birth must be an integer in [0, inf), got -1"),
    (dict(birth=3, death=3), "death must be an integer in [4, inf), got 3"),
    (dict(birth=3, death=1), "death must be an integer in [4, inf), got 1"),
    (dict(birth=2, turns=Turn(frame=2, degrees=10.0)),
     "turn frame must be an integer in [3, inf) (after birth=2 and after the previous turn), got 2"),
    (dict(turns=(Turn(frame=5, degrees=1.0), Turn(frame=4, degrees=1.0))),
     "turn frame must be an integer in [6, inf) (after birth=0 and after the previous turn), got 4"),
    (dict(turns=("left",)), "turns must contain Turn objects, got 'left'"),
])
def test_target_refuses_bad_parameters(kwargs, message):
    args = dict(start=(1.0, 1.0), velocity=(0.5, 0.5), amplitude=1.0)
    args.update(kwargs)
    with pytest.raises(SceneError, match=whole(message)):
        Target(**args)


def test_turn_refuses_bad_parameters():
    with pytest.raises(SceneError, match=whole(
            "a Turn needs exactly one of degrees or velocity, got degrees=None, velocity=None")):
        Turn(frame=3)
    with pytest.raises(SceneError, match=whole(
            "a Turn needs exactly one of degrees or velocity, got degrees=5.0, velocity=(1.0, 0.0)")):
        Turn(frame=3, degrees=5.0, velocity=(1.0, 0.0))
    with pytest.raises(SceneError, match=whole(
            "turn degrees must be a finite real number in (-inf, inf), got nan")):
        Turn(frame=3, degrees=np.nan)
    with pytest.raises(SceneError, match=whole("turn frame must be an integer in [1, inf), got 0")):
        Turn(frame=0, degrees=5.0)
