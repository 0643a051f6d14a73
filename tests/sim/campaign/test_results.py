"""The campaign's results (:mod:`dptbd.sim.campaign.results`): a case's verdict from its runs,
the campaign's totals and its functional coverage (bins added, the empty ones named)."""

from __future__ import annotations

import math

from dptbd.sim.campaign.results import CampaignResult, RunOutcome, summarise


def _outcome(seed, passed, bins):
    return RunOutcome("c", seed, passed, "bit-exact" if passed else "mismatch", 10 * seed,
                      9 * seed, 20 * seed, 0.5, 1.0, (), bins)


def test_a_case_passes_when_every_run_passes_and_keeps_its_first_failure():
    good = _outcome(1, True, {"a: x": 1, "b: y": 0})
    bad, worse = _outcome(2, False, {"a: x": 0}), _outcome(3, False, {})
    case = summarise("c", "dp", [good, bad, worse])
    assert (case.runs, case.passed, case.words_in, case.words_out, case.cycles) == \
        (3, False, 60, 54, 120)
    assert case.first_failure is bad and case.words_per_second == 54 / 1.5
    alone = summarise("c", "dp", [good])
    assert alone.passed and alone.first_failure is None
    assert math.isnan(summarise("c", "dp", []).words_per_second)


def test_the_campaign_adds_its_runs_and_their_bins():
    runs = (_outcome(1, True, {"a: x": 1, "b: y": 0}), _outcome(2, True, {"b: y": 0}))
    result = CampaignResult((summarise("c", "dp", list(runs)),), runs, 3.0, 2)
    assert (result.passed, result.words_in, result.words_out, result.mismatches) == \
        (True, 30, 27, 0)
    assert result.bins == {"a: x": 1, "b: y": 0}
    assert result.empty_bins == ["b: y"] and not result.covered
    failed = (runs[0], _outcome(2, False, {"b: y": 3}))
    result = CampaignResult((summarise("c", "dp", list(failed)),), failed, 3.0, 2)
    assert (result.passed, result.mismatches, result.covered) == (False, 1, True)
