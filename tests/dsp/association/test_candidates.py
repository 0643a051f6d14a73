"""The candidate steps of the tracker (``dptbd.dsp.association.candidates``): headings,
cluster suppression, wake suppression."""

import math

import numpy as np
import pytest

from dptbd.dsp.association import CANDIDATE_DTYPE, ONE
from helpers.candidate_lists import K, cand, records, tracker


def test_a_cluster_of_candidates_gives_one_track():
    """DP energy spreads around a target (001 §2, 团聚效应): the 3x3 clump is one point."""
    tr = tracker()
    for s in range(6):
        r, c = 30 + 4 * s, 40 + 2 * s
        clump = [cand(r + dr, c + dc, 1000 + (200 if (dr, dc) == (0, 0) else 0), r - 3, c - 2)
                 for dr in (-1, 0, 1) for dc in (-1, 0, 1)]
        tr.step(records(clump))
    assert tr.active() == 1
    (track,) = tr.confirmed_tracks()
    assert track.hits == 6
    np.testing.assert_array_equal(track.points["row"], 30 + 4 * np.arange(6))
    assert tr.stats["suppressed"] == 6 * 8


def _wake_run(wake=None, **kw):
    """A target at 1 px/frame along a row (6 px a segment, its path starting 5 px back) and
    from segment 4 on ``wake(s)``: weaker candidates behind it; the tracker after 12
    segments."""
    tr = tracker(**kw)
    for s in range(12):
        col = 10 + 6 * s
        items = [cand(40, col, 3000, 40, col - 5)]
        if s >= 4 and wake is not None:
            items += wake(s, col)
        tr.step(records(items))
    return tr


def test_wake_suppression_keeps_the_recent_path_of_a_track_from_starting_tracks():
    """A candidate 4 px behind the target every segment (2 px ahead of the track's previous
    point, 1 px from its newest point's path start): without wake suppression it starts a
    track that follows the target and is confirmed (a false track); with ``wake_radius =
    2`` it starts none. A candidate far from every track still starts one."""
    def behind(s, col):
        return [cand(40, col - 4, 1500, 40, col - 9)]

    off = _wake_run(behind)
    assert len(off.confirmed_tracks()) == 2 and off.stats["wake_suppressed"] == 0
    on = _wake_run(behind, wake_radius=2)
    assert [t.first_segment for t in on.confirmed_tracks()] == [0]
    assert on.stats["wake_suppressed"] == 8
    far = _wake_run(lambda s, col: [cand(90, col, 1500, 90, col - 5)], wake_radius=2)
    assert far.stats["wake_suppressed"] == 0
    assert [t.first_segment for t in far.confirmed_tracks()] == [0, 4]


@pytest.mark.parametrize("points, path, suppressed", [(1, 1, 8), (1, 0, 0), (2, 0, 8)])
def test_wake_suppression_reaches_the_newest_points_and_their_path_starts(points, path,
                                                                           suppressed):
    """A candidate 7 px behind the target (the track's newest point, extended in this
    segment): 2 px from that point's path start (5 px back), 1 px from the point before
    (6 px back). It is on the recent path with ``wake_points = 2``, or with 1 when the
    path is known."""
    def behind(s, col):
        return [cand(40, col - 7, 1500, 40, col - 12)]

    tr = tracker(wake_radius=2, wake_points=points)
    for s in range(12):                  # d = 5: the move (0, +1), the heading without a path
        col = 10 + 6 * s
        tr.step(records([(40, col, 3000, 5, 40, col - 5, path)]
                        + (behind(s, col) if s >= 4 else [])))
    assert tr.stats["wake_suppressed"] == suppressed


def test_heading_from_direction_code_without_paths():
    """Without backtracked paths the heading is the move of d (one frame)."""
    tr = tracker()
    c = np.array([(10, 10, 100, 5, 10, 10, 0)], dtype=CANDIDATE_DTYPE)   # d = 5: (0, +1)
    tr.step(c)
    rec = tr.tracks[0]
    assert (rec["v_row"], rec["v_col"]) == (0, K * ONE)
    assert rec["pred_col"] == (10 + K) * ONE and math.isclose(rec["gate"] / ONE, 3.0)
