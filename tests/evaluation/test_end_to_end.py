"""``dptbd.evaluation.end_to_end``: the chain over seeds, its outcome per run and summary."""

from __future__ import annotations

import math

import pytest

from dptbd.evaluation import end_to_end as e2e
from dptbd.evaluation.run.scenario import ScenarioError, TargetSpec, default_scenario
from dptbd.scenes import chain as chain_scenes
from helpers.refusals import whole


def _tiny():
    """48 x 48, 36 frames (6 lists of K = 6), two targets at SNR 2, 11 candidates per list."""
    return e2e.scenario("paper001-experiment-2").replace(
        name="tiny", height=48, width=48, frames=36, snr=2.0, false_alarm_rate=0.005,
        targets=(TargetSpec((10.0, 10.0), (0.5, 0.7)), TargetSpec((40.0, 8.0), (-0.4, 0.8))))


def test_the_chain_on_two_seeds_of_a_small_scene_gives_its_exact_outcome():
    summary = e2e.run_chain(_tiny(), "0-1")
    assert summary.runs == (e2e.RunOutcome(0, (36, None), 0, 6), e2e.RunOutcome(1, (30, 36), 0, 6))
    assert [r.clean for r in summary.runs] == [False, True]
    assert (summary.clean, summary.all_confirmed, summary.false_tracks) == (1, 1, 0)
    assert summary.frames_until_output == [36, 30, 36]
    assert summary.median == 36.0
    assert summary.median_interval == (30.0, 36.0)      # below 6 values: the whole range
    assert summary.lines() == [
        "scenario tiny, seeds 0-1, ideal lists",
        "clean runs (all targets confirmed, no false track): 1/2 [0.09, 0.91]",
        "all targets confirmed: 1/2 [0.09, 0.91]",
        "runs with a false track: 0/2 [0.00, 0.66]; false tracks 0 (0.00 per run)",
        "frames until output: median 36 [30, 36] over 3 confirmed target(s)",
        "target 1: confirmed 2/2 [0.34, 1.00], median frames until output 33",
        "target 2: confirmed 1/2 [0.09, 0.91], median frames until output 36"]
    assert summary.per_target() == [[36, 30], [36]]


def test_a_variant_is_another_chain_on_the_same_scenes():
    sc = e2e.variant(_tiny(), dp={"segment_frames": 8}, association={"confirm_hits": 3})
    assert sc.dp["segment_frames"] == 8 and sc.association == {"confirm_hits": 3}
    assert sc.replace(dp=_tiny().dp, association={}) == _tiny()
    summary = e2e.run_chain(sc, "0-1")
    # 4 lists of K = 8 in 36 frames; confirmed after 3 hits: 24 frames, a false track on seed 1
    assert summary.runs == (e2e.RunOutcome(0, (24, None), 0, 4), e2e.RunOutcome(1, (24, 24), 1, 4))


def test_a_variant_with_another_false_alarm_rate_has_other_list_lengths():
    # 48 x 48 pixels: 0.005 keeps n = 12 candidates per list, 0.002 n = 5: fewer confirmations
    sc = e2e.variant(_tiny(), false_alarm_rate=0.002)
    assert sc == _tiny().replace(false_alarm_rate=0.002)
    assert e2e.run_chain(sc, "0-1").runs == (e2e.RunOutcome(0, (None, None), 0, 6),
                                             e2e.RunOutcome(1, (30, None), 0, 6))
    assert e2e.variant(_tiny()).false_alarm_rate == 0.005


@pytest.mark.parametrize("kwargs, message", [
    ({"dp": {"segment_frames": 0}},
     "scenario 'tiny': segment_frames must be an integer in [1, 65535], got 0"),
    ({"association": {"nokey": 1}},
     "scenario 'tiny': unknown association parameter(s) ['nokey']; allowed: ['capacity', "
     "'max_candidates', 'max_points', 'output_capacity', 'max_speed', 'merge_radius', "
     "'duplicate_radius', 'seed_gate', 'gate_base', 'gate_growth', 'gate_growth_segments', "
     "'gate_miss', 'gate_max', 'manoeuvre', 'link_gate', 'heading_weight', 'reject_reversed', "
     "'heading_min', 'confirm_hits', 'confirm_ratio', 'predict_hits', 'predict_ratio', "
     "'delete_ratio', 'max_misses']"),
    ({"false_alarm_rate": 0.0},
     "[segmentation] false_alarm_rate must be in (0, 1], got 0.0"),
    ({"false_alarm_rate": 1.5},
     "[segmentation] false_alarm_rate must be in (0, 1], got 1.5"),
])
def test_a_bad_variant_is_refused_naming_the_key(kwargs, message):
    with pytest.raises(ScenarioError, match=whole(message)):
        e2e.variant(_tiny(), **kwargs)


def test_a_false_alarm_rate_that_keeps_no_candidate_is_refused():
    # 48 x 48 = 2304 pixels: round(rate x 2304) >= 1 needs rate >= 0.5 / 2304
    msg = ("false_alarm_rate 0.0002 keeps no candidate point of 2304 pixels; allowed: at least "
           "0.000217014 (n = 1)")
    with pytest.raises(e2e.ChainError, match=whole(msg)):
        e2e.variant(_tiny(), false_alarm_rate=0.0002)
    assert e2e.variant(_tiny(), false_alarm_rate=0.5 / 2304).false_alarm_rate == 0.5 / 2304


def test_a_false_track_makes_a_run_unclean():
    run = e2e.run_outcome(_tiny(), 11)
    assert run == e2e.RunOutcome(11, (None, None), 1, 6)
    assert not run.clean and not run.all_confirmed


def test_no_confirmed_target_has_no_median():
    summary = e2e.ChainSummary("x", "ideal", range(7, 8), (e2e.RunOutcome(7, (None,), 0, 6),))
    assert math.isnan(summary.median) and all(map(math.isnan, summary.median_interval))


def test_the_named_scenarios():
    assert e2e.scenario("paper001-experiment-2") == default_scenario()
    for name, targets in [("manoeuvring", chain_scenes.manoeuvring_targets()),
                          ("crossing", chain_scenes.crossing_targets())]:
        sc = e2e.scenario(name)
        assert sc.name == name
        assert sc.replace(targets=()) == default_scenario().replace(name=name, targets=())
        built = [t.target(sc.snr, sc.sigma) for t in sc.targets]
        assert built == targets
        sc.check()


@pytest.mark.parametrize("text, seeds", [("0-39", range(0, 40)), ("100-199", range(100, 200)),
                                         ("5", range(5, 6)), ("7-7", range(7, 8))])
def test_seed_ranges(text, seeds):
    assert e2e.parse_seeds(text) == seeds


@pytest.mark.parametrize("call, message", [
    (lambda: e2e.scenario("straight"),
     "unknown scenario 'straight'; allowed: paper001-experiment-2, manoeuvring, crossing"),
    (lambda: e2e.run_chain("crossng", "0-1"),
     "unknown scenario 'crossng'; allowed: paper001-experiment-2, manoeuvring, crossing"),
    (lambda: e2e.parse_seeds("0..39"), "seeds must be A-B (integers 0 <= A <= B) or A, got '0..39'"),
    (lambda: e2e.parse_seeds("-3-4"), "seeds must be A-B (integers 0 <= A <= B) or A, got '-3-4'"),
    (lambda: e2e.parse_seeds("39-0"), "seeds A-B need A <= B, got '39-0'"),
    (lambda: e2e.parse_seeds("0-100000"),
     "seeds A-B may hold at most 100000 seeds, got '0-100000' (100001)"),
    (lambda: e2e.run_chain("crossing", range(3, 3)),
     "seeds must be a non-empty range of integers >= 0 in steps of 1, got range(3, 3)"),
    (lambda: e2e.run_chain("crossing", range(0, 9, 2)),
     "seeds must be a non-empty range of integers >= 0 in steps of 1, got range(0, 9, 2)"),
    (lambda: e2e.run_chain("crossing", "0-1", lists="best"),
     "lists must be one of 'gateware', 'ideal', got 'best'"),
])
def test_refusals(call, message):
    with pytest.raises(e2e.ChainError, match=whole(message)):
        call()
