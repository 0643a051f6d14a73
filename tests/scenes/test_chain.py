"""``dptbd.scenes.chain``: the manoeuvring and the crossing scenes of the chain comparison."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.scenes import SceneError
from dptbd.scenes import chain
from dptbd.scenes.reach import check_reach
from dptbd.scenes.synthetic import TABLE1_MU, TABLE1_SIGMA
from helpers.refusals import whole


def test_the_manoeuvring_target_is_where_its_definition_puts_it():
    scene = chain.manoeuvring_scene(seed=0)
    (truth,) = scene.truth
    pos = truth.position
    # right at 0.9 to frame 30, down at 0.9 to 55, (0.45, -0.45) to 75, (-0.3, -0.9) to 99
    np.testing.assert_allclose(pos[[0, 30, 55, 75, 99]],
                               [[20.0, 20.0], [20.0, 47.0], [42.5, 47.0], [51.5, 38.0],
                                [44.3, 16.4]], atol=1e-9)
    np.testing.assert_allclose(np.diff(pos[:31], axis=0), [[0.0, 0.9]] * 30, atol=1e-9)
    np.testing.assert_allclose(np.diff(pos[30:56], axis=0), [[0.9, 0.0]] * 25, atol=1e-9)
    assert truth.visible.all()
    assert scene.frames.shape == (100, 128, 128)
    assert scene.params["scenario"] == "manoeuvring"
    # it turns and changes speed: four velocity pieces, three speeds
    speeds = [np.hypot(*v) for _, v in scene.targets[0].velocities()]
    assert len(speeds) == 4 and len({round(s, 6) for s in speeds}) == 3


def test_the_crossing_targets_share_a_pixel_in_frame_50_only():
    scene = chain.crossing_scene(seed=0)
    a, b = scene.truth
    np.testing.assert_allclose(a.position[[0, 50, 99]], [[24, 24], [64, 64], [103.2, 103.2]])
    np.testing.assert_allclose(b.position[[0, 50, 99]], [[104, 24], [64, 64], [24.8, 103.2]])
    assert np.flatnonzero((a.pixel == b.pixel).all(axis=1)).tolist() == [50]
    assert a.visible.all() and b.visible.all()
    # the amplitudes add on the shared pixel
    clean = chain.crossing_scene(seed=0, noise=False)
    assert clean.frames[50, 64, 64] == pytest.approx(TABLE1_MU + 2 * 2.0 * TABLE1_SIGMA)


@pytest.mark.parametrize("targets", [chain.manoeuvring_targets(), chain.crossing_targets()])
def test_every_step_is_within_the_move_set_of_radius_1(targets):
    check_reach(targets, chain.SIZE, chain.FRAMES, 1)
    for target in targets:
        pixel = np.rint(target.positions(chain.FRAMES))
        assert np.abs(np.diff(pixel, axis=0)).max() == 1


@pytest.mark.parametrize("make", [chain.manoeuvring_scene, chain.crossing_scene])
def test_same_seed_same_scene_other_seed_other_noise(make):
    a, b, c = make(seed=7), make(seed=7), make(seed=8)
    np.testing.assert_array_equal(a.frames, b.frames)
    assert not np.array_equal(a.frames, c.frames)
    assert make(snr=3.0, seed=7).truth[0].amplitude == pytest.approx(3.0 * TABLE1_SIGMA)


@pytest.mark.parametrize("make", [chain.manoeuvring_scene, chain.crossing_scene])
@pytest.mark.parametrize("kwargs, message", [
    ({"snr": 0.0}, "snr must be a finite real number in (0, inf), got 0.0"),
    ({"snr": float("nan")}, "snr must be a finite real number in (0, inf), got nan"),
    ({"radius": 0}, "radius must be an integer in [1, inf), got 0"),
])
def test_refusals_name_the_parameter_and_the_allowed_range(make, kwargs, message):
    with pytest.raises(SceneError, match=whole(message)):
        make(**kwargs)


def test_a_motion_beyond_reach_would_be_refused_when_the_scene_is_built(monkeypatch):
    monkeypatch.setattr(chain, "MANOEUVRING", (((0.4, 1.0), (1.5, 0.0), ()),))
    with pytest.raises(SceneError, match=whole(
            "target 1 moves (2, 0) pixels from frame 0 to frame 1, beyond the move set's reach: "
            "its row and column steps must be integers in [-1, 1] (radius=1)")):
        chain.manoeuvring_scene()
