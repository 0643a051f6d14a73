"""``dptbd.evaluation.family.wake``: past positions kept among a map's n largest."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.errors import DptbdError
from dptbd.evaluation.family import detection as fd
from dptbd.evaluation.family import wake
from helpers.refusals import whole


def test_scene_counts_on_a_constructed_map():
    # a target at row 10 moving 2 columns per frame; one map, of frame 5 (target at (10, 20))
    pixel = np.array([[10, 10 + 2 * t] for t in range(8)])
    visible = np.ones(8, dtype=bool)
    mask = np.zeros((1, 64, 64), dtype=bool)
    mask[0, 10, 16] = True   # the frame-3 position: lag 2
    mask[0, 50, 50] = True   # far from the track
    mask[0, 10, 21] = True   # within the gate of the current position: not a false point
    c = wake._scene_counts(mask, np.array([5]), pixel, visible, (1, 2, 4, 6), near=3, history=40)
    # lag 6 reaches before frame 0: no opportunity
    assert c.hits == (0, 1, 0, 0) and c.opportunities == (1, 1, 1, 0)
    assert (c.false_points, c.near_track, c.maps) == (2, 1, 1)
    assert c.kept(1, 4) == (1, 3)


def test_past_positions_inside_the_gate_or_invisible_are_no_opportunity():
    pixel = np.array([[10, 10 + t] for t in range(6)])   # 1 px per frame: lag 1 is in the gate
    visible = np.array([True, False, True, True, True, True])
    mask = np.zeros((1, 32, 32), dtype=bool)
    c = wake._scene_counts(mask, np.array([5]), pixel, visible, (1, 2, 4), near=3, history=40)
    assert c.opportunities == (0, 1, 0) and c.hits == (0, 0, 0)   # frame 1 is not visible


def test_false_points_are_those_of_first_level_counts():
    variant = fd.recursive(0.9, warmup=7)
    per = wake.wake_counts(variant, 2.3, (1.0, 1.0), lags=(2, 10), trials=2, seed=5, size=32)
    ref = fd.variant_trial_counts(variant, 2.3, (1.0, 1.0), trials=2, seed=5, size=32)
    assert [w.false_points for w in per] == [c.false_points for c in ref]
    assert [w.maps for w in per] == [c.frames for c in ref] == [93, 93]
    total = per[0] + per[1]
    assert total.hits == tuple(a + b for a, b in zip(per[0].hits, per[1].hits))
    assert all(0 <= h <= o for h, o in zip(total.hits, total.opportunities))
    assert 0 <= total.near_track <= total.false_points


def test_parse_lags():
    assert wake.parse_lags("1-4") == (1, 2, 3, 4)
    assert wake.parse_lags("2, 10,13-15") == (2, 10, 13, 14, 15)


@pytest.mark.parametrize("call, message", [
    (lambda: wake.parse_lags("1-x"), "lags must be comma-separated integers or FIRST-LAST ranges, got '1-x'"),
    (lambda: wake.parse_lags("1-2-3"), "lags must be comma-separated integers or FIRST-LAST ranges, got '1-2-3'"),
    (lambda: wake.parse_lags("0-3"), "lags[0] must be an integer in [1, 99], got 0"),
    (lambda: wake.parse_lags("5,3"), "lags must be distinct and ascending, got [5, 3]"),
    (lambda: wake.parse_lags("2,2"), "lags must be distinct and ascending, got [2, 2]"),
    (lambda: wake.check_lags([]), "lags must hold at least one lag in [1, 99]"),
    (lambda: wake.wake_counts(fd.segments(6), 2.3, (1.0, 1.0), lags=(2,), trials=1, seed=0, near=11),
     "near must be an integer in [0, 10], got 11"),
    (lambda: wake.wake_counts(fd.segments(6), 2.3, (1.0, 1.0), lags=(2,), trials=1, seed=0, history=0),
     "history must be an integer in [1, 99], got 0"),
    (lambda: wake.WakeCounts((1,), (0,), (0,), 0, 0, 0) + wake.WakeCounts((2,), (0,), (0,), 0, 0, 0),
     "wake counts of lags (1,) and (2,) cannot be added"),
])
def test_refusals(call, message):
    with pytest.raises(DptbdError, match=whole(message)):
        call()
