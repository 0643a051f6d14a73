"""The verification campaign (:mod:`dptbd.sim.campaign`, ``dptbd verify``): a slice of at
least 10^6 compared words runs in the default suite; the full campaign (10^8) is
``dptbd verify`` (``docs/gateware.md``, "Verification campaign")."""

from __future__ import annotations

import numpy as np

from dptbd.sim import campaign
from dptbd.sim.campaign import Case, default_cases, hostile_frames, make_run, run_campaign
from dptbd.sim.coverage.bins import GROUPS, POSITIONS


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
    assert {"dp", "core", "segmenter"} <= {c.design for c in cases}
    assert all(set(c.faults) >= {"reset", "misaligned_first", "short_frame", "long_frame", "lut",
                                 "settings"} for c in cases)
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
    assert any(s.valid_gap == 0 < s.ready_pause for s in stalls)       # back-pressure only
    assert any(s.ready_pause == 0 < s.valid_gap for s in stalls)       # gaps only
    # with the build's latency, some runs reset early: 2 cycles of power-up reset, then
    # 0 … L + 1 cycles of words
    early = [make_run(case, s, latency=13) for s in range(20)]
    firsts = [stim.resets[0][0] for _, stim, notes in early
              if any(n.startswith("early reset") for n in notes)]
    assert len(firsts) >= 5 and all(2 <= c <= 2 + 14 for c in firsts)
    assert all(make_run(case, s)[1].resets == stim.resets[len(stim.resets)
                                                         - len(make_run(case, s)[1].resets):]
               for s, (_, stim, _) in enumerate(early))       # the other draws unchanged


def test_a_slice_of_the_campaign_is_bit_exact():
    """>= 10^6 compared words over every default case, the 4-state store checks included."""
    result = run_campaign(runs_scale=0.01, workers=2, base_seed=11)
    failures = [f"{o.case} seed {o.seed}: {o.report} ({o.notes})" for o in result.outcomes
                if not o.passed]
    assert not failures, failures
    assert result.words_out >= 10**6
    assert {c.name for c in result.cases} >= {c.name for c in default_cases()}
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
    assert {g.name for g in GROUPS} - {k.split(":")[0] for k in bins} == {"soft reset",
                                                                         "register"}


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
