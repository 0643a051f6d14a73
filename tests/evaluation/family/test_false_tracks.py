"""``dptbd.evaluation.family.false_tracks``: what makes the false tracks, and descent."""

from __future__ import annotations

import types

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.dsp.association import POINT_DTYPE
from dptbd.errors import DptbdError
from dptbd.evaluation.family import detection as fd
from dptbd.evaluation.family import false_tracks as ft
from helpers.refusals import whole


def _truth(n_t=60):
    """One target at row 20 moving one column per frame from column 10, always visible."""
    return [types.SimpleNamespace(pixel=np.array([[20, 10 + t] for t in range(n_t)]),
                                  visible=np.ones(n_t, dtype=bool))]


def test_classify_points():
    truth = _truth()
    rows = np.array([21, 20, 23, 24, 60])
    cols = np.array([42, 35, 30, 30, 60])
    frames = np.array([30, 30, 30, 30, 30])     # the target is at (20, 40) in frame 30
    # (21, 42): on target (Chebyshev 2); (20, 35): the frame-25 position (wake);
    # (23, 30): 3 from the frame-20 position (wake); (24, 30): 4 away (elsewhere); far away
    np.testing.assert_array_equal(ft.classify_points(rows, cols, frames, truth), [0, 1, 1, 2, 2])
    # the history bounds the wake: frame 20 is more than 5 frames back
    np.testing.assert_array_equal(
        ft.classify_points(rows, cols, frames, truth, history=5), [0, 1, 2, 2, 2])
    # an invisible target makes nothing on target
    truth[0].visible[30] = False
    assert ft.classify_points(rows[:1], cols[:1], frames[:1], truth)[0] == 1


def _run(points_of_tracks, owners):
    tracks = []
    for i, pts in enumerate(points_of_tracks):
        p = np.zeros(len(pts), dtype=POINT_DTYPE)
        for j, (seg, r, c, r0, c0) in enumerate(pts):
            p[j]["seg"], p[j]["row"], p[j]["col"], p[j]["row0"], p[j]["col0"] = seg, r, c, r0, c0
        tracks.append(types.SimpleNamespace(id=i + 1, points=p))
    result = types.SimpleNamespace(tracks=tracks, cfg=DPConfig(width=64, height=64),
                                   segments=types.SimpleNamespace(end_frames=5 + 6 * np.arange(10)))
    return types.SimpleNamespace(result=result, truth=_truth(),
                                 evaluation=types.SimpleNamespace(track_target=dict(owners)))


def test_false_tracks_kinds_chains_and_steps():
    run = _run([
        # far from the target; lists 1, 2, 3, 5: pairs (1,2) and (2,3); (2,3) chained
        [(1, 50, 50, 0, 0), (2, 50, 53, 40, 40), (3, 50, 56, 50, 54), (5, 50, 62, 0, 0)],
        # a track of the target: not a false track
        [(1, 20, 21, 20, 16), (2, 20, 27, 20, 22)],
        # list 3 ends at frame 23 (target at (20, 33)): two wake points, one on target
        [(3, 21, 30, 21, 25), (4, 20, 31, 20, 30), (5, 20, 45, 20, 40)],
    ], {1: -1, 2: 0, 3: -1})
    out = ft.false_tracks(run)
    assert [t.track_id for t in out] == [1, 3]
    a, b = out
    assert (a.points, a.kind, a.pairs, a.chained, a.step) == ((0, 0, 4), "elsewhere", 2, 1, 3.0)
    # track 3: (21, 30) at frame 23 is 3 behind the target: wake; (20, 31) at frame 29 (target
    # at 39): wake; (20, 45) at frame 35 (target at 45): on target; pairs (3,4) chained, (4,5) not
    assert (b.points, b.kind, b.pairs, b.chained) == ((1, 2, 0), "wake", 2, 1)


def test_a_tie_goes_to_the_class_nearer_the_target():
    run = _run([[(3, 20, 33, 0, 0), (4, 60, 60, 0, 0)]], {1: -1})
    assert ft.false_tracks(run)[0].kind == "on target"


def _recursive_cfg(size=16):
    return DPConfig(width=size, height=size, recursive=True, forgetting=0.75, energy_bits=16)


def test_descent_of_a_bright_pixel_through_the_recursion():
    rng = np.random.default_rng(1)
    frames = rng.integers(0, 4, (4, 16, 16))
    frames[2, 8, 8] = 255
    cfg = _recursive_cfg()
    d = ft.descent_counts(frames, cfg, 1, lags=(1,), first=2)
    # the one pair (2, 3): frame 3's largest pixel is a neighbour of (8, 8), which it came from
    assert (d.lags, d.descended, d.candidates, d.pairs) == ((1,), (1,), (1,), (1,))
    assert d.coverage == (9 / 256,)
    assert d.background == (9 / 256,)   # lag 1: every pixel's path is the pixel itself
    total = d + d
    assert (total.descended, total.candidates, total.pairs) == ((2,), (2,), (2,))
    with pytest.raises(DptbdError, match=whole("descent counts of lags (1,) and (2,) cannot be added")):
        d + ft.descent_counts(frames, cfg, 1, lags=(2,), first=1)


@pytest.mark.parametrize("start, descended", [((8, 9), 1), ((12, 12), 0)])
def test_descent_between_segments(start, descended):
    rng = np.random.default_rng(2)
    frames = rng.integers(0, 4, (12, 16, 16))
    frames[5, 8, 8] = 255          # segment 0's strongest pixel (its last frame)
    for i in range(6):             # segment 1's strongest path starts at `start`
        frames[6 + i, start[0], min(start[1] + i, 15)] = 255
    cfg = DPConfig(width=16, height=16, segment_frames=6)
    d = ft.descent_counts(frames, cfg, 1, lags=(6,))
    assert (d.descended, d.candidates, d.pairs) == ((descended,), (1,), (1,))
    assert d.coverage == (9 / 256,)


@pytest.mark.parametrize("call, message", [
    (lambda: ft.check_descent_lags([]), "lags must hold at least one lag in [1, 99]"),
    (lambda: ft.check_descent_lags([3, 2]), "lags must be distinct and ascending, got [3, 2]"),
    (lambda: ft.check_descent_lags([0]), "lags[0] must be an integer in [1, 99], got 0"),
    (lambda: ft.check_descent_lags([12], 12), "lags[0] must be an integer in [1, 11], got 12"),
    (lambda: ft.descent_counts(np.zeros((12, 16, 16), dtype=np.int64),
                               DPConfig(width=16, height=16, segment_frames=6), 1, lags=(1, 6)),
     "segments of K = 6 (stride K) have paths of K frames: lags must be [6], got [1, 6]"),
    (lambda: ft.recursive_config(fd.segments(6), DPConfig(width=16, height=16)),
     "recursive_config needs a recursive variant, got 'segments K=6'"),
])
def test_refusals(call, message):
    with pytest.raises(DptbdError, match=whole(message)):
        call()


def test_rate_ratio():
    from dptbd.evaluation.stats import wilson_interval
    r, lo, hi = ft.rate_ratio(29, 16)
    p_lo, p_hi = wilson_interval(29, 45)
    assert r == 29 / 16
    assert (lo, hi) == pytest.approx((p_lo / (1 - p_lo), p_hi / (1 - p_hi)))
    assert lo < r < hi
    assert ft.rate_ratio(3, 0)[0] == float("inf") and ft.rate_ratio(0, 3)[:2] == (0.0, 0.0)
    with pytest.raises(DptbdError, match=whole("rate_ratio needs at least one event, got a = b = 0")):
        ft.rate_ratio(0, 0)
