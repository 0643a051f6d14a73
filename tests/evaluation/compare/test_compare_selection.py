"""The candidate rule (:mod:`dptbd.evaluation.compare.selection`): exactly n per image, the
numba kernel equal to the plain rule, ties broken by the scene's keys."""

from __future__ import annotations

import numpy as np

from dptbd.evaluation.compare import selection


def test_select_kernel_equals_the_plain_rule_under_heavy_ties():
    # small-integer images (many pixels share the n-th largest value) and constant images:
    # the numba kernel keeps exactly min(n, H*W) pixels, the same ones as candidate_indices
    rng = np.random.default_rng(0)
    n_seg, h, w = 3, 8, 8
    near = np.zeros((n_seg, h * w), bool)
    near[:, 10:13] = True
    for case in range(120):
        energy = rng.integers(0, rng.integers(1, 6), (2 * n_seg, h * w)).astype(np.uint32)
        if case % 7 == 0:
            energy[:] = 5
        count = int(rng.integers(1, 70))
        keys = selection.image_keys(7, 3, 2, n_seg)
        idx = np.zeros((len(energy), count), np.int64)
        n_cand = np.zeros(len(energy), np.int64)
        hit = np.zeros(len(energy), np.bool_)
        near_count = np.zeros(len(energy), np.int64)
        selection._select(energy, selection.nth_largest(energy, count), keys, near, n_seg, count, idx,
                    n_cand, hit, near_count)
        for i in range(len(energy)):
            ref = selection.candidate_indices(energy[i].reshape(h, w), count, int(keys[i]))
            assert n_cand[i] == len(ref) == min(count, h * w)
            assert np.array_equal(idx[i, :n_cand[i]], ref)
            assert near_count[i] == near[i % n_seg][ref].sum() and hit[i] == (near_count[i] > 0)
            # every pixel kept is >= every pixel dropped
            kept = np.zeros(h * w, bool)
            kept[ref] = True
            if 0 < kept.sum() < h * w:
                assert energy[i][kept].min() >= energy[i][~kept].max()


def test_tie_break_is_keyed_by_the_scene_and_spread_over_the_frame():
    flat = np.zeros((16, 16))
    keys = selection.image_keys(2024, 0, 200, 8)
    assert len(np.unique(keys)) == keys.size                       # one key per image
    assert np.array_equal(keys[8:16], selection.image_keys(2024, 1, 1, 8))  # a trial's keys, any chunk
    assert not np.array_equal(keys, selection.image_keys(2025, 0, 200, 8))  # seeded
    rows = np.concatenate([selection.candidate_indices(flat, 8, int(k)) // 16 for k in keys])
    # a constant image: the 8 kept pixels are spread over the frame, not the first rows
    # (raster order would keep row 0 only); expected fraction in the top half 0.5
    assert 0.46 < np.mean(rows < 8) < 0.54
    assert np.array_equal(selection.candidate_indices(flat, 8, 5), selection.candidate_indices(flat, 8, 5))
