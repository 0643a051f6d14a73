"""``dptbd.evaluation.family.recursive_pipeline``: the recursive DP's maps through the DSP
association."""

from __future__ import annotations


import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.dsp.association import AssociationConfig
from dptbd.dsp.backtrack import backtrack
from dptbd.evaluation.family import detection as fd
from dptbd.errors import DptbdError
from dptbd.evaluation.family.association import job_outcome, job_run
from dptbd.evaluation.family.recursive_pipeline import (associate_lists, independent_lists,
                                                        recursive_lists, recursive_view,
                                                        run_recursive_pipeline)
from dptbd.model.family import run_family_fixed
from helpers.refusals import whole


def _scene(seed=0, n_t=20, size=24):
    rng = np.random.default_rng(seed)
    frames = rng.integers(0, 40, (n_t, size, size))
    for t in range(n_t):  # a bright target moving (+1, +1) per frame
        frames[t, 2 + t, 1 + t] = 255
    return frames


def test_view_and_refusals():
    cfg = DPConfig(width=8, height=8, recursive=True, forgetting=0.5)
    view = recursive_view(cfg, 6, 3)
    assert (view.segment_frames, view.segment_stride, view.recursive) == (6, 3, False)
    with pytest.raises(ValueError, match=r"^run_recursive_pipeline needs a configuration with "
                                         r"recursive=True$"):
        recursive_view(cfg.replace(recursive=False), 6, 6)
    with pytest.raises(ValueError, match=whole(
            "every must be an integer in [1, path_frames=6], got 7")):
        recursive_view(cfg, 6, 7)


def test_maps_and_lists_come_from_the_recursion():
    frames = _scene()
    cfg = DPConfig(width=24, height=24, recursive=True, forgetting=0.75, energy_bits=16)
    res = run_recursive_pipeline(frames, cfg, 5, AssociationConfig(), path_frames=6, every=4)
    np.testing.assert_array_equal(res.segments.end_frames, [5, 9, 13, 17])
    full = run_family_fixed(frames, cfg)
    for s, t in enumerate(res.segments.end_frames):
        np.testing.assert_array_equal(res.segments.energy[s], full.energy[t])
        np.testing.assert_array_equal(res.maps[s, 1:], full.direction[t - 4:t + 1])
        assert np.all(res.maps[s, 0] == cfg.start_code)
    # the target is each map's strongest pixel; its path is the true track's last 6 frames
    for s, t in enumerate(res.segments.end_frames):
        path = backtrack(res.maps[s], 2 + t, 1 + t, res.cfg)
        np.testing.assert_array_equal(path, [(2 + f, 1 + f) for f in range(t - 5, t + 1)])
    assert len(res.tracks) == 1


def test_job_outcome_counts_the_lists():
    seg = job_outcome(fd.segments(6), 0)
    rec = job_outcome(fd.recursive(0.8, segment_frames=6), 0)
    assert seg.maps == rec.maps == 16
    assert all(opp == 16 for _, opp in seg.hits) and all(opp == 16 for _, opp in rec.hits)


def test_independent_lists_of_one_sequence_are_the_recursions_lists():
    frames = _scene(n_t=20)
    cfg = DPConfig(width=24, height=24, recursive=True, forgetting=0.75, energy_bits=16)
    ref, ref_maps = recursive_lists(frames, cfg, path_frames=6, every=4)
    # list s from its own sequence: here every sequence is the same, so every list is the same
    own, own_maps = independent_lists([frames[:6 + 4 * s] for s in range(4)], cfg,
                                      path_frames=6, every=4)
    np.testing.assert_array_equal(own.end_frames, ref.end_frames)
    np.testing.assert_array_equal(own.energy, ref.energy)
    np.testing.assert_array_equal(own.direction, ref.direction)
    np.testing.assert_array_equal(own_maps, ref_maps)
    # the pipeline is the association of those lists
    res = run_recursive_pipeline(frames, cfg, 5, AssociationConfig(), path_frames=6, every=4)
    again = associate_lists(ref, ref_maps, recursive_view(cfg, 6, 4), 5, AssociationConfig())
    assert [t.id for t in res.tracks] == [t.id for t in again.tracks]
    np.testing.assert_array_equal(res.tracks[0].points, again.tracks[0].points)
    with pytest.raises(ValueError, match=whole(
            "independent_lists: sequence 1 must be (T, H, W) with T > 9 frames, got shape (9, 24, 24)")):
        independent_lists([frames, frames[:9]], cfg, path_frames=6, every=4)


@pytest.mark.parametrize("kwargs, message", [
    (dict(lists="x"), "lists must be one of 'recursion', 'independent', got 'x'"),
    (dict(lists="independent"), "lists='independent' needs a recursive variant, got 'segments K=6'"),
    (dict(count=0), "count must be an integer in [1, 128], got 0"),
])
def test_job_run_refusals(kwargs, message):
    with pytest.raises(DptbdError, match=whole(message)):
        job_run(fd.segments(6), 0, **kwargs)


def test_noise_only_and_independent_lists():
    seg = job_run(fd.segments(6), 3, noise_only=True, count=20)
    assert seg.truth == () and seg.evaluation.false_tracks == len(seg.result.tracks)
    # lists of n = 20 (fewer where pixels tie at the 21st largest), all given to the tracker
    sizes = [len(c) for c in seg.result.candidates]
    assert len(sizes) == 16 and max(sizes) == 20 and seg.result.stats["candidates"] == sum(sizes)
    rec = fd.recursive(0.7, segment_frames=6)
    one = job_run(rec, 3, noise_only=True, lists="recursion")
    own = job_run(rec, 3, noise_only=True, lists="independent")
    np.testing.assert_array_equal(one.result.segments.end_frames, own.result.segments.end_frames)
    # list 0 differs (its own noise), and the lists are those of the recursion on that noise
    assert not np.array_equal(one.result.segments.energy[0], own.result.segments.energy[0])
