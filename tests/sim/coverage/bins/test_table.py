"""The campaign's bins (:mod:`dptbd.sim.coverage.bins.table`): the merge by addition and the
table in group order."""

from __future__ import annotations

from dptbd.sim.coverage import bins


def test_merge_adds_hits_over_the_union_of_declared_bins():
    assert bins.merge({"a: x": 1, "b: y": 0}, {"a: x": 2, "c: z": 0}, {}) == \
        {"a: x": 3, "b: y": 0, "c: z": 0}
    assert bins.merge() == {}
    assert bins.table({"reset: 10 words in flight": 1, "reset: 2 words in flight": 0,
                       "stall: gaps light, back-pressure none, interior": 5,
                       "stall: gaps none, back-pressure heavy, first row": 7}) == [
        ("stall: gaps none, back-pressure heavy, first row", "dp, core, segmenter, axi", 7),
        ("stall: gaps light, back-pressure none, interior", "dp, core, segmenter, axi", 5),
        ("reset: 2 words in flight", "dp, core, segmenter", 0),
        ("reset: 10 words in flight", "dp, core, segmenter", 1)]
