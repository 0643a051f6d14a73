"""Backtracking the direction maps of the bit-accurate model (paper 001 §2): a path per segment,
a position per frame."""

import numpy as np

from dptbd.config import DPConfig
from dptbd.dsp.backtrack import backtrack, segment_direction_maps, track_positions
from dptbd.scenes import synthetic as scenes

K = 6  # frames per segment; stride K


def test_backtracking_recovers_the_path_of_a_bright_target():
    """Direction maps of the bit-accurate model, walked back from the segment's last frame."""
    cfg = DPConfig(width=32, height=24, segment_frames=K, input_bits=12, energy_bits=16)
    target = scenes.Target((3.0, 4.0), (0.8, 0.6), 40.0)
    scene = scenes.make_scene((24, 32), 3 * K, [target], mu=30.0, sigma=1.0, seed=3)
    frames = scene.quantised(12, gain=16.0)
    maps = segment_direction_maps(frames, cfg)
    assert maps.shape == (3, K, 24, 32) and np.all(maps[:, 0] == cfg.start_code)
    truth = scene.truth[0].pixel
    for s in range(3):
        end = s * K + K - 1
        path = backtrack(maps[s], *truth[end], cfg)
        np.testing.assert_array_equal(path, truth[s * K:end + 1])
    points = np.zeros(2, dtype=[("seg", "i4"), ("row", "u2"), ("col", "u2")])
    points["seg"] = [0, 2]
    points["row"], points["col"] = truth[[K - 1, 3 * K - 1]].T
    frames_idx, pos, measured = track_positions(points, maps, cfg)
    np.testing.assert_array_equal(frames_idx, np.arange(3 * K))
    assert measured.sum() == 2 * K and not measured[K:2 * K].any()
    np.testing.assert_array_equal(pos[measured], truth[measured])
    err = np.abs(pos[K:2 * K] - scene.truth[0].position[K:2 * K]).max()
    assert err < 1.5                                    # interpolated across the missed segment
