"""DSP-style track association (paper 001 §3) on synthetic candidate lists.

Each test builds the candidate records a segment would hand to the DSP (row, col, E, d and
the backtracked path start), runs the tracker segment by segment and checks the tracks.
"""

import math

import numpy as np
import pytest

from dptbd.dsp import association, records as record_module
from dptbd.dsp.association import config as association_config
from dptbd.dsp.association import (
    CANDIDATE_DTYPE, CONFIRMED, FREE, ONE, TENTATIVE, AssociationConfig, AssociationError,
    Tracker)
from dptbd.scenes.targets import Target, Turn

K = 6  # frames per segment; stride K


def cand(row, col, energy=1000, row0=None, col0=None):
    """One candidate; its path start defaults to no motion."""
    return (row, col, energy, 4, row if row0 is None else row0, col if col0 is None else col0, 1)


def target_cand(start, vel, s, energy=2000):
    """A target moving at ``vel`` px/frame: its pixel at segment s's last frame and path start."""
    end = s * K + K - 1
    r, c = (round(start[0] + vel[0] * end), round(start[1] + vel[1] * end))
    r0, c0 = (round(start[0] + vel[0] * (end - K + 1)), round(start[1] + vel[1] * (end - K + 1)))
    return cand(r, c, energy, r0, c0)


def records(items):
    return np.array(items, dtype=CANDIDATE_DTYPE)


def clutter(rng, n, avoid=None, size=128):
    out = []
    while len(out) < n:
        r, c = (int(x) for x in rng.integers(0, size, 2))
        if avoid is not None and abs(r - avoid[0]) <= 8 and abs(c - avoid[1]) <= 8:
            continue
        out.append(cand(r, c, int(rng.integers(500, 1500)), int(rng.integers(max(r - 5, 0), r + 6)),
                        int(rng.integers(max(c - 5, 0), c + 6))))
    return out


def tracker(**kw):
    return Tracker(AssociationConfig(**kw), segment_frames=K, segment_stride=K, height=128,
                   width=128)


def test_straight_target_in_clutter_is_confirmed_at_the_output_threshold():
    rng = np.random.default_rng(1)
    start, vel = (20.0, 30.0), (0.8, 0.4)
    tr = tracker()
    for s in range(12):
        t = target_cand(start, vel, s)
        tr.step(records([t] + clutter(rng, 30, avoid=t[:2])))
    tracks = tr.confirmed_tracks()
    on_target = [t for t in tracks if t.first_segment == 0]
    assert len(on_target) == 1
    track = on_target[0]
    # 4 hits in 4 segments pass the output threshold (hits >= 4, ratio >= 0.6) at segment 3
    assert track.confirm_segment == 3
    assert track.hits == 12 and track.alive
    ends = np.arange(12) * K + K - 1
    np.testing.assert_array_equal(track.points["row"], np.round(start[0] + vel[0] * ends))
    np.testing.assert_array_equal(track.points["col"], np.round(start[1] + vel[1] * ends))
    # 30 clutter points per segment with random path starts do line up now and then (seed 1:
    # two short false tracks confirmed late); they must never take the target's points.
    false = [t for t in tracks if t.first_segment != 0]
    assert len(false) <= 2
    for t in false:
        assert not set(zip(t.points["seg"], t.points["row"], t.points["col"])) & set(
            zip(track.points["seg"], track.points["row"], track.points["col"]))


def test_velocity_and_prediction_are_fixed_point_integers():
    tr = tracker()
    for s in range(4):
        tr.step(records([cand(10 + 6 * s, 20 + 3 * s, row0=10 + 6 * s - 5, col0=20 + 3 * s - 2)]))
    rec = tr.tracks[tr.tracks["state"] != FREE][0]
    assert rec["v_row"] == 6 * ONE and rec["v_col"] == 3 * ONE   # Q4 pixels per segment
    assert rec["pred_row"] == (10 + 6 * 4) * ONE and rec["pred_col"] == (20 + 3 * 4) * ONE
    assert rec["state"] == CONFIRMED and rec["hits"] == 4 and rec["misses"] == 0


def test_missed_detections_are_coasted_through_with_a_wider_gate():
    start, vel = (40.0, 20.0), (0.5, 0.9)
    tr = tracker()
    gates = []
    for s in range(14):
        present = s not in (6, 9, 10)              # one miss, then two in a row
        tr.step(records([target_cand(start, vel, s)] if present else []))
        live = tr.tracks[tr.tracks["state"] != FREE]
        assert len(live) == 1                      # never a second track for the same target
        gates.append(int(live[0]["gate"]))
    track = tr.confirmed_tracks()[0]
    assert track.first_segment == 0 and track.hits == 11 and track.alive
    assert gates[9] > gates[8] and gates[10] > gates[9]   # the gate widens while coasting
    assert gates[11] < gates[10]                          # and shrinks back after a hit
    assert set(track.points["seg"].tolist()) == set(range(14)) - {6, 9, 10}


def test_too_many_misses_delete_a_confirmed_track_into_the_output():
    tr = tracker(max_misses=2)
    for s in range(5):
        tr.step(records([target_cand((10.0, 10.0), (1.0, 1.0), s)]))
    for _ in range(3):
        tr.step(records([]))
    assert tr.active() == 0
    (track,) = tr.confirmed_tracks()
    assert not track.alive and track.hits == 5 and track.last_segment == 4


@pytest.mark.parametrize("degrees", [30.0, 45.0])
def test_a_manoeuvring_target_keeps_its_track(degrees):
    """001 §3 (2): the prediction allows for manoeuvres. A turn at segment 6."""
    target = Target((20.0, 20.0), (0.0, 0.9), 1.0, turns=[Turn(6 * K, degrees=-degrees)])
    pos = target.positions(14 * K)
    tr = tracker()
    for s in range(14):
        end, first = s * K + K - 1, s * K
        r, c = np.rint(pos[end]).astype(int)
        r0, c0 = np.rint(pos[first]).astype(int)
        tr.step(records([cand(int(r), int(c), 2000, int(r0), int(c0))]))
    (track,) = tr.confirmed_tracks()
    assert track.hits == 14 and track.first_segment == 0   # one track, through the turn


def test_manoeuvre_rule_follows_the_newest_step():
    """Two steps differing by more than ``manoeuvre`` px: the velocity is the newest step."""
    tr = tracker(manoeuvre=3.0, gate_base=8.0, gate_max=12.0)
    pts = [(20, 20), (20, 25), (20, 30), (24, 33)]      # a turn: step (0, 5) then (4, 3)
    heads = [(0, 4), (0, 4), (0, 4), (3, 3)]           # path displacement over the segment
    for (r, c), (hr, hc) in zip(pts, heads):
        tr.step(records([cand(r, c, row0=r - hr, col0=c - hc)]))
    assert tr.active() == 1
    rec = tr.tracks[tr.tracks["state"] != FREE][0]
    assert (rec["v_row"], rec["v_col"]) == (4 * ONE, 3 * ONE)
    tr2 = tracker(manoeuvre=100.0, gate_base=8.0, gate_max=12.0)
    for (r, c), (hr, hc) in zip(pts, heads):
        tr2.step(records([cand(r, c, row0=r - hr, col0=c - hc)]))
    rec2 = tr2.tracks[tr2.tracks["state"] != FREE][0]
    assert (rec2["v_row"], rec2["v_col"]) == (2 * ONE, 4 * ONE)   # mean of (0, 5) and (4, 3)


def test_heading_agreement_picks_the_candidate_moving_like_the_track():
    """Two candidates equally far from the prediction: the one heading the same way wins;
    with ``reject_reversed`` one heading backwards is never taken (001 §2: targets do not
    retreat), by default it only costs more (001 §3 ranks by heading, it does not gate)."""
    tr = tracker()
    for s in range(3):
        tr.step(records([cand(30, 10 + 6 * s, row0=30, col0=10 + 6 * s - 5)]))
    # predicted (30, 28): candidates 2 px above and below it, one moving right, one left
    tr.step(records([cand(28, 28, row0=28, col0=33), cand(32, 28, row0=32, col0=23)]))
    rec = tr.tracks[tr.tracks["id"] == 1][0]
    assert rec["p_row"][1] == 32 * ONE
    for reject, hits in ((True, 3), (False, 4)):
        tr2 = tracker(reject_reversed=reject)
        for s in range(3):
            tr2.step(records([cand(30, 10 + 6 * s, row0=30, col0=10 + 6 * s - 5)]))
        tr2.step(records([cand(30, 28, row0=30, col0=33)]))   # on the prediction but reversed
        rec2 = tr2.tracks[tr2.tracks["id"] == 1][0]
        assert rec2["hits"] == hits and rec2["misses"] == (1 if reject else 0)


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


def test_duplicate_tracks_on_one_target_are_merged():
    tr = tracker(merge_radius=0)
    for s in range(6):
        r, c = 30 + 4 * s, 40 + 2 * s
        tr.step(records([cand(r, c, 1200, r - 3, c - 2), cand(r + 1, c + 1, 1100, r - 2, c - 1)]))
    assert tr.stats["duplicates"] >= 1
    assert len(tr.confirmed_tracks()) == 1


def test_a_lower_output_threshold_confirms_sooner():
    def confirm_segment(**kw):
        tr = tracker(**kw)
        for s in range(8):
            tr.step(records([target_cand((20.0, 20.0), (0.7, 0.7), s)] if s != 1 else []))
        return tr.confirmed_tracks()[0].confirm_segment
    assert confirm_segment(confirm_hits=3) < confirm_segment(confirm_hits=5)


def _overlapping_run(detected, **kw):
    """K = 8 frames every 4 (each frame in two consecutive lists): a target at 0.5 px/frame
    detected in the segments ``detected`` of 0 .. 9; the tracker and its track's
    ``counted`` after every segment."""
    tr = Tracker(AssociationConfig(**kw), segment_frames=8, segment_stride=4, height=128,
                 width=128)
    counted = []
    for s in range(10):
        end = 4 * s + 7
        r, c = 20 + end // 2, 30 + end // 2
        tr.step(records([cand(r, c, 2000, r - 3, c - 3)] if s in detected else []))
        counted.append(int(tr.tracks["counted"][0]))
    return tr, counted


def test_disjoint_confirmation_counts_only_hits_from_lists_that_share_no_frame():
    """confirm_disjoint: lists s and s' share no frame when (s - s') * S_t >= K, here every
    second segment: hits 0, 2, 4, 6 count and the fourth counted hit confirms (segment 6,
    not 3); a miss shifts the count (hits 0, 1, 3, 4, ...: 0, 3, 5, 7 count)."""
    off, counted_off = _overlapping_run(range(10))
    on, counted_on = _overlapping_run(range(10), confirm_disjoint=True)
    assert (off.confirm_gap, on.confirm_gap) == (1, 2)
    assert counted_off == [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]
    assert counted_on == [1, 1, 2, 2, 3, 3, 4, 4, 5, 5]
    assert [t.confirm_segment for t in off.confirmed_tracks()] == [3]
    assert [t.confirm_segment for t in on.confirmed_tracks()] == [6]
    assert on.tracks["hits"][0] == off.tracks["hits"][0] == 10
    assert on.tracks["count_seg"][0] == 8 and off.tracks["count_seg"][0] == 9
    missed, counted = _overlapping_run([0, 1, 3, 4, 5, 6, 7, 8, 9], confirm_disjoint=True)
    assert counted == [1, 1, 1, 2, 2, 3, 3, 4, 4, 5]
    assert [t.confirm_segment for t in missed.confirmed_tracks()] == [7]


def test_disjoint_confirmation_changes_nothing_for_back_to_back_segments():
    """S_t = K: consecutive lists never share a frame, so every hit counts (gap 1) and the
    records are bit for bit those without the setting."""
    runs = []
    for disjoint in (False, True):
        rng = np.random.default_rng(3)
        tr = tracker(confirm_disjoint=disjoint)
        for s in range(12):
            t = target_cand((20.0, 30.0), (0.8, 0.4), s)
            tr.step(records([t] + clutter(rng, 30, avoid=t[:2])))
        runs.append(tr)
    assert runs[1].confirm_gap == 1
    assert runs[0].tracks.tobytes() == runs[1].tracks.tobytes()
    assert np.array_equal(runs[0].tracks["counted"], runs[0].tracks["hits"])
    assert len(runs[1].confirmed_tracks()) >= 1


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


def test_capacity_overflow_drops_the_weakest_new_candidates_and_never_evicts():
    """All records in use: candidates left over start no track (counted), existing tracks stay."""
    tr = tracker(capacity=4)
    # segment 0: six isolated candidates, energies 100..600: the four strongest get records
    tr.step(records([cand(10 + 20 * i, 10, 100 * (i + 1)) for i in range(6)]))
    assert tr.active() == 4 and tr.stats["dropped_candidates"] == 2
    starts = sorted(int(r) // ONE for r in tr.tracks["p_row"][:, 1])
    assert starts == [50, 70, 90, 110]                 # rows of E = 300 … 600
    # a target confirmed in record 0 onwards keeps its record while clutter floods in
    tr2 = tracker(capacity=4)
    rng = np.random.default_rng(5)
    for s in range(10):
        t = target_cand((64.0, 10.0), (0.0, 1.0), s)
        tr2.step(records([t] + clutter(rng, 20, avoid=t[:2])))
        assert tr2.active() <= 4
    target_tracks = [t for t in tr2.confirmed_tracks() if t.first_segment == 0]
    assert len(target_tracks) == 1 and target_tracks[0].hits == 10 and target_tracks[0].alive
    assert tr2.stats["dropped_candidates"] > 0
    # records freed by deletions are reused: every segment starts some new tracks
    assert tr2.stats["started"] > 4


def _state_buffers(tr):
    arrays = (tr.tracks, tr.history, tr.archive, tr.archive_history, tr.inbuf, tr._keep,
              tr._claimed, tr._order, tr._head_row, tr._head_col, tr._class, tr._match,
              tr._order_tracks)
    return [(id(a), a.__array_interface__["data"][0], a.shape) for a in arrays]


def test_no_allocation_per_segment_and_input_capacity():
    """The state is allocated once: the same buffers, and no memory kept or grown per
    segment, through starts, confirmations, deletions and archiving in heavy clutter."""
    import tracemalloc

    tr = tracker(max_candidates=40, capacity=16, output_capacity=4)
    before = _state_buffers(tr)
    rng = np.random.default_rng(3)
    segs = [records([target_cand((20.0, 20.0), (0.8, 0.4), s)] + clutter(rng, 30))
            for s in range(40)]
    for c in segs[:5]:                                 # warm-up (numpy caches, ints)
        tr.step(c)
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        peaks = []
        for c in segs[5:]:
            tracemalloc.reset_peak()
            tr.step(c)
            peaks.append(tracemalloc.get_traced_memory()[1] - base)
        growth = tracemalloc.get_traced_memory()[0] - base
    finally:
        tracemalloc.stop()
    assert _state_buffers(tr) == before
    assert tr.stats["deleted"] > 0 and tr.stats["started"] > 16      # records were reused
    state_bytes = sum(a.nbytes for a in (tr.tracks, tr.history, tr.archive, tr.archive_history))
    # transient Python objects only (a few KiB), far below one copy of the state; no growth
    assert max(peaks) < min(16384, state_bytes // 2), (max(peaks), state_bytes)
    assert growth < 8192, growth                   # numpy's small caches; not per segment
    tr = tracker(max_candidates=8)
    with pytest.raises(AssociationError, match=(r"^9 candidates in one segment but the input "
                                                r"buffer holds max_candidates=8$")):
        tr.step(records([cand(i, i) for i in range(9)]))
    with pytest.raises(AssociationError, match=(r"^candidates must be CANDIDATE_DTYPE records "
                                                r"\(make_candidates\), got dtype \[\('row', "
                                                r"'<u2'\), \('col', '<u2'\)\]$")):
        tr.step(np.zeros(2, dtype=[("row", "u2"), ("col", "u2")]))


def test_history_ring_keeps_the_newest_points():
    tr = tracker(max_points=4)
    for s in range(7):
        tr.step(records([target_cand((10.0, 10.0), (1.0, 0.5), s)]))
    (track,) = tr.confirmed_tracks()
    assert track.hits == 7
    np.testing.assert_array_equal(track.points["seg"], [3, 4, 5, 6])
    assert tr.stats["history_wrapped"] == 3


def test_tentative_tracks_die_and_free_their_records():
    tr = tracker()
    tr.step(records([cand(10, 10), cand(100, 100)]))
    assert tr.active() == 2 and set(tr.tracks["state"][:2]) == {TENTATIVE}
    for _ in range(2):                                  # 1 hit in 3 segments < delete ratio 0.4
        tr.step(records([]))
    assert tr.active() == 0 and tr.confirmed_tracks() == []


def test_heading_from_direction_code_without_paths():
    """Without backtracked paths the heading is the move of d (one frame)."""
    tr = tracker()
    c = np.array([(10, 10, 100, 5, 10, 10, 0)], dtype=CANDIDATE_DTYPE)   # d = 5: (0, +1)
    tr.step(c)
    rec = tr.tracks[0]
    assert (rec["v_row"], rec["v_col"]) == (0, K * ONE)
    assert rec["pred_col"] == (10 + K) * ONE and math.isclose(rec["gate"] / ONE, 3.0)


def test_work_per_segment_is_bounded():
    """Worst case: every record in use and every candidate inside every gate. Cost
    evaluations stay <= C x n per segment (each track is in one class), independent of
    how long the tracks are; the other loops are over C and n only (module docstring)."""
    cap, n = 12, 20
    tr = tracker(capacity=cap, max_candidates=n, merge_radius=0, duplicate_radius=0,
                 seed_gate=200.0, gate_base=200.0, gate_max=200.0, delete_ratio=0.0,
                 predict_ratio=0.0, confirm_ratio=0.0, max_misses=255)
    calls = []
    orig = tr._cost

    def counting(i, j):
        calls[-1] += 1
        return orig(i, j)

    tr._cost = counting
    rng = np.random.default_rng(11)
    for s in range(30):
        calls.append(0)
        tr.step(records([cand(int(r), int(c), int(e)) for r, c, e in
                         zip(rng.integers(40, 80, n), rng.integers(40, 80, n),
                             rng.integers(500, 1500, n))]))
        assert tr.active() <= cap
    assert tr.active() == cap
    assert max(calls) <= cap * n
    # with every record in use, the bound is reached (n >= C: no track is left without a
    # candidate before the last one is scored) but the work does not grow with time
    assert calls[-1] >= cap * n - cap * (cap - 1) // 2
    assert calls[-1] == calls[-10]


def test_link_gate_follows_a_turn_the_prediction_missed():
    """Off by default; with ``link_gate`` a candidate outside the prediction gate whose DP
    path starts at the track's newest point (the target turned) extends the track."""
    def run(**kw):
        tr = tracker(**kw)
        for s in range(4):
            tr.step(records([cand(30, 10 + 6 * s, row0=30, col0=10 + 6 * s - 5)]))
        # predicted (30, 34); the target turned down: path from (30, 28) to (36, 31)
        tr.step(records([cand(36, 31, row0=30, col0=28)]))
        return tr.tracks[tr.tracks["id"] == 1][0]

    assert run()["misses"] == 1
    rec = run(link_gate=2.0)
    assert rec["misses"] == 0 and rec["hits"] == 5 and rec["p_row"][1] == 36 * ONE


def test_records_and_configuration_are_re_exported():
    for name in association.__all__:
        assert hasattr(association, name), name
    for module in (record_module, association_config):
        for name in module.__all__:
            assert getattr(association, name) is getattr(module, name), name
