"""Histogram segmentation (docs/arithmetic.md §6) against a sort-based oracle."""

import numpy as np
import pytest

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
    with pytest.raises(ValueError, match=r"rate must be in \[0, 1\]"):
        count_for_rate(1.5, 100)
    with pytest.raises(ValueError, match="count must be an integer >= 0"):
        candidate_mask(np.zeros((4, 4)), -1)
    with pytest.raises(ValueError, match="same shape"):
        candidates(np.zeros((4, 4)), np.zeros((4, 3)), 2)
