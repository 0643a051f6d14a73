"""The verification campaign (:mod:`dptbd.sim.campaign`, ``dptbd verify``): a slice of at
least 10^6 compared words runs in the default suite; the full campaign (10^8) is
``dptbd verify`` (``docs/gateware.md``, "Verification campaign")."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest
from helpers.refusals import whole

from dptbd.evaluation.execution import ExecutionError
from dptbd.sim import campaign
from dptbd.sim.axi.runs import AXI_FAULTS
from dptbd.sim.campaign import (Case, campaign_task, campaign_tasks, default_cases, make_run,
                                run_campaign)
from dptbd.sim.coverage.bins import GROUPS, POSITIONS, declared_axi


@pytest.mark.slow
def test_a_slice_of_the_campaign_is_bit_exact():
    """>= 10^6 compared words over every default case but the AXI ones (their builds are
    long; ``tests/sim/axi/test_runs.py`` and the test below run a small AXI case), the AXI4
    state store's (``tests/sim/campaign/test_store.py``) and those at P > 1 (the wide-cases
    test below), the 4-state store checks included."""
    cases = [c for c in default_cases() if c.design not in ("axi", "dp_axi", "axi_store")
             and c.cfg.pixels_per_clock == 1]
    result = run_campaign(cases, runs_scale=0.01, workers=2, base_seed=11)
    failures = [f"{o.case} seed {o.seed}: {o.report} ({o.notes})" for o in result.outcomes
                if not o.passed]
    assert not failures, failures
    assert result.words_out >= 10**6
    assert {c.name for c in result.cases} >= {c.name for c in cases}
    assert all(c.runs >= 1 for c in result.cases)
    # functional coverage: the slice (one run per case) fills every bin but the stall bands
    # its runs did not draw, some reset stages and LUT writes by row (the full campaign's)
    bins, empty = result.bins, result.empty_bins
    assert not result.covered and result.passed
    assert [b for b in empty if not b.startswith(("stall:", "reset:", "LUT: written"))] == []
    assert len(bins) - len(empty) >= 60
    for o in [o for o in result.outcomes if o.bins]:   # each run's bands, at every position
        band = next(k.rsplit(", ", 1)[0] for k, v in o.bins.items() if k.startswith("stall") and v)
        assert all(bins[f"{band}, {p}"] > 0 for p in POSITIONS), band
    assert bins["reset: 0 words in flight"] >= 1
    assert sum(bins[f"reset: {k} word{'s' * (k != 1)} in flight"] > 0 for k in range(15)) >= 7
    assert {g.name for g in GROUPS} - {k.split(":")[0] for k in bins} == {
        "soft reset", "aresetn", "register", "store"}


SMALL_SLICE = ("37x23-k3-in8-e12-f4", "core-96x64-garbage-store", "segmenter-33x17-k2-n3")


def test_a_small_slice_of_the_campaign_is_bit_exact():
    """The slice above (``-m slow``) on three of its cases, one per design (``dptbd_dp``,
    ``dptbd_core`` with the garbage store, ``dptbd_seg``): >= 10^6 compared words, one run
    each, bit-exact, and the 4-state store checks."""
    cases = [c for c in default_cases() if c.name in SMALL_SLICE]
    assert [c.name for c in cases] == list(SMALL_SLICE)
    result = run_campaign(cases, runs_scale=0.01, workers=2, base_seed=11)
    failures = [f"{o.case} seed {o.seed}: {o.report} ({o.notes})" for o in result.outcomes
                if not o.passed]
    assert not failures, failures
    assert [(c.name, c.runs) for c in result.cases] == [(n, 1) for n in SMALL_SLICE] + [
        (n, 1) for n in ("x-store-16x12", "garbage-store-16x12", "x-store-r2-14x11",
                         "garbage-store-r2-14x11")]
    assert result.words_out >= 10**6
    # functional coverage: every bin of these designs but the stall bands their runs did not
    # draw, reset stages, the LUT write in the first row and saturation (the narrow case's)
    bins, empty = result.bins, result.empty_bins
    assert [b for b in empty if not b.startswith(("stall:", "reset:", "LUT: written",
                                                   "saturation:"))] == []
    assert len(bins) - len(empty) >= 32
    for o in [o for o in result.outcomes if o.bins]:   # each run's bands, at every position
        band = next(k.rsplit(", ", 1)[0] for k, v in o.bins.items() if k.startswith("stall") and v)
        assert all(bins[f"{band}, {p}"] > 0 for p in POSITIONS), band
    assert not result.covered and result.passed


def test_the_campaign_runs_an_axi_case():
    """``design="axi"``: the runs come from :mod:`dptbd.sim.axi.runs`, through the pool."""
    case = Case("axi-12x10", dict(width=12, height=10, segment_frames=2, max_segment_frames=4,
                                  candidate_count=4, candidate_capacity=6, histogram_bits=6,
                                  histogram_shift=2), "axi", 20, 3, AXI_FAULTS)
    result = run_campaign([case], workers=1, x_store=False, base_seed=2)
    assert [(c.name, c.design, c.runs, c.passed) for c in result.cases] == \
        [("axi-12x10", "axi", 3, True)]
    plans = [make_run(case, o.seed) for o in result.outcomes]
    assert result.words_in == sum(len(p.beats) for p in plans)
    assert all(o.notes == p.notes for o, p in zip(result.outcomes, plans))
    assert set(result.bins) == set(declared_axi(case.cfg, 17))       # L = 17: this build's
    assert all(sum(o.bins.values()) > 0 for o in result.outcomes)


def test_the_ecp5_cases_are_named_cases_again_on_the_family_build():
    """``family_cases``: each case of ``FAMILY_CASES`` again with ``family="ecp5"``, named
    ``<name>-ecp5``, with half its runs; the AXI top's (registered control, DP16KD store
    and histogram on the model) one shortened run through the campaign, bit-exact."""
    from dptbd.sim.campaign.cases import FAMILY_CASES
    from dptbd.sim.verilator import build

    cases = default_cases()
    by_name = {c.name: c for c in cases}
    family = [c for c in cases if c.family is not None]
    assert [c.name for c in family] == [f"{name}-ecp5" for name in FAMILY_CASES]
    assert {c.design for c in family} == {"dp", "core", "segmenter", "axi", "dp_axi",
                                           "axi_store"}
    for case in family:
        base = by_name[case.name.removesuffix("-ecp5")]
        assert base.family is None and case == dataclasses.replace(
            base, name=case.name, family="ecp5", runs=max(1, base.runs // 2))
    case = dataclasses.replace(by_name["axi-24x16-f0-k2-ecp5"], frames=40)
    result = run_campaign([case], runs_scale=0.25, workers=1, x_store=False, base_seed=5)
    assert [(c.name, c.runs, c.passed) for c in result.cases] == \
        [("axi-24x16-f0-k2-ecp5", 1, True)], [o.report for o in result.outcomes]
    assert result.words_in == len(make_run(case, result.outcomes[0].seed).beats)
    sim = build(case.cfg, "axi", family="ecp5")           # the campaign's build, cached
    assert sim.cached and sim.manifest["core_options"]["histogram_style"] == "dp16kd"


@pytest.mark.parametrize("p", [pytest.param(2, marks=pytest.mark.slow), 4])
def test_the_campaign_runs_the_wide_cases(p):
    """``dptbd_seg`` and ``dptbd_axi`` at P = 2 and 4 (``wide_cases``; the default suite
    P = 4, ``-m slow`` both): two shortened runs each, bit-exact with their faults (beats of
    P pixels through ``check_stream`` and ``check_axi``)."""
    from dptbd.sim.campaign.cases import wide_cases

    cases = [dataclasses.replace(c, frames=c.frames // 4, runs=2)
             for c in wide_cases(default_cases()[1].faults) if c.cfg.pixels_per_clock == p]
    assert {c.design for c in cases} == {"segmenter", "axi"}
    result = run_campaign(cases, workers=1, x_store=False, base_seed=3)
    assert [(c.name, c.runs, c.passed) for c in result.cases] == \
        [(c.name, 2, True) for c in cases], [o.report for o in result.outcomes]
    pixels = {c.name: c.cfg.pixels_per_clock for c in cases if c.design == "segmenter"}
    assert sum(o.words_in for o in result.outcomes if o.case in pixels) == sum(
        len(make_run(c, o.seed)[0]) * pixels[c.name]
        for c in cases for o in result.outcomes if o.case == c.name and c.name in pixels)
    assert all(sum(o.bins.values()) > 0 for o in result.outcomes)


def test_a_wrong_model_fails_the_campaign(monkeypatch):
    """The campaign can fail: a model whose LUT differs from the gateware's is caught."""
    import dptbd.sim.rtl.check as rtl_check

    real = rtl_check.expected_stream

    def off_by_one(cfg, pixels, first, lut_changes=None, settings_changes=None):
        exp = real(cfg, pixels, first, lut_changes, settings_changes)
        exp.words[len(exp.words) // 2] ^= np.uint64(1)
        return exp

    monkeypatch.setattr(rtl_check, "expected_stream", off_by_one)
    case = Case("tiny", dict(width=9, height=7, segment_frames=2), "dp", 6, 1)
    outcome = campaign.check_run(case, 3)
    assert not outcome.passed
    assert "first mismatch at output" in outcome.report and "field energy" in outcome.report
    # through the campaign (in this process, where the patch holds): every failing run is
    # reported as it finishes, the case's verdict names the first
    seen = []
    result = run_campaign([dataclasses.replace(case, runs=2)], workers=1, x_store=False,
                          base_seed=1, on_outcome=seen.append)
    assert not result.passed and result.mismatches == 2 and result.workers == 1
    assert [(o.seed, o.passed) for o in seen] == [(1_000_003, False), (1_000_004, False)]
    assert result.cases[0].first_failure == seen[0]


# ---- on the execution layer ----------------------------------------------------------------

def _short(case: Case, frames: int, runs: int) -> Case:
    """``case`` with fewer frames and runs: the same parameter set, so the same build."""
    return dataclasses.replace(case, name=case.name + "-short", frames=frames, runs=runs)


def _untimed(result: campaign.CampaignResult) -> campaign.CampaignResult:
    """``result`` without its timings (and worker count): what must not depend on workers."""
    def run(o):
        return None if o is None else dataclasses.replace(o, sim_seconds=0.0, wall_seconds=0.0)
    return dataclasses.replace(
        result, wall_seconds=0.0, workers=0, outcomes=tuple(run(o) for o in result.outcomes),
        cases=tuple(dataclasses.replace(c, sim_seconds=0.0, first_failure=run(c.first_failure))
                    for c in result.cases))


def test_the_campaign_is_the_same_on_one_and_two_workers():
    """The whole result but its timings, in task order, whatever finished first; the
    progress callback sees every outcome once. The 4-state store checks left out (tasks on
    the same layer; the small slice above runs them)."""
    cases = [_short(default_cases()[1], 12, 3), _short(default_cases()[7], 4, 2)]
    seen = {1: [], 2: []}
    results = {w: run_campaign(cases, workers=w, base_seed=5, x_store=False,
                               on_outcome=seen[w].append)
               for w in (1, 2)}
    assert results[1].workers == 1 and results[2].workers == 2
    assert _untimed(results[1]) == _untimed(results[2])
    assert results[1].passed and len(results[1].outcomes) == 3 + 2
    assert [(o.case, o.seed) for o in results[1].outcomes] == [
        (c.name, s) for kind, c, s, _ in campaign_tasks(cases, base_seed=5, x_store=False)]
    for w in (1, 2):
        assert sorted(seen[w], key=results[w].outcomes.index) == list(results[w].outcomes)


def test_campaign_tasks_are_seeded_by_case_and_run():
    cases = [_short(default_cases()[1], 12, 3), _short(default_cases()[7], 4, 20)]
    tasks = campaign_tasks(cases, runs_scale=0.1, base_seed=2, root="/r")
    assert tasks[:3] == [("run", cases[0], 2_000_006 + r, "/r") for r in range(1)] + [
        ("run", cases[1], 2_000_006 + 7919 + r, "/r") for r in range(2)]
    assert [t[0] for t in tasks[3:]] == ["x_store"] * 4
    assert len(campaign_tasks(cases, x_store=False)) == 23
    with pytest.raises(ValueError, match=whole(
            "campaign task kind must be 'run' or 'x_store', got 'nope'")):
        campaign_task("nope")


def test_a_bad_worker_count_is_the_layers_refusal():
    with pytest.raises(ExecutionError, match=whole(
            "workers must be an integer in [1, 1024], got 0")):
        run_campaign([], workers=0)


def test_a_worker_without_the_clients_build_root_builds_for_itself(tmp_path):
    """A ``dask worker`` process whose ``DPTBD_BUILD_DIR`` is its own (a machine without the
    client's file system): the client builds into its cache, the worker builds the same
    executable into its own, and the run is bit-exact."""
    from helpers.dask_processes import DASK, process_cluster

    own = tmp_path / "worker-cache"
    case = Case("tiny-9x7", dict(width=9, height=7, segment_frames=2), "dp", 6, 2,
                ("lut", "misaligned_first"))
    worker = ["env", f"DPTBD_BUILD_DIR={own}", str(DASK), "worker"]
    with process_cluster(tmp_path, {"elsewhere": worker}) as (address, _):
        result = run_campaign([case], scheduler=address, x_store=False)
    assert result.passed and result.workers == 1 and len(result.outcomes) == 2
    built = [p.name for p in (own / "verilator").iterdir() if p.name.startswith("9x7-")]
    assert len(built) == 1 and re.fullmatch(r"9x7-k2-.*-dp-[0-9a-f]{12}", built[0])


def test_a_case_that_saturates_on_purpose_warns_nowhere():
    """The narrow case's EnergyWidthWarning (its point) is not printed by every worker."""
    import warnings

    from dptbd.config import EnergyWidthWarning

    case = _short(next(c for c in default_cases() if c.name.startswith("narrow")), 6, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("error", EnergyWidthWarning)
        assert campaign.check_run(case, 0).passed
