"""Histogram segmentation (docs/arithmetic.md §6) against a sort-based oracle."""

import numpy as np
import pytest

from dptbd.errors import DptbdError
from dptbd.model.segmentation import candidate_mask, candidates, count_for_rate, threshold_level


def oracle_mask(image, n):
    """Keep the pixels strictly above the (n+1)-th largest value; computed by sorting."""
    values = np.sort(image.ravel())[::-1]
    if n >= values.size:
        return np.ones(image.shape, bool)
    return image > values[n]


@pytest.mark.parametrize("levels", [3, 50, 100000])
@pytest.mark.parametrize("n", [0, 1, 5, 33, 63, 64, 100])
def test_mask_matches_sort_oracle(levels, n):
    rng = np.random.default_rng(levels * 1000 + n)
    image = rng.integers(0, levels, (8, 8)).astype(np.uint32)
    mask = candidate_mask(image, n)
    np.testing.assert_array_equal(mask, oracle_mask(image, n))
    assert mask.sum() <= n


def test_distinct_values_give_exactly_n():
    image = np.random.default_rng(0).permutation(128 * 128).reshape(128, 128)
    assert candidate_mask(image, 33).sum() == 33
    assert candidate_mask(image.astype(float) / 7, 33).sum() == 33


def test_ties_at_the_boundary_are_excluded_not_broken():
    image = np.array([[9, 7, 7], [7, 1, 0], [0, 0, 0]])
    # n = 2: the 3rd largest is 7, tied with the 2nd: only the 9 is kept
    np.testing.assert_array_equal(np.argwhere(candidate_mask(image, 2)), [[0, 0]])
    assert candidate_mask(image, 4).sum() == 4


def test_batched_images_each_get_their_own_threshold():
    rng = np.random.default_rng(3)
    images = rng.normal(size=(3, 2, 16, 16))
    masks = candidate_mask(images, 10)
    for idx in np.ndindex(3, 2):
        np.testing.assert_array_equal(masks[idx], oracle_mask(images[idx], 10))
    assert threshold_level(images, 10).shape == (3, 2)


def test_candidate_records_in_raster_order():
    energy = np.array([[5, 1, 8], [2, 9, 3], [7, 0, 4]], dtype=np.uint32)
    direction = np.arange(9, dtype=np.uint8).reshape(3, 3)
    rec = candidates(energy, direction, 3)
    assert rec.dtype["energy"] == np.uint32
    assert [(r["row"], r["col"], r["energy"], r["direction"]) for r in rec] == [
        (0, 2, 8, 2), (1, 1, 9, 4), (2, 0, 7, 6)]


def test_count_for_rate_paper_setting():
    assert count_for_rate(0.002, 128 * 128) == 33
    assert count_for_rate(0.0, 100) == 0
    with pytest.raises(DptbdError, match=r"^false-alarm rate must be a finite real number in \[0, 1\], "
                                         r"got 1\.5$"):
        count_for_rate(1.5, 100)
    with pytest.raises(DptbdError, match=r"^n_pixels must be an integer in \[1, inf\), got 0$"):
        count_for_rate(0.5, 0)
    with pytest.raises(DptbdError, match=r"^candidate count must be an integer in \[0, inf\), got -1$"):
        candidate_mask(np.zeros((4, 4)), -1)
    with pytest.raises(ValueError, match=(r"^energy and direction must be two images of the "
                                          r"same shape \(H, W\), got \(4, 4\) and \(4, 3\)$")):
        candidates(np.zeros((4, 4)), np.zeros((4, 3)), 2)


# ---------------------------------------------------------------------------------------
# the gateware segmenter's model (docs/arithmetic.md §6.1 - §6.5)
# ---------------------------------------------------------------------------------------

import warnings  # noqa: E402

from dptbd.config import DPConfig, EnergyWidthWarning  # noqa: E402
from dptbd.model.segmentation import (  # noqa: E402
    histogram_bins,
    histogram_fixed,
    segment_fixed,
    segment_sequence,
    segment_stream,
    threshold_bin,
)


def seg_config(**kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**kw)


def brute_threshold(true_counts, n):
    """Smallest T with sum(h[T:]) <= n, on the unsaturated histogram."""
    for t in range(len(true_counts) + 1):
        if true_counts[t:].sum() <= n:
            return t
    raise AssertionError


@pytest.mark.parametrize("n", [0, 1, 3, 7, 30])
@pytest.mark.parametrize("seed", range(4))
def test_threshold_bin_matches_brute_force_despite_saturation(n, seed):
    cfg = seg_config(width=16, height=16, candidate_count=n, histogram_bits=4, histogram_shift=0)
    rng = np.random.default_rng(seed)
    energy = rng.integers(0, [4, 16, 40, 16][seed], (16, 16))
    true = np.bincount(np.minimum(energy, 15).ravel(), minlength=16)
    hist = histogram_fixed(energy, cfg)
    np.testing.assert_array_equal(hist, np.minimum(true, (1 << cfg.bin_count_bits) - 1))
    assert threshold_bin(hist, cfg) == brute_threshold(true, n)


def test_saturation_happens_and_is_harmless():
    cfg = seg_config(width=8, height=8, candidate_count=2, candidate_capacity=2,
                     histogram_bits=3, histogram_shift=0)
    energy = np.zeros((8, 8), int)
    energy[0, :3] = 7
    hist = histogram_fixed(energy, cfg)
    assert cfg.bin_count_bits == 2 and hist[0] == 3           # 61 pixels saturate at 3 (C = 2)
    assert threshold_bin(hist, cfg) == brute_threshold(np.bincount(energy.ravel(), minlength=8), 2)
    assert threshold_bin(hist, cfg) == 8                       # the top bin's 3 > n = 2


def test_bins_shift_and_clamp():
    cfg = seg_config(width=4, height=4, histogram_bits=3, histogram_shift=2, energy_bits=16)
    e = np.array([0, 3, 4, 27, 28, 31, 32, 65535])
    np.testing.assert_array_equal(histogram_bins(e, cfg), [0, 0, 1, 6, 7, 7, 7, 7])
    with pytest.raises(ValueError, match=r"^energy must be in \[0, E_max = 65535\]$"):
        histogram_bins(np.array([-1]), cfg)


def test_same_segment_histogram_is_the_section_6_rule():
    """With s = 0, enough bins and C >= n, thresholding an image with its OWN histogram is
    exactly :func:`candidates` (E > the (n+1)-th largest E)."""
    rng = np.random.default_rng(11)
    for n, levels in [(5, 30), (33, 200), (0, 10), (12, 3)]:
        cfg = seg_config(width=16, height=12, candidate_count=n, histogram_bits=8,
                         histogram_shift=0)
        energy = rng.integers(0, levels, (12, 16)).astype(np.uint32)
        direction = rng.integers(0, 10, (12, 16)).astype(np.uint8)
        got = segment_fixed(energy, direction, cfg, prev_hist=histogram_fixed(energy, cfg))
        want = candidates(energy, direction, n)
        assert got.count <= n and not got.overflow
        np.testing.assert_array_equal(got.records, want)


def test_first_segment_is_empty_and_unprimed():
    cfg = seg_config(width=8, height=8, candidate_count=3, histogram_bits=4)
    assert cfg.bin_shift == 6                          # bitlen(4 * 255) = 10 bits over 16 bins
    energy = np.arange(64).reshape(8, 8) * 16
    lst = segment_fixed(energy, np.zeros((8, 8), int), cfg)
    assert (lst.count, lst.threshold, lst.primed, lst.overflow) == (0, 16, False, False)
    assert lst.trailer == {"count": 0, "threshold": 16, "overflow": 0, "primed": 0,
                           "aligned": 1, "missed": 0}
    np.testing.assert_array_equal(lst.histogram, np.full(16, 4))


def test_stale_threshold_cap_keeps_the_first_c_in_raster_order():
    cfg = seg_config(width=4, height=4, candidate_count=2, candidate_capacity=3,
                     histogram_bits=4, histogram_shift=0)
    prev = np.zeros((4, 4), int)
    prev[0, :3] = [9, 8, 7]                 # threshold from this: T = 8 (two pixels >= 8)
    cur = np.array([[0, 9, 8, 7], [15, 8, 0, 0], [12, 0, 0, 8], [8, 0, 0, 0]])
    lst = segment_fixed(cur, np.arange(16).reshape(4, 4), cfg, histogram_fixed(prev, cfg))
    assert lst.threshold == 8
    assert [(r["row"], r["col"]) for r in lst.records] == [(0, 1), (0, 2), (1, 0)]
    assert lst.overflow and lst.count == 3            # (1,1), (2,0), (2,3), (3,0) dropped
    assert 7 not in lst.records["energy"]             # bin T - 1 is excluded


def test_ties_in_the_threshold_bin_are_all_kept_or_all_excluded():
    cfg = seg_config(width=4, height=4, candidate_count=3, histogram_bits=3, histogram_shift=1)
    energy = np.array([[14, 15, 15, 14], [12, 13, 10, 11], [0] * 4, [0] * 4])  # bins 7x4 6x2 5x2
    hist = histogram_fixed(energy, cfg)
    assert threshold_bin(hist, cfg) == 8              # four pixels share the top bin > n = 3
    cfg6 = cfg.replace(candidate_count=6)
    assert threshold_bin(histogram_fixed(energy, cfg6), cfg6) == 6     # 4 + 2 = 6 <= 6
    cfg5 = cfg.replace(candidate_count=5)
    assert threshold_bin(histogram_fixed(energy, cfg5), cfg5) == 7     # 6 > 5: bin 6 out


def test_empty_bins_below_the_last_kept_bin_lower_the_threshold():
    """T = bin of the (n+1)-th largest E, plus one: empty bins between it and the kept bins
    are included, so a later image's pixels there are selected (§6.3)."""
    cfg = seg_config(width=4, height=4, candidate_count=2, histogram_bits=4, histogram_shift=0)
    prev = np.zeros((4, 4), int)
    prev[0, :3] = [9, 8, 1]
    assert threshold_bin(histogram_fixed(prev, cfg), cfg) == 2


def test_stream_model_equals_the_image_model_on_well_formed_streams():
    cfg = seg_config(width=6, height=5, segment_frames=3, candidate_count=4,
                     candidate_capacity=5, histogram_bits=5, histogram_shift=3)
    rng = np.random.default_rng(2)
    n_seg = 5
    frames_e = rng.integers(0, 300, (n_seg * 3, 5, 6))
    frames_d = rng.integers(0, 10, (n_seg * 3, 5, 6))
    states = np.zeros((n_seg * 3, 5, 6, 5), int)
    states[..., 0], states[..., 1] = frames_e, frames_d
    states[:, :, -1, 2] = 1
    states[:, -1, -1, 3] = 1
    states[2::3, -1, -1, 4] = 1
    by_stream = segment_stream(states.reshape(-1, 5), cfg)
    by_image = segment_sequence(frames_e[2::3], frames_d[2::3], cfg)
    assert len(by_stream) == len(by_image) == n_seg
    for a, b in zip(by_stream, by_image):
        np.testing.assert_array_equal(a.records, b.records)
        assert a.trailer == b.trailer
        np.testing.assert_array_equal(a.histogram, b.histogram)
    assert any(lst.overflow for lst in by_image) and by_image[1].primed


def test_stream_model_realigns_on_end_of_segment():
    """A frame cut short (the DP resynchronised): the list in progress is not aligned, the
    segment end seen outside a scored frame is reported as missed, and after it the lists
    are aligned again."""
    cfg = seg_config(width=4, height=3, segment_frames=2, candidate_count=2, histogram_bits=3,
                     histogram_shift=5)
    rng = np.random.default_rng(4)

    def frames(n, first_k=0):
        out = np.zeros((n, 3, 4, 5), int)
        out[..., 0] = rng.integers(0, 256, (n, 3, 4))
        out[:, -1, -1, 3] = 1
        for t in range(n):
            out[t, -1, -1, 4] = int((t + first_k) % 2 == 1)
        return out.reshape(-1, 5)

    cut = frames(1)[:5]
    cut[:, 3:] = 0
    stream = np.concatenate([frames(2), cut, frames(6)])
    lists = segment_stream(stream, cfg)
    assert [(lst.aligned, lst.missed) for lst in lists] == [
        (True, False), (False, False), (True, True), (True, False)]


def test_stream_model_keeps_the_settings_at_a_misaligned_segment_start():
    """§6.5a: after a resync the segmenter takes settings only where it realigns. K = 1
    until a frame is cut after 5 words, then a resync's segment of K = 3 (and n = 0): the
    counters' own segment starts (words 24, 36, 48) keep K = 1 (a list per 12 words, the
    last one cut at the end_of_segment of word 52); the word after it takes K = 3. Taking
    the word's own segment's K = 3 at word 24 would give 4 lists."""
    cfg = seg_config(width=4, height=3, segment_frames=1, max_segment_frames=3,
                     candidate_count=2, histogram_bits=3, histogram_shift=5)
    rng = np.random.default_rng(5)

    def frames(n, k):
        out = np.zeros((n, 3, 4, 5), int)
        out[..., 0] = rng.integers(0, 256, (n, 3, 4))
        out[:, :, -1, 2] = 1
        out[:, -1, -1, 3] = 1
        out[k - 1::k, -1, -1, 4] = 1
        return out.reshape(-1, 5)

    cut = frames(1, 1)[:5]
    cut[:, 2:] = 0
    stream = np.concatenate([frames(1, 1), cut, frames(6, 3)])
    settings = np.array([[1, 2, 5]] * 17 + [[3, 0, 5]] * 72)
    lists = segment_stream(stream, cfg, settings)
    assert [(lst.aligned, lst.missed) for lst in lists] == [
        (True, False), (False, False), (False, False), (False, False), (False, False),
        (True, False)]


def test_segment_fixed_shape_errors():
    cfg = seg_config(width=4, height=4)
    with pytest.raises(ValueError, match=(r"^energy and direction must both have shape \(H, "
                                          r"W\) = \(4, 4\), got \(4, 5\) and \(4, 5\)$")):
        segment_fixed(np.zeros((4, 5)), np.zeros((4, 5)), cfg)
    with pytest.raises(ValueError, match=r"^histogram must have 16 bins, got shape \(32,\)$"):
        threshold_bin(np.zeros(32), seg_config(width=4, height=4, histogram_bits=4))
