"""The track records of the tracker (``dptbd.dsp.association.tracks``): velocity and prediction,
coasting, thresholds, duplicates, disjoint confirmation, capacity, history, deletion."""

import numpy as np

from dptbd.dsp.association import CONFIRMED, FREE, ONE, TENTATIVE, AssociationConfig, Tracker
from helpers.candidate_lists import cand, clutter, records, target_cand, tracker


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
