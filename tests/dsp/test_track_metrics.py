"""Track metrics against ground truth (``dptbd/dsp/track_metrics.py``) on hand-built tracks.

Every expected value below is worked out by hand from the definitions in the module
docstring, with K = 4 back to back: segment s ends at frame 4 s + 3.
"""

import math

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.dsp.association import POINT_DTYPE, ConfirmedTrack
from dptbd.scenes.synthetic import TargetTruth
from dptbd.dsp.track_metrics import evaluate_tracks

CFG = DPConfig(width=64, height=64, segment_frames=4)
N_SEG = 6                                   # frames 0 … 23


def truth(position, visible=None):
    position = np.asarray(position, dtype=float)
    vis = np.ones(len(position), bool) if visible is None else np.asarray(visible, bool)
    return TargetTruth(position=position, pixel=np.rint(position).astype(np.int64),
                       alive=vis.copy(), visible=vis, amplitude=1.0)


def track(tid, confirm, points):
    """points: (segment, row, col) of each measured point, oldest first."""
    pts = np.zeros(len(points), POINT_DTYPE)
    for i, (s, r, c) in enumerate(points):
        pts[i]["seg"], pts[i]["row"], pts[i]["col"] = s, r, c
    return ConfirmedTrack(id=tid, first_segment=points[0][0], confirm_segment=confirm,
                          last_segment=points[-1][0], hits=len(points),
                          length=points[-1][0] - points[0][0] + 1, alive=True, points=pts)


def positions_for(tr, first_frame, last_frame):
    """A position per frame; measured (backtracked) only at each point's segment end."""
    frames = np.arange(first_frame, last_frame + 1)
    pos = np.full((len(frames), 2), -100.0)          # unmeasured frames: never compared
    measured = np.zeros(len(frames), bool)
    for p in tr.points:
        f = int(p["seg"]) * 4 + 3
        pos[f - first_frame] = (p["row"], p["col"])
        measured[f - first_frame] = True
    return frames, pos, measured


@pytest.fixture
def scene():
    t = np.arange(24)
    # target 0: (10 + t, 5), appears at frame 5 (segment 1 is the first to end after it)
    t0 = truth(np.stack([10.0 + t, np.full(24, 5.0)], axis=1), visible=t >= 5)
    # target 1: still at (25.3, 20.4), pixel (25, 20), visible from frame 0
    t1 = truth(np.tile([25.3, 20.4], (24, 1)))
    # target 2: never near any track
    t2 = truth(np.tile([50.0, 50.0], (24, 1)))
    # track 7 (target 0): segments 1-3 = frames 7, 11, 15, true pixels (17, 5), (21, 5), (25, 5)
    a = track(7, 3, [(1, 17, 5), (2, 22, 6), (3, 25, 9)])      # near, near (1, 1), far (col 4)
    # track 9 (target 0): segments 4, 5 = frames 19, 23, true (29, 5), (33, 5)
    b = track(9, 4, [(4, 29, 5), (5, 33, 8)])                  # near, far (col 3): 1/2
    # track 11: nowhere near a target: false
    c = track(11, 3, [(2, 0, 0), (3, 0, 1)])
    # track 12 (target 1): segments 0-2 = frames 3, 7, 11
    d = track(12, 2, [(0, 25, 20), (1, 26, 21), (2, 25, 23)])  # near, near, far (col 3)
    tracks = [a, b, c, d]
    positions = {7: positions_for(a, 4, 15), 9: positions_for(b, 16, 23),
                 11: positions_for(c, 8, 15), 12: positions_for(d, 0, 11)}
    return tracks, positions, (t0, t1, t2)


def test_ownership_and_false_tracks(scene):
    tracks, positions, tt = scene
    ev = evaluate_tracks(tracks, positions, tt, CFG, N_SEG)
    assert ev.track_target == {7: 0, 9: 0, 11: -1, 12: 1}
    assert ev.confirmed_tracks == 4 and ev.false_tracks == 1
    assert [r.track_ids for r in ev.targets] == [(7, 9), (12,), ()]


def test_frames_and_segments_until_confirmation(scene):
    tracks, positions, tt = scene
    t0, t1, t2 = evaluate_tracks(tracks, positions, tt, CFG, N_SEG).targets
    # target 0 appears at frame 5: first segment ending after it is 1 (frames 4-7); its
    # first track (7) is confirmed in segment 3, which ends at frame 15
    assert t0.confirm_segment == 3
    assert t0.segments_until_confirmation == 3 - 1 + 1
    assert t0.frames_until_output == 15 - 5 + 1
    # target 1 is there from frame 0 (segment 0); track 12 confirmed in segment 2 (frame 11)
    assert (t1.confirm_segment, t1.segments_until_confirmation, t1.frames_until_output) \
        == (2, 3, 12)
    # target 2: no track
    assert (t2.confirm_segment, t2.segments_until_confirmation, t2.frames_until_output) \
        == (None, None, None)
    assert t2.track_frames == 0 and math.isnan(t2.rms_error) and t2.measured_frames == 0


def test_confirmed_length(scene):
    tracks, positions, tt = scene
    t0, t1, _ = evaluate_tracks(tracks, positions, tt, CFG, N_SEG).targets
    # tracks 7 (frames 4-15) and 9 (16-23) together cover frames 4-23; after output
    # (frame 15): 16-23
    assert t0.track_frames == 20 and t0.track_frames_after_output == 8
    # track 12 covers frames 0-11 and was confirmed at frame 11: nothing after output
    assert t1.track_frames == 12 and t1.track_frames_after_output == 0


def test_position_error_rms_and_max(scene):
    tracks, positions, tt = scene
    t0, t1, _ = evaluate_tracks(tracks, positions, tt, CFG, N_SEG).targets
    # target 0, measured points against the true positions: track 7: 0, sqrt(1 + 1), 4;
    # track 9: 0, 3  ->  RMS sqrt((0 + 2 + 16 + 0 + 9) / 5), max 4
    assert t0.measured_frames == 5
    assert t0.rms_error == pytest.approx(math.sqrt(27 / 5))
    assert t0.max_error == pytest.approx(4.0)
    # target 1 at (25.3, 20.4): errors sqrt(.09 + .16), sqrt(.49 + .36), sqrt(.09 + 6.76)
    assert t1.measured_frames == 3
    assert t1.rms_error == pytest.approx(math.sqrt((0.25 + 0.85 + 6.85) / 3))
    assert t1.max_error == pytest.approx(math.sqrt(6.85))


def test_min_fraction_and_radius_decide_ownership(scene):
    tracks, positions, tt = scene
    # tracks 7 and 12 have 2/3 of their points near, track 9 1/2: none reaches 0.7
    ev = evaluate_tracks(tracks, positions, tt, CFG, N_SEG, min_fraction=0.7)
    assert ev.false_tracks == 4 and all(r.track_ids == () for r in ev.targets)
    # radius 3 takes in the far points at column distance 3 (tracks 9 and 12), not 4 (7)
    ev = evaluate_tracks(tracks, positions, tt, CFG, N_SEG, radius=3, min_fraction=0.9)
    assert ev.track_target == {7: -1, 9: 0, 11: -1, 12: 1}
    # with 7 false, target 0's first track is 9, confirmed in segment 4 (frame 19)
    t0 = ev.targets[0]
    assert (t0.segments_until_confirmation, t0.frames_until_output) == (4, 19 - 5 + 1)
    assert t0.track_frames == 8 and t0.track_frames_after_output == 4


def test_track_near_two_targets_goes_to_the_larger_fraction_then_the_lower_index():
    t0 = truth(np.tile([10.0, 10.0], (24, 1)))
    t1 = truth(np.tile([10.0, 30.0], (24, 1)))
    half = track(1, 1, [(0, 10, 10), (1, 10, 30)])                 # 1/2 and 1/2
    more = track(2, 2, [(0, 10, 11), (1, 10, 29), (2, 11, 30)])    # 1/3 and 2/3
    positions = {1: positions_for(half, 0, 7), 2: positions_for(more, 0, 11)}
    ev = evaluate_tracks([half, more], positions, (t0, t1), CFG, N_SEG)
    assert ev.track_target == {1: 0, 2: 1} and ev.false_tracks == 0


def test_invisible_target_frames_never_count_as_near():
    # the track sits on the target's path, but the target is only visible from frame 12 on
    t = np.arange(24)
    t0 = truth(np.tile([10.0, 10.0], (24, 1)), visible=t >= 12)
    tr = track(1, 2, [(0, 10, 10), (1, 10, 10), (2, 10, 10)])     # frames 3, 7, 11
    ev = evaluate_tracks([tr], {1: positions_for(tr, 0, 11)}, (t0,), CFG, N_SEG)
    assert ev.track_target == {1: -1} and ev.false_tracks == 1
