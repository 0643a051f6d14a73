"""The candidate rules (:mod:`dptbd.evaluation.compare.selection`): ``random`` (exactly n per
image, the numba kernel equal to the plain rule, ties broken by the scene's keys) and the
gateware segmenter's ``gateware`` and ``gateware-bins``, on hand-made images with ties and
against the model's §6 selection."""

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


# ---- the rules on hand-made images with ties ----------------------------------------------

#: 4 x 4, raster indices: 0 -> 5, 10 -> 6, four pixels tied at 4 (2, 3, 5, 8), two at 3
#: (12, 13); sorted descending 6, 5, 4, 4, 4, 4, 3, 3, 2, 2, 1, 1, 1, 0, 0, 0.
_HAND = np.array([[5, 1, 4, 4],
                  [0, 4, 2, 1],
                  [4, 0, 6, 1],
                  [3, 3, 2, 0]], np.uint32)
_TIED_AT_4 = [2, 3, 5, 8]


def _plan(count: int, tie_rule: str, n_seg: int = 1, near=None):
    """What the rules read of a Plan: the candidate count, the rule, the segments, the gate."""
    from types import SimpleNamespace
    near = np.zeros((n_seg, 16), bool) if near is None else near
    return SimpleNamespace(spec=SimpleNamespace(candidate_count=count, tie_rule=tie_rule),
                           ends=np.zeros(n_seg), near_flat=near)


def _hand_cfg(width=4, height=4, **kw):
    """A DPConfig of the image size (the histogram fields under test)."""
    import warnings
    from dptbd.config import DPConfig, EnergyWidthWarning
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(width=width, height=height, **kw)


def _kept(cand, i=0) -> list[int]:
    return cand.idx[i, :cand.n_cand[i]].tolist()


def _run(rule, image, count, key=12345, cfg=None, near=None):
    plan = _plan(count, rule, near=near)
    return selection._candidates(image[None], np.zeros((1,) + image.shape, np.uint8), plan,
                                 np.array([key], np.uint64), cfg)


def test_one_function_per_rule_of_the_spec():
    from dptbd.evaluation.compare.spec import TIE_RULES
    assert tuple(selection.RULES) == TIE_RULES


def test_random_rule_fills_up_to_n_from_the_tie_by_priority():
    # n = 3: 6 and 5 are above the 3rd largest (4); one of the four pixels at 4 fills the
    # third place: the one with the smallest priority _mix(key ^ p * golden)
    for key in (1, 2, 12345, 2**63 + 7):
        with np.errstate(over="ignore"):  # uint64 arithmetic wraps, as in the kernel
            prio = {p: int(selection._mix_np(np.uint64(key) ^ (np.uint64(p) * selection._GOLDEN)))
                    for p in _TIED_AT_4}
        assert _kept(_run("random", _HAND, 3, key)) == sorted([0, 10, min(prio, key=prio.get)])
    # n = 6: everything down to the tie, which fits whole; n = 7: one of the two 3s
    assert _kept(_run("random", _HAND, 6)) == [0, 2, 3, 5, 8, 10]
    kept7 = _kept(_run("random", _HAND, 7))
    assert len(kept7) == 7 and set(kept7) - {0, 2, 3, 5, 8, 10} in ({12}, {13})


def test_gateware_rule_drops_the_tie_at_the_boundary_whole():
    # keep E > the (n+1)-th largest E
    expected = {1: [10],                  # 2nd largest 5
                2: [0, 10],               # 3rd largest 4
                3: [0, 10],               # 4th largest 4: the four 4s dropped, 2 < n kept
                5: [0, 10],               # 6th largest 4
                6: [0, 2, 3, 5, 8, 10],   # 7th largest 3
                7: [0, 2, 3, 5, 8, 10],   # 8th largest 3: the two 3s dropped
                8: [0, 2, 3, 5, 8, 10, 12, 13],
                15: [0, 1, 2, 3, 5, 6, 7, 8, 10, 11, 12, 13, 14],  # 16th largest 0: the 0s out
                16: list(range(16))}      # n >= H*W: every pixel
    for n, want in expected.items():
        for key in (1, 99):               # no priorities: the key does not matter
            assert _kept(_run("gateware", _HAND, n, key)) == want, n
        # on the float image: the same rule
        assert _kept(_run("gateware", _HAND.astype(np.float64), n)) == want, n


def test_gateware_bins_rule_selects_on_the_configurations_bins():
    # s = 1: bins E >> 1 = [2 0 2 2 / 0 2 1 0 / 2 0 3 0 / 1 1 1 0]; n = 3: the 4th largest
    # bin is 2, so only the 6 (bin 3) is kept, though E = 5 is above every 4
    cfg1 = _hand_cfg(histogram_shift=1)
    assert cfg1.bin_shift == 1
    assert _kept(_run("gateware-bins", _HAND, 3, cfg=cfg1)) == [10]
    assert _kept(_run("gateware-bins", _HAND, 6, cfg=cfg1)) == [0, 2, 3, 5, 8, 10]  # 7th: 1
    # s = 2: bins [1 0 1 1 / 0 1 0 0 / 1 0 1 0 / 0 0 0 0]: six pixels in bin 1, n = 3 keeps none
    assert _kept(_run("gateware-bins", _HAND, 3, cfg=_hand_cfg(histogram_shift=2))) == []
    # s = 0 with 4 bins: min(E, 3) clamps 6, 5, 4 and 3 into bin 3 (8 pixels): n = 3 keeps none
    clamp = _hand_cfg(histogram_shift=0, histogram_bits=2)
    assert _kept(_run("gateware-bins", _HAND, 3, cfg=clamp)) == []
    assert _kept(_run("gateware-bins", _HAND, 8, cfg=clamp)) == [0, 2, 3, 5, 8, 10, 12, 13]
    # s = 0 with enough bins is the gateware rule; a float model (cfg None) selects on E
    cfg0 = _hand_cfg(histogram_shift=0)
    for n in range(17):
        want = _kept(_run("gateware", _HAND, n))
        assert _kept(_run("gateware-bins", _HAND, n, cfg=cfg0)) == want
        assert _kept(_run("gateware-bins", _HAND.astype(np.float32), n)) == want


def test_every_rule_counts_the_candidates_in_the_gate():
    near = np.zeros((1, 16), bool)
    near[0, [2, 3, 10, 12]] = True
    for rule, n, cfg in [("random", 3, None), ("gateware", 3, None), ("gateware", 7, None),
                         ("gateware-bins", 3, _hand_cfg(histogram_shift=1)),
                         ("gateware-bins", 3, _hand_cfg(histogram_shift=2))]:
        cand = _run(rule, _HAND, n, cfg=cfg, near=near)
        inside = int(near[0, _kept(cand)].sum())
        assert cand.near_count[0] == inside and cand.hit[0] == (inside > 0), (rule, n)


def test_gateware_rules_are_the_segmenters_selection_with_the_images_own_histogram():
    """``gateware`` = ``dptbd.model.segmentation.segment_fixed`` thresholding each image
    with its OWN histogram at s = 0 (enough bins: one per E value), and ``gateware-bins`` =
    the same at the configuration's s and bin count (clamped top bin included)."""
    from dptbd.model.segmentation import candidate_mask, histogram_fixed, segment_fixed

    rng = np.random.default_rng(5)
    h, w = 12, 16
    for case in range(40):
        levels = int(rng.choice([3, 12, 60, 400]))
        n = int(rng.integers(0, 40))
        images = rng.integers(0, levels, (3, h, w)).astype(np.uint32)
        direction = rng.integers(0, 9, (3, h, w)).astype(np.uint8)
        flat = images.reshape(3, -1)
        plan = _plan(n, "gateware", n_seg=3, near=np.zeros((3, h * w), bool))
        keys = selection.image_keys(1, 0, 1, 3)
        own = _hand_cfg(w, h, candidate_count=n, histogram_bits=9, histogram_shift=0)
        binned = _hand_cfg(w, h, candidate_count=n, histogram_bits=int(rng.integers(2, 6)),
                           histogram_shift=int(rng.integers(0, 4)))
        got = selection.gateware_rule(flat, plan, keys, None)
        got_bins = selection.gateware_bins_rule(flat, plan, keys, binned)
        for i in range(3):
            for cfg, (idx, n_cand, _, _) in ((own, got), (binned, got_bins)):
                lst = segment_fixed(images[i], direction[i], cfg,
                                    prev_hist=histogram_fixed(images[i], cfg))
                assert not lst.overflow and lst.count <= n
                assert idx[i, :n_cand[i]].tolist() == (lst.records["row"].astype(int) * w
                                                        + lst.records["col"]).tolist()
            # ... and the s = 0 rule is the model's E > v_(n+1)
            assert got[0][i, :got[1][i]].tolist() == np.flatnonzero(
                candidate_mask(images[i], n)).tolist()


def test_random_rule_is_the_select_kernel_unchanged():
    # the random rule through _candidates is exactly the _select kernel at the n-th largest,
    # and a pinned case keeps its tie-break (the default run's outputs depend on it)
    rng = np.random.default_rng(3)
    energy = rng.integers(0, 4, (6, 64)).astype(np.uint32)
    keys = selection.image_keys(2024, 5, 3, 2)
    near = np.zeros((2, 64), bool)
    near[:, 20:30] = True
    plan = _plan(9, "random", n_seg=2, near=near)
    cand = selection._candidates(energy.reshape(6, 8, 8), np.zeros((6, 8, 8), np.uint8), plan, keys)
    idx = np.zeros((6, 9), np.int64)
    n_cand, hit, near_count = np.zeros(6, np.int64), np.zeros(6, np.bool_), np.zeros(6, np.int64)
    selection._select(energy, selection.nth_largest(energy, 9), keys, near, 2, 9, idx, n_cand, hit,
                      near_count)
    assert np.array_equal(cand.idx, idx) and np.array_equal(cand.n_cand, n_cand)
    assert np.array_equal(cand.hit, hit) and np.array_equal(cand.near_count, near_count)
    assert selection.candidate_indices(_HAND, 3, 2024).tolist() == [0, 3, 10]   # computed before the rules were added
