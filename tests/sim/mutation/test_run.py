"""Mutant verdicts: a run that hangs, crashes or is refused by Yosys is reported as such and
never counted as killed; the slice stops at a mutant's first failing run."""

from __future__ import annotations

import types

import pytest

from dptbd.sim.mutation import run as R
from dptbd.sim.mutation.netlist import Mutation

from helpers.refusals import whole


def fake(results: dict):
    """A runner answering ``results[(kind, seed)]`` (default survived), recording calls and
    the mutant selected through the environment."""
    calls = []

    def runner(sim, kind, seed):
        import os
        calls.append((kind, seed, os.environ["DPTBD_MUTANT"], os.environ["DPTBD_MUTANT_SECONDS"]))
        answer = results.get((kind, seed), ("survived", ""))
        if isinstance(answer, Exception):
            raise answer
        return answer

    return runner, calls


SIM = types.SimpleNamespace(design="segmenter")
RUNS = (("clean", 0), ("faults", 0), ("faults", 1))


@pytest.mark.parametrize("answer, verdict, report", [
    (("killed", "first mismatch at output word 3"), "killed", "first mismatch at output word 3"),
    (("timeout", "cycle budget ran out"), "timeout", "cycle budget ran out"),
    (RuntimeError("dptbd_sim failed (exit 124): "), "timeout", "wall-clock limit of 5 s"),
    (RuntimeError("dptbd_sim failed (exit -6): %Error: design did not converge\nmore"),
     "crashed", "dptbd_sim failed (exit -6): %Error: design did not converge"),
])
def test_verdicts_stop_at_the_first_failing_run(answer, verdict, report):
    runner, calls = fake({("faults", 0): answer})
    outcome = R.run_slice(SIM, 7, RUNS, wall_seconds=5, runner=runner)
    assert (outcome.index, outcome.verdict, outcome.run, outcome.report) == \
        (7, verdict, "faults seed 0", report)
    assert calls == [("clean", 0, "7", "5"), ("faults", 0, "7", "5")]


def test_survivor_runs_every_run_and_environment_restored(monkeypatch):
    monkeypatch.setenv("DPTBD_MUTANT", "keep")
    monkeypatch.delenv("DPTBD_MUTANT_SECONDS", raising=False)
    runner, calls = fake({})
    outcome = R.run_slice(SIM, 2, RUNS, wall_seconds=9, runner=runner)
    assert (outcome.verdict, outcome.run, outcome.report) == ("survived", "", "")
    assert [c[:2] for c in calls] == list(RUNS)
    import os
    assert os.environ["DPTBD_MUTANT"] == "keep" and "DPTBD_MUTANT_SECONDS" not in os.environ


def test_score_counts_only_killed():
    m = Mutation("mutate -mode inv", "inv", "c", "Y", 0, None, None, None, ())
    outcomes = tuple(R.MutantOutcome(i, v, "", "", 0.0) for i, v in
                     enumerate(("killed", "survived", "timeout", "crashed", "no-build"), 1))
    result = R.MutationResult("segmenter", 1, (m,) * 5, outcomes[0], outcomes, RUNS, 1.0, 1)
    assert (result.killed, result.total, result.killed_fraction) == (1, 5, 0.2)
    assert result.shown_equivalent({}) == {} and result.score({}) == 0.2   # none shown
    assert [o.index for o, _ in result.of("timeout")] == [3]


def test_slice_runs_scaled():
    assert R.slice_runs("axi", 0.01) == (("faults", 0), ("backpressure", 1), ("random", 0),
                                         ("lut", 0), ("counters", 0), ("presets", 0),
                                         ("irq", 0),
                                         ("restart", 0), ("decode", 0), ("n-values", 0),
                                         ("noise", 0), ("resync", 0), ("lut-reverse", 0),
                                         ("shifts", 0), ("line-ends", 0),
                                         ("lut-entry", 0), ("low-shift", 0),
                                         ("list-lengths", 0), ("full-fifo", 0),
                                         ("reference", 0), ("stalls", 0), ("lists", 0))
    assert len(R.slice_runs("segmenter")) == len(R.SLICE_RUNS["segmenter"])


@pytest.mark.parametrize("status, report, verdict", [
    ("budget", "timeout after 9000 cycles: 70 of 120 words in", "timeout"),
    ("budget", "done; bit-exact: 2 lists, 5 records, 7 words", "timeout"),
    ("budget", "incomplete: 3 of 7 words received (1 list), all bit-exact", None),
    ("budget", "first mismatch at output word 3", None),
    ("budget", "2 word(s) beyond the 7 expected (1 list)", None),
    ("done", "bit-exact: 2 lists", None),
    ("done", "incomplete: 3 of 7 words received, all bit-exact", None),
])
def test_a_hang_is_killed_only_where_the_model_expects_more_words(status, report, verdict):
    """A run out of its cycle budget: killed (the check decides) if a word the model expects
    is missing, wrong or extra; a timeout if every expected word came."""
    assert R.hang_verdict(status, report) == verdict


def test_the_axi_slice_lut_runs_are_their_seed_at_k_max():
    """A ``lut`` run: the seed's LUT (codes in [0, 2**F], not all equal) from the first beat,
    K = K_max and n = C written first, 16 whole frames; another seed, another LUT."""
    from dptbd.sim.mutation.slices.axi import LUT_RUNS, RUNS, lut_scenario

    cfg = R.config("axi")
    beats, steps = lut_scenario(cfg, 3)
    again, other = lut_scenario(cfg, 3)[1], lut_scenario(cfg, 4)[1]
    (step,) = steps
    assert step == again[0] and step["lut_codes"] != other[0]["lut_codes"]
    assert step["writes"] == [["SEGMENT_FRAMES", cfg.k_max],
                              ["CANDIDATE_COUNT", cfg.record_capacity]]
    codes = [c for row in step["lut_codes"] for c in row]
    assert len(codes) == cfg.lut_entries and len(set(codes)) > 1
    assert min(codes) >= 0 and max(codes) <= 1 << cfg.weight_frac_bits
    assert step["stop"] == len(beats) == 16 * cfg.width * cfg.height
    assert [r for r in RUNS if r[0] == "lut"] == [("lut", s) for s in range(LUT_RUNS)]
    assert RUNS[-2:] == (("stalls", 0), ("lists", 0))  # the long runs last: few reach them


def test_the_slice_of_a_build_is_its_design_and_pixels_per_clock():
    """``dp``, ``dp2`` and ``dp4`` are all Verilator builds of ``dp``: the build's P tells them
    apart (``dp`` runs its slice, ``dp2`` and ``dp4`` the wide one, parametrised by P); a build
    no design with mutants is refused by name."""
    def build(design, cfg):
        return types.SimpleNamespace(design=design, cfg=cfg)

    assert R.slice_design(build("dp", R.config("dp"))) == "dp"
    assert R.slice_design(build("dp", R.config("dp2"))) == "dp2"
    assert R.slice_design(build("dp", R.config("dp4"))) == "dp4"
    assert R.slice_design(build("segmenter", R.config("segmenter"))) == "segmenter"
    assert R.RUNNERS["dp2"] is not R.RUNNERS["dp"]
    assert R.RUNNERS["dp4"] is R.RUNNERS["dp2"]         # one slice, parametrised by P
    with pytest.raises(ValueError, match=whole(
            "no design with mutants is a build of 'core' at pixels_per_clock=1; they are "
            "segmenter (segmenter, P = 1), axi (axi, P = 1), dp (dp, P = 1), dp2 (dp, P = 2), "
            "dp4 (dp, P = 4)")):
        R.slice_design(build("core", R.config("dp")))
