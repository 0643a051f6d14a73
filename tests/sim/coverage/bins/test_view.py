"""The model's view of a run (:mod:`dptbd.sim.coverage.bins.view`): where its lists end."""

from __future__ import annotations

import pytest

from dptbd.model.segmentation import segment_stream
from dptbd.sim.campaign.cases import Case
from dptbd.sim.campaign.draw import make_stream_run
from dptbd.sim.coverage import bins
from dptbd.sim.stream_model import expected_stream, split_words


@pytest.mark.parametrize("seed", range(4))
def test_list_ends_follow_the_segmenters_control_flow(seed):
    """One list end per list of segment_stream, on hostile streams with every framing fault
    and run-time settings."""
    case = Case("t", dict(width=7, height=5, segment_frames=3, candidate_count=3), "segmenter",
                40, 1, ("misaligned_first", "short_frame", "long_frame", "settings"))
    cfg = case.cfg
    words, stim, _, events = make_stream_run(case, seed)
    assert {f for f, _ in events} == {"misaligned_first", "short_frame", "long_frame"}
    pixels, first = split_words(cfg, words)
    exp = expected_stream(cfg, pixels, first, None, {int(i): s for i, s in stim.settings_changes})
    lists = segment_stream(exp.fields, cfg, exp.settings)
    ends = bins.list_ends(cfg, exp.fields, exp.settings)
    assert len(ends) == len(lists) > 5
    assert all(a[0] < b[0] for a, b in zip(ends, ends[1:]))
    for j, (end, n) in enumerate(ends):            # list j is made by word `end`, not before
        assert len(segment_stream(exp.fields[:end], cfg, exp.settings[:end])) == j
        assert len(segment_stream(exp.fields[:end + 1], cfg, exp.settings[:end + 1])) == j + 1
        assert 0 <= n <= cfg.record_capacity
    assert {n for _, n in ends} > {cfg.n_candidates}                # n rewritten at run time
