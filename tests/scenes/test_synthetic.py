"""Scene generators of ``dptbd.scenes.synthetic``: noise, scenes with targets, the papers'
001 §4 and 000 §3/§5 scenarios; the names it re-exports from its sibling modules."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dptbd import scenes as scene_package
from dptbd.scenes import adc, snr, synthetic as scenes, targets as target_module
from dptbd.scenes.synthetic import (
    Scene,
    SceneError,
    Target,
    amplitude_from_snr,
    make_noise,
    make_scene,
)
from helpers.refusals import whole


def _one(start=(5.0, 5.0), velocity=(0.0, 0.0), amplitude=10.0, **kw):
    return Target(start, velocity, amplitude, **kw)


# ---- reproducibility ----------------------------------------------------------------------

def test_same_seed_identical_scene():
    a = make_scene((16, 20), 5, [_one()], mu=3.0, sigma=2.0, seed=7)
    b = make_scene((16, 20), 5, [_one()], mu=3.0, sigma=2.0, seed=7)
    assert a.frames.dtype == np.float64
    assert np.array_equal(a.frames, b.frames)
    assert a.params["seed"] == 7


def test_different_seeds_differ():
    a = make_noise((16, 16), 3, seed=1)
    b = make_noise((16, 16), 3, seed=2)
    assert not np.any(a == b)


def test_seed_none_records_entropy_that_reproduces():
    a = make_scene((8, 8), 2, seed=None)
    b = make_scene((8, 8), 2, seed=a.params["seed"])
    assert np.array_equal(a.frames, b.frames)


def test_noise_statistics():
    x = make_noise((256, 256), 4, mu=30.0, sigma=math.sqrt(3.0), seed=3)
    # 262144 samples: standard error of the mean 0.0034, of the std ~0.0024
    assert abs(x.mean() - 30.0) < 0.02
    assert abs(x.std() - math.sqrt(3.0)) < 0.02
    # independent frames and pixels
    assert abs(np.corrcoef(x[0].ravel(), x[1].ravel())[0, 1]) < 0.02
    assert abs(np.corrcoef(x[0, :, :-1].ravel(), x[0, :, 1:].ravel())[0, 1]) < 0.02


def test_float32_option():
    a = make_noise((32, 32), 2, mu=30.0, sigma=2.0, seed=4, dtype=np.float32)
    assert a.dtype == np.float32
    assert abs(a.mean() - 30.0) < 0.2


# ---- targets: separability, amplitude, motion ------------------------------------------

def test_noise_free_target_pixel_is_background_plus_snr_sigma():
    sigma = math.sqrt(3.0)
    amp = amplitude_from_snr(2.3, sigma)
    assert amp == 2.3 * sigma
    sc = make_scene((12, 12), 4, [_one(start=(3, 4), velocity=(1, 2), amplitude=amp)],
                    mu=30.0, sigma=sigma, noise=False)
    for t in range(4):
        r, c = 3 + t, 4 + 2 * t
        assert sc.frames[t, r, c] == 30.0 + 2.3 * sigma
        frame = sc.frames[t].copy()
        frame[r, c] = 30.0
        assert np.all(frame == 30.0)


def test_scene_minus_noise_is_target_signal():
    target = _one(start=(2, 2), velocity=(1, 1), amplitude=4.5)
    sc = make_scene((10, 10), 6, [target], mu=30.0, sigma=1.5, seed=11, trials=3)
    noise = make_noise((10, 10), 6, mu=30.0, sigma=1.5, seed=11, trials=3)
    diff = sc.frames - noise
    expected = np.where(sc.target_mask(), 4.5, 0.0)
    np.testing.assert_allclose(diff, np.broadcast_to(expected, diff.shape), atol=1e-12)


def test_birth_and_death():
    target = _one(start=(4.0, 1.0), velocity=(0.0, 1.0), birth=2, death=5)
    sc = make_scene((10, 10), 8, [target], mu=0.0, noise=False)
    tr = sc.truth[0]
    assert tr.alive.tolist() == [False, False, True, True, True, False, False, False]
    assert np.array_equal(tr.visible, tr.alive)
    # start is the position at the birth frame
    assert tr.position[2].tolist() == [4.0, 1.0]
    assert tr.position[0].tolist() == [4.0, -1.0]  # extrapolated, not drawn
    drawn = [int(np.count_nonzero(sc.frames[t])) for t in range(8)]
    assert drawn == [0, 0, 1, 1, 1, 0, 0, 0]
    assert sc.frames[4, 4, 3] == 10.0


def test_target_leaving_image_is_not_drawn():
    target = _one(start=(1.0, 1.0), velocity=(-1.0, 0.0))
    sc = make_scene((5, 5), 4, [target], noise=False)
    tr = sc.truth[0]
    assert tr.alive.all()
    assert tr.visible.tolist() == [True, True, False, False]
    assert tr.pixel[3].tolist() == [-2, 1]
    assert np.count_nonzero(sc.frames[2:]) == 0


def test_two_targets_on_one_pixel_add():
    targets = [_one(amplitude=2.0), _one(amplitude=3.0)]
    sc = make_scene((10, 10), 1, targets, mu=1.0, noise=False)
    assert sc.frames[0, 5, 5] == 6.0


# ---- batches --------------------------------------------------------------------------

def test_batch_shape_and_independence():
    target = _one(start=(3, 3), velocity=(1, 0), amplitude=5.0)
    sc = make_scene((8, 9), 4, [target], mu=30.0, sigma=1.0, seed=5, trials=3)
    assert sc.frames.shape == (3, 4, 8, 9)
    assert sc.trials == 3 and sc.n_frames == 4 and sc.shape == (8, 9)
    assert not np.any(sc.frames[0] == sc.frames[1])
    single = make_scene((8, 9), 4, [target], mu=30.0, sigma=1.0, seed=5)
    assert single.frames.shape == (4, 8, 9)
    assert np.array_equal(single.frames, sc.frames[0])


def test_batch_chunks_match_one_batch():
    whole = make_noise((6, 6), 3, seed=9, trials=5)
    parts = [make_noise((6, 6), 3, seed=9, trials=2, first_trial=0),
             make_noise((6, 6), 3, seed=9, trials=3, first_trial=2)]
    assert np.array_equal(whole, np.concatenate(parts))


# ---- quantisation --------------------------------------------------------------------------

def test_quantise_gain_offset_and_scene_method():
    sc = scenes.paper000_scenario(noise=False)
    q = sc.quantised(8, gain=10.0, offset=100.0)
    assert q.shape == (20, 64, 64) and q.dtype == np.uint16
    r, c = sc.truth[0].pixel[0]
    assert q[0, r, c] == 116  # rint(10 * 1.5996 + 100)
    assert q[0, 0, 0] == 100


def test_quantise_table1_in_range():
    sc = scenes.table1_scenario(2.3, seed=1)
    q = sc.quantised(8)
    assert q.min() >= 0 and q.max() <= 255
    assert abs(q.astype(float).mean() - 30.0) < 0.1


# ---- built-in scenarios --------------------------------------------------------------------

def test_table1_scenario_default_start_keeps_target_inside():
    sc = scenes.table1_scenario(2.0, (1, 1), noise=False)
    tr = sc.truth[0]
    assert sc.frames.shape == (100, 128, 128)
    assert tr.position[0].tolist() == [14.0, 14.0]
    assert tr.position[99].tolist() == [113.0, 113.0]
    assert tr.visible.all()
    assert sc.params["mu"] == 30.0 and sc.params["sigma"] == math.sqrt(3.0)
    assert sc.frames[0, 14, 14] == 30.0 + 2.0 * math.sqrt(3.0)
    for v in [(0.8, -0.4), (0.4, 0.6)]:
        assert scenes.table1_scenario(2.3, v, noise=False).truth[0].visible.all()


def test_paper001_two_targets():
    sc = scenes.paper001_two_targets(noise=False)
    assert sc.frames.shape == (100, 128, 128)
    a, b = sc.truth
    assert a.position[0].tolist() == [30.0, 100.0]
    assert b.position[0].tolist() == [54.0, 40.0]
    np.testing.assert_allclose(a.position[99], [30 + 0.8 * 99, 100 - 0.4 * 99])
    np.testing.assert_allclose(b.position[99], [54 + 0.4 * 99, 40 + 0.6 * 99])
    assert a.visible.all() and b.visible.all()
    assert a.amplitude == 2.0 * math.sqrt(3.0)
    assert scenes.paper001_one_target(noise=False).truth[0].visible.all()


def test_paper000_scenario():
    sc = scenes.paper000_scenario(seed=2, trials=2)
    assert sc.frames.shape == (2, 20, 64, 64)
    tr = sc.truth[0]
    assert tr.pixel[0].tolist() == [12, 52]
    assert tr.pixel[19].tolist() == [50, 14]
    assert tr.visible.all()
    assert tr.amplitude == pytest.approx(1.6, abs=1e-3)
    assert sc.params["mu"] == 0.0 and sc.params["sigma"] == 1.0


def test_scene_is_a_scene():
    sc = make_scene((4, 4), 1)
    assert isinstance(sc, Scene) and sc.truth == () and sc.target_mask().shape == (1, 4, 4)


# ---- bad input -------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, message", [
    (dict(shape=(0, 5)), "shape[0] (height) must be an integer in [1, 65535], got 0"),
    (dict(shape=(5, -2)), "shape[1] (width) must be an integer in [1, 65535], got -2"),
    (dict(shape=(5,)), "shape must be a pair (height, width) of integers in [1, 65535], got (5,)"),
    (dict(shape=(5, 5, 5)),
     "shape must be a pair (height, width) of integers in [1, 65535], got (5, 5, 5)"),
    (dict(shape=(5.0, 5)), "shape[0] (height) must be an integer in [1, 65535], got 5.0"),
    (dict(frames=0), "frames must be an integer in [1, 10000000], got 0"),
    (dict(sigma=0.0), "sigma must be a finite real number in (0, inf), got 0.0"),
    (dict(sigma=-1.0), "sigma must be a finite real number in (0, inf), got -1.0"),
    (dict(sigma=np.nan), "sigma must be a finite real number in (0, inf), got nan"),
    (dict(mu=np.inf), "mu must be a finite real number in (-inf, inf), got inf"),
    (dict(trials=0), "trials must be an integer in [1, 10000000], got 0"),
    (dict(first_trial=-1), "first_trial must be an integer in [0, inf), got -1"),
    (dict(seed=-3), "seed must be an integer in [0, inf), got -3"),
    (dict(seed=1.5), "seed must be an integer in [0, inf), got 1.5"),
    (dict(dtype=np.int32), "dtype must be float32 or float64, got int32"),
    (dict(noise="yes"), "noise must be true or false, got 'yes'"),
])
def test_make_scene_refuses_bad_parameters(kwargs, message):
    args = dict(shape=(5, 5), frames=2)
    args.update(kwargs)
    with pytest.raises(SceneError, match=whole(message)):
        make_scene(args.pop("shape"), args.pop("frames"), **args)


def test_target_truth_refuses_non_target():
    with pytest.raises(SceneError, match=whole("targets must contain Target objects, got (1, 1)")):
        make_scene((4, 4), 2, [(1, 1)])
    with pytest.raises(SceneError, match=whole("targets must be an iterable of Target, got 5")):
        make_scene((4, 4), 2, 5)


# ---- the names kept importable from here ---------------------------------------------------

def test_moved_names_are_re_exported():
    for name in scenes.__all__:
        assert hasattr(scenes, name), name
    for module in (target_module, snr, adc):
        for name in module.__all__:
            assert name in scenes.__all__ and getattr(scenes, name) is getattr(module, name)
    assert scenes.SceneError is scene_package.SceneError
