"""``dptbd.scenes.reach``: targets that leave the DP's move set's reach are refused."""

from __future__ import annotations

import pytest

from dptbd.scenes import SceneError
from dptbd.scenes.reach import check_reach
from dptbd.scenes.targets import Target, Turn
from helpers.refusals import whole


def test_moves_within_the_radius_pass():
    check_reach([Target((5.0, 5.0), (1.0, -1.0), 1.0)], (16, 16), 8, 1)
    check_reach([Target((5.0, 5.0), (0.7, 0.3), 1.0, turns=[Turn(3, degrees=90.0)])], (16, 16), 8, 1)
    check_reach([Target((2.0, 2.0), (2.0, 2.0), 1.0)], (16, 16), 6, 2)
    # frames in which the target is not visible are not moves: born at 4, gone at 6
    check_reach([Target((0.0, 0.0), (3.0, 0.0), 1.0, birth=4, death=5)], (64, 64), 8, 1)
    check_reach([], (4, 4), 2, 1)


@pytest.mark.parametrize("targets, radius, message", [
    ([Target((1.0, 1.0), (0.5, 0.5), 1.0), Target((0.4, 1.0), (1.5, 0.0), 1.0)], 1,
     # 0.4 -> 1.9 -> 3.4: the rounded pixel jumps 0 -> 2 although the speed is 1.5
     "target 2 moves (2, 0) pixels from frame 0 to frame 1, beyond the move set's reach: its row "
     "and column steps must be integers in [-1, 1] (radius=1)"),
    # a speed change after frame 3: column 5 -> 2.5, rounded to 2 (half to even): 3 pixels
    ([Target((5.0, 5.0), (1.0, 0.0), 1.0, turns=[Turn(3, velocity=(0.0, -2.5))])], 2,
     "target 1 moves (0, -3) pixels from frame 3 to frame 4, beyond the move set's reach: its row "
     "and column steps must be integers in [-2, 2] (radius=2)"),
])
def test_a_target_beyond_reach_is_refused_naming_it(targets, radius, message):
    with pytest.raises(SceneError, match=whole(message)):
        check_reach(targets, (32, 32), 10, radius)


@pytest.mark.parametrize("args, message", [
    (((8, 8), 4, 0), "radius must be an integer in [1, inf), got 0"),
    (((0, 8), 4, 1), "shape[0] (height) must be an integer in [1, 65535], got 0"),
    (((8, 8), 0, 1), "frames must be an integer in [1, inf), got 0"),
])
def test_bad_parameters(args, message):
    with pytest.raises(SceneError, match=whole(message)):
        check_reach([], *args)
