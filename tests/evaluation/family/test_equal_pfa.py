"""K-frame segments against the recursive DP at equal Pfa per pixel: one threshold per map
index from the noise-only scenes, counts at each threshold, refusals."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.evaluation.family import detection as fd
from dptbd.evaluation.family import equal_pfa as ep
from dptbd.evaluation.metrics import DetectionCounts
from dptbd.evaluation.pfa import PfaError, pixel_threshold
from helpers.refusals import whole

SETTING = [(2.3, (0.2, 0.2))]  # stays inside 32 x 32, its gate too


def test_thresholds_are_each_map_index_quantile_of_the_noise_only_scenes():
    variants = [fd.segments(8), fd.recursive(0.9, warmup=0)]
    res = ep.compare_equal_pfa(variants, [0.01, 0.001], trials=1, seed=3, noise_seeds=[40, 41],
                               settings=SETTING, size=32)
    assert res.labels == ("segments K=8", "recursive alpha=0.9")
    for v in variants:
        maps = np.stack([ep.noise_maps(v, s, 32) for s in (40, 41)])  # (seeds, S, H, W)
        assert maps.shape[1] == ep.scored_maps(v, 32) == (12 if v.forgetting is None else 100)
        thr = res.thresholds[v.label]
        assert thr.shape == (2, maps.shape[1])
        for m in range(maps.shape[1]):
            assert thr[0, m] == pixel_threshold(maps[:, m], 0.01)
            assert thr[1, m] == pixel_threshold(maps[:, m], 0.001)
        above = [(maps > thr[j][None, :, None, None]).sum() for j in range(2)]
        assert res.measured[v.label] == (above[0] / maps.size, above[1] / maps.size)
        assert res.measured[v.label][0] <= 0.01 and res.measured[v.label][1] <= 0.001
        assert res.noise_pixels[v.label] == maps.size
    # the recursion's noise-only E grows with the frame: its thresholds do too
    # (about 1 / (1 - 0.9) = 10 times the first frame's at the end)
    rec = res.thresholds["recursive alpha=0.9"][0]
    assert np.all(np.diff(rec[:20]) > 0) and rec[-1] > 5 * rec[0]
    c = res.pooled("segments K=8", 0)
    assert c.frames == 12 and c.opportunities == 12
    assert res.per_scene("segments K=8", 0) == [c]
    again = ep.compare_equal_pfa(variants, [0.01, 0.001], trials=1, seed=3, noise_seeds=[40, 41],
                                 settings=SETTING, size=32)
    assert all(np.array_equal(again.thresholds[k], res.thresholds[k]) for k in res.labels)
    assert again.counts == res.counts


def test_threshold_counts_at_the_extremes():
    v = fd.segments(8)
    lo, hi = ep.threshold_counts(v, 2.3, (0.2, 0.2), [-np.inf, np.inf], trials=1, seed=3, size=32)[0]
    # every pixel above -inf: a detection in every map, all pixels outside the 3x3 gate false
    assert lo == DetectionCounts(12, 12, 12 * (32 * 32 - 9), 12)
    assert hi == DetectionCounts(0, 12, 0, 12)
    per_map = ep.threshold_counts(v, 2.3, (0.2, 0.2), [np.full(12, -np.inf)], trials=1, seed=3,
                                  size=32)[0][0]
    assert per_map == lo


@pytest.mark.parametrize("kw, message", [
    (dict(pfas=[1.0]), "pfa (false-alarm probability per pixel) must be a finite real number in (0, 1), got 1.0"),
    (dict(pfas=[0]), "pfa (false-alarm probability per pixel) must be a finite real number in (0, 1), got 0"),
    (dict(pfas=[]), "pfa must hold at least one false-alarm probability in (0, 1)"),
    (dict(pfas=[1e-4]),
     "pfa=0.0001 needs at least 10000 noise-only pixels, got 2048; add noise-only scenes or raise pfa"),
    (dict(noise_seeds=[5, 5]), "seeds must be distinct, got [5, 5]"),
    (dict(variants=[]), "variants must hold at least one variant"),
    (dict(trials=0), "trials must be an integer in [1, inf), got 0"),
])
def test_refusals_before_any_work(kw, message):
    args = dict(variants=[fd.segments(8)], pfas=[0.01], trials=1, seed=3, noise_seeds=[40, 41],
                settings=SETTING, size=32)
    args.update(kw)
    with pytest.raises(PfaError, match=whole(message)):
        ep.compare_equal_pfa(args.pop("variants"), args.pop("pfas"), **args)
