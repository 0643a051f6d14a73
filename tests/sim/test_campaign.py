"""The verification campaign (:mod:`dptbd.sim.campaign`, ``dptbd verify``): a slice of at
least 10^6 compared words runs in the default suite; the full campaign (10^8) is
``dptbd verify`` (``docs/gateware.md``, "Verification campaign")."""

from __future__ import annotations

import numpy as np

from dptbd.sim import campaign
from dptbd.sim.axi_runs import AXI_FAULTS
from dptbd.sim.campaign import Case, default_cases, hostile_frames, make_run, run_campaign


def test_default_cases_cover_what_the_campaign_promises():
    cases = default_cases()
    assert len({c.name for c in cases}) == len(cases) >= 8
    cfgs = [c.cfg for c in cases]
    assert any((c.width, c.height) == (128, 128) and c.segment_frames == 8 and c.input_bits == 12
               for c in cfgs)                                        # 001's setting
    assert any(c.width & (c.width - 1) and c.height & (c.height - 1) for c in cfgs)
    assert any(c.energy_bits < c.energy_bits_needed for c in cfgs)  # saturates
    assert {0, 8} <= {c.weight_frac_bits for c in cfgs}
    assert any(c.radius == 2 for c in cfgs)
    assert any(c.random_lut for c in cases)
    assert {"dp", "core", "segmenter", "axi"} <= {c.design for c in cases}
    assert all(set(c.faults) >= {"reset", "misaligned_first", "short_frame", "long_frame", "lut",
                                 "settings"} for c in cases if c.design != "axi")
    axi = [c for c in cases if c.design == "axi"]
    assert all(set(c.faults) == set(AXI_FAULTS) for c in axi)
    assert any((c.cfg.width, c.cfg.height, c.cfg.segment_frames) == (128, 128, 8) for c in axi)
    assert {1, 2} <= {c.cfg.radius for c in axi} and 0 in {c.cfg.weight_frac_bits for c in axi}
    assert any(0 < c.cfg.weight_frac_bits < 8 for c in axi)
    assert all(c.cfg.k_max > c.cfg.segment_frames for c in axi if c.cfg.width < 128)
    assert any("store_garbage" in c.faults for c in cases)
    assert sum(c.runs * c.words_per_run for c in cases if c.design != "segmenter") >= 10**8


def test_hostile_frames_hold_every_kind_of_frame():
    cfg = default_cases()[1].cfg
    frames = hostile_frames(cfg, 400, np.random.default_rng(1))
    assert frames.shape == (400, cfg.height, cfg.width) and frames.max() <= cfg.pixel_max
    flat = frames.reshape(len(frames), -1)
    assert (flat == cfg.pixel_max).all(axis=1).any()                 # all maximum
    assert (flat == 0).all(axis=1).any()                             # all zero
    assert (flat == flat[:, :1]).all(axis=1).sum() > 2               # constant
    checker = (frames[:, 0::2, 0::2] == frames[:, :1, :1]).all(axis=(1, 2)) & \
        (frames[:, 1::2, 0::2] != frames[:, :1, :1]).all(axis=(1, 2))
    assert checker.any()                                             # checkerboards


def test_runs_are_seeded_and_draw_their_faults():
    case = default_cases()[1]
    a, b = make_run(case, 5), make_run(case, 5)
    assert np.array_equal(a[0], b[0]) and a[1].resets == b[1].resets and a[2] == b[2]
    notes = " ".join(n for seed in range(6) for n in make_run(case, seed)[2])
    for what in ("marker", "cut to", "runs", "LUT rewritten", "resets at cycles",
                 "settings (K, n, s) rewritten"):
        assert what in notes
    stalls = [make_run(case, s)[1] for s in range(20)]
    assert max(s.valid_gap for s in stalls) > 0.5 and min(s.valid_gap for s in stalls) == 0.0


def test_a_slice_of_the_campaign_is_bit_exact():
    """>= 10^6 compared words over every default case but the AXI ones (their builds are
    long; ``tests/sim/test_axi_runs.py`` and the test below run a small AXI case), the
    4-state store checks included."""
    cases = [c for c in default_cases() if c.design != "axi"]
    result = run_campaign(cases, runs_scale=0.01, workers=2, base_seed=11)
    failures = [f"{o.case} seed {o.seed}: {o.report} ({o.notes})" for o in result.outcomes
                if not o.passed]
    assert not failures, failures
    assert result.words_out >= 10**6
    assert {c.name for c in result.cases} >= {c.name for c in cases}
    assert all(c.runs >= 1 for c in result.cases)


def test_the_campaign_runs_an_axi_case():
    """``design="axi"``: the runs come from :mod:`dptbd.sim.axi_runs`, through the pool."""
    case = Case("axi-12x10", dict(width=12, height=10, segment_frames=2, max_segment_frames=4,
                                  candidate_count=4, candidate_capacity=6, histogram_bits=6,
                                  histogram_shift=2), "axi", 20, 3, AXI_FAULTS)
    result = run_campaign([case], workers=1, x_store=False, base_seed=2)
    assert [(c.name, c.design, c.runs, c.passed) for c in result.cases] == \
        [("axi-12x10", "axi", 3, True)]
    plans = [make_run(case, o.seed) for o in result.outcomes]
    assert result.words_in == sum(len(p.beats) for p in plans)
    assert all(o.notes[:-1] == p.notes for o, p in zip(result.outcomes, plans))


def test_a_wrong_model_fails_the_campaign(monkeypatch):
    """The campaign can fail: a model whose LUT differs from the gateware's is caught."""
    import dptbd.sim.rtl_check as rtl_check

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
