"""What a campaign run draws from its seed (:mod:`dptbd.sim.campaign.draw`): hostile scenes,
stalls and faults, the same for the same seed."""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.sim.campaign.cases import default_cases
from dptbd.sim.campaign.draw import hostile_frames, make_run


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
    # 16 of the case's 400 frames (the draws do not need more: every framing fault is drawn
    # from 4 frames on), the same parameter set
    case = dataclasses.replace(default_cases()[1], frames=16)
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


def test_runs_at_p_pixels_per_clock_fault_at_beat_boundaries():
    """P = 2 and 4: the words are beats of P pixels; every framing fault falls on a beat
    boundary, ``first`` only on a beat's pixel 0, every change before a beat of the run and
    every reset within the run's cycles."""
    import re

    from dptbd.sim.campaign.cases import wide_cases
    from dptbd.sim.rtl.check import split_beats
    from dptbd.sim.verilator import cycle_budget

    # 12 frames: every framing fault is drawn from 4 frames on
    for case in [dataclasses.replace(c, frames=12)
                 for c in wide_cases(default_cases()[1].faults) if c.design == "segmenter"]:
        cfg, p = case.cfg, case.cfg.pixels_per_clock
        notes = []
        for seed in range(4):
            words, stim, run_notes = make_run(case, seed)
            notes += run_notes
            pixels, first = split_beats(cfg, words)
            assert len(pixels) == p * len(words)
            assert first.sum() == first[::p].sum() > case.frames // 2
            assert all(c < cycle_budget(len(words), stim.valid_gap, stim.ready_pause, 0)
                       for c, _ in stim.resets)
            assert all(0 <= i <= len(words)
                       for i, _ in (*stim.lut_changes, *stim.settings_changes))
        positions = [int(v) for v in re.findall(r"(?:marker at pixel|cut to|runs) (\d+)",
                                                " ".join(notes))]
        assert len(positions) == 12 and all(v % p == 0 for v in positions), positions
