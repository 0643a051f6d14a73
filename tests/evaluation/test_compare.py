"""``dptbd compare``: the float kernel, the SNR-loss arithmetic, the Monte Carlo's invariants
(worker count, chunking, agreement), bad input refused before any work, output files."""

from __future__ import annotations

import argparse
import json
import math
import warnings

import numpy as np
import pytest

from dptbd.config import ConfigError, DPConfig, plain_weights
from dptbd.evaluation import compare as cmp
from dptbd.scenes import synthetic as scenes
from dptbd.evaluation.compare import build_spec, cosine_weights, make_plan, measure_frames, run_compare
from dptbd.model.fast_float import run_float_fast
from dptbd.evaluation.metrics import first_level_counts
from dptbd.model.reference import run_float
from dptbd.model.segmentation import candidate_mask
from dptbd.evaluation.snr_loss import (
    LossEstimate, bootstrap_losses, clustered_wilson, crossing, isotonic, snr_db)
from dptbd.evaluation.stats import wilson_interval
from dptbd.evaluation import sweep

#: A small run: 16 x 16, 12 frames (3 segments of K = 4), 5 candidates per frame.
SMALL = {
    "trials": 6, "seed": 7, "snr": [1.5, 2.5, 3.5], "size": 16, "frames": 12,
    "velocity": [1.0, 0.0], "segment_frames": 4, "false_alarm_rate": 0.02, "chunk": 2,
    "bootstrap": 50, "thresholds": [2.0, 3.0, 4.0],
    "config": [{"name": "eight", "input_bits": 8},
               {"name": "four", "input_bits": 4, "energy_bits": 5},
               {"name": "cos", "input_bits": 8, "lut": "cosine", "weight_frac_bits": 2}],
    "sweep": {},
}


# ---- the float kernel ----------------------------------------------------------------------

@pytest.mark.parametrize("kw", [
    {}, {"radius": 2}, {"segment_frames": 3, "segment_stride": 2}, {"segment_frames": 1},
    {"weights": "random"}, {"weights": "plain"},
])
def test_float_kernel_is_bit_identical_to_run_float(kw):
    kw = dict(kw)
    radius = kw.get("radius", 1)
    m = (2 * radius + 1) ** 2
    if kw.get("weights") == "random":
        kw["weights"] = np.random.default_rng(3).random((m + 1, m))
    elif kw.get("weights") == "plain":
        kw["weights"] = plain_weights(radius)
    cfg = DPConfig(width=11, height=7, **kw)
    rng = np.random.default_rng(1)
    frames = rng.normal(30, 2, (2, 9, 7, 11)).astype(np.float32)
    frames[0, :, 3, 4] = 30.0  # equal values: ties must break the same way
    frames[1] = np.rint(frames[1])
    a, b = run_float_fast(frames, cfg, threads=2), run_float(frames, cfg)
    assert np.array_equal(a.energy, b.energy) and a.energy.dtype == np.float64
    assert np.array_equal(a.direction, b.direction)
    assert np.array_equal(a.end_frames, b.end_frames)


def test_float_kernel_refuses_what_run_float_refuses():
    cfg = DPConfig(width=5, height=5)
    bad = np.full((4, 5, 5), np.nan)
    for fn in (run_float, run_float_fast):
        with pytest.raises(ValueError, match="finite"):
            fn(bad, cfg)
        with pytest.raises(ValueError, match="shorter than one segment"):
            fn(np.zeros((2, 5, 5)), cfg)


# ---- SNR crossing and loss ---------------------------------------------------------------------

def test_crossing_interpolates_linearly_between_grid_points():
    x = [0.0, 1.0, 2.0, 3.0]
    assert crossing(x, [0.2, 0.4, 0.6, 0.8], 0.5) == pytest.approx(1.5)
    assert crossing(x, [0.2, 0.4, 0.6, 0.9], 0.8) == pytest.approx(2.0 + 0.2 / 0.3)
    assert crossing(x, [0.2, 0.5, 0.6, 0.9], 0.5) == pytest.approx(1.0)  # exactly on a point
    assert crossing(x, [0.6, 0.7, 0.8, 0.9], 0.5) == -math.inf             # below the grid
    assert crossing(x, [0.1, 0.2, 0.3, 0.4], 0.5) == math.inf              # never reached


def test_crossing_makes_the_curve_monotone_first():
    # a dip (0.6 then 0.4) is pooled to 0.5, 0.5: one crossing, at the first pooled point
    assert np.allclose(isotonic([0.1, 0.6, 0.4, 0.7]), [0.1, 0.5, 0.5, 0.7])
    assert np.allclose(isotonic([0.1, 0.6, 0.4, 0.7], [1, 1, 3, 1]), [0.1, 0.45, 0.45, 0.7])
    assert crossing([0, 1, 2, 3], [0.1, 0.6, 0.4, 0.7], 0.5) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        crossing([0, 2, 1], [0.1, 0.5, 0.9], 0.5)


def _curves(n_trials: int, pd_ref, pd_det, opp: int = 20, seed: int = 0):
    """Per-trial detections drawn from given Pd curves."""
    rng = np.random.default_rng(seed)
    det = np.stack([rng.binomial(opp, np.broadcast_to(np.asarray(p)[:, None], (len(p), n_trials)))
                    for p in (pd_ref, pd_det)])
    return det, np.full((len(pd_ref), n_trials), opp)


def test_loss_of_an_identical_detector_is_exactly_zero():
    x = snr_db([1.5, 2.0, 2.5, 3.0])
    det, opp = _curves(50, [0.2, 0.5, 0.8, 0.95], [0.2, 0.5, 0.8, 0.95])
    det[1] = det[0]
    (est,) = bootstrap_losses(x, det, opp, [(1, 0)], (0.5, 0.8), n_boot=200, seed=1)
    for e in est:
        assert e.loss == 0.0 and e.lo == 0.0 and e.hi == 0.0
        assert e.within(0.1) and not e.differs()


def test_loss_of_a_shifted_curve_is_the_shift_and_its_interval_covers_it():
    # the detector's Pd at grid point j is the reference's at j - 1: it needs one grid
    # step (1 dB) more SNR wherever both curves are linear in between
    x = np.arange(0.0, 8.0)
    ref = np.array([0.05, 0.15, 0.3, 0.45, 0.6, 0.75, 0.88, 0.97])
    det_pd = np.concatenate([[0.01], ref[:-1]])
    det, opp = _curves(400, ref, det_pd, opp=50, seed=2)
    est = bootstrap_losses(x, det, opp, [(1, 0), (0, 1)], (0.5, 0.8), n_boot=400, seed=3)
    for e, back in zip(est[0], est[1]):
        assert e.lo < 1.0 < e.hi and e.hi - e.lo < 0.5
        assert e.loss == pytest.approx(1.0, abs=0.2)
        assert back.loss == pytest.approx(-e.loss)  # swapping the pair flips the sign
        assert e.beyond(0.1) and e.differs()


def test_loss_interval_is_unbounded_when_the_level_is_not_reached():
    x = snr_db([1.5, 2.0, 2.5])
    det, opp = _curves(40, [0.3, 0.6, 0.9], [0.0, 0.05, 0.1])
    (est,) = bootstrap_losses(x, det, opp, [(1, 0)], (0.5,), n_boot=100, seed=0)
    assert est[0].loss == math.inf and est[0].hi == math.inf and est[0].beyond(0.1)
    assert sweep.verdict(est, 0.1) == "beyond"
    (est0,) = bootstrap_losses(x, det, opp, [(1, 0)], (0.5,), n_boot=0)
    assert math.isnan(est0[0].lo) and sweep.verdict(est0, 0.1) == "undecided"


def test_verdicts():
    def e(lo, hi):
        return LossEstimate(0.5, (lo + hi) / 2, lo, hi, 0.0, 0.0, 0.0)
    assert sweep.verdict([e(-0.05, 0.08), e(0.0, 0.1)], 0.1) == "within"
    assert sweep.verdict([e(-0.05, 0.08), e(0.05, 0.2)], 0.1) == "undecided"
    assert sweep.verdict([e(-0.05, 0.08), e(0.11, 0.3)], 0.1) == "beyond"


def test_cost_key_and_choose_the_smallest_configuration_within_the_tolerance():
    spec = build_spec({"trials": 1,
                       "config": [{"name": "tiny", "input_bits": 3, "weight_frac_bits": 0}],
                       "sweep": {"input_bits": [6, 7, 8], "energy_headroom": [0, -1],
                                 "weight_frac_bits": [0]}})
    by = {f.name: f for f in spec.configs}
    assert not by["tiny"].in_sweep
    f = by["7/9/0 truncate paper"]
    assert sweep.cost_key(f) == (9 + 4, 0, 7, 0)               # B_E + B_d (r = 1), LUT4, B_in, F
    assert sweep.cost_key(f, {"lut4": 745}) == (13, 745, 7, 0)
    verdicts = {name: "beyond" for name in by}
    verdicts.update({"tiny": "within",                        # smaller, but not in the sweep
                     "8/10/0 truncate paper": "within", "8/11/0 truncate paper": "within",
                     "7/10/0 truncate paper": "within", "7/9/0 truncate paper": "within",
                     "6/8/0 truncate paper": "undecided"})
    assert sweep.choose(spec.configs, verdicts) == {"within": "7/9/0 truncate paper",
                                                   "not_beyond": "6/8/0 truncate paper"}
    # the state word first: 7/10/0 and 8/10/0 tie at 14 bits; then SB_LUT4 when known, else B_in
    verdicts["7/9/0 truncate paper"] = "beyond"
    verdicts["6/8/0 truncate paper"] = "beyond"
    assert sweep.choose(spec.configs, verdicts)["within"] == "7/10/0 truncate paper"
    hw = {"7/10/0 truncate paper": {"lut4": 800}, "8/10/0 truncate paper": {"lut4": 780}}
    assert sweep.choose(spec.configs, verdicts, hw) == {"within": "8/10/0 truncate paper",
                                                       "not_beyond": "8/10/0 truncate paper"}
    # nothing within: None; no configuration in a sweep: every configuration is a candidate
    assert sweep.choose(spec.configs, {n: "beyond" for n in by}) == {"within": None,
                                                                   "not_beyond": None}
    alone = build_spec({"trials": 1, "sweep": {},
                        "config": [{"name": "a", "input_bits": 8}, {"name": "b", "input_bits": 6}]})
    assert sweep.choose(alone.configs, {"a": "within", "b": "within"})["within"] == "b"


def test_paired_difference():
    from dptbd.evaluation.compare_report import paired_difference
    # identical detectors: exactly zero, a zero-width interval
    assert paired_difference([3, 5, 2], [3, 5, 2], [10, 10, 10]) == (0.0, 0.0, 0.0)
    # by hand: delta = 2/30; residuals (a - b) - delta n = (4/3, -2/3, -2/3), sum of
    # squares 8/3, times k/(k-1) = 3/2 gives 4: se = 2/30
    d, lo, hi = paired_difference([3, 5, 2], [1, 5, 2], [10, 10, 10])
    z = 1.959963984540054
    assert d == pytest.approx(2 / 30)
    assert (lo, hi) == pytest.approx((2 / 30 - z * 2 / 30, 2 / 30 + z * 2 / 30))
    back = paired_difference([1, 5, 2], [3, 5, 2], [10, 10, 10])   # swapped: sign flips
    assert back == pytest.approx((-d, -hi, -lo))
    # the same difference in every cluster: no spread, a zero-width interval
    assert paired_difference([4, 4], [2, 2], [10, 10]) == pytest.approx((0.2, 0.2, 0.2))
    d1, lo1, hi1 = paired_difference([3], [1], [10])               # one cluster: no interval
    assert d1 == pytest.approx(0.2) and math.isnan(lo1) and math.isnan(hi1)
    assert all(math.isnan(v) for v in paired_difference([0], [0], [0]))
    # pairing: outcomes that move together cancel; the same marginal counts unpaired are wider
    rng = np.random.default_rng(1)
    base = rng.binomial(20, 0.5, 200)
    paired = paired_difference(base + (rng.random(200) < 0.1), base, np.full(200, 21))
    unpaired = paired_difference(base + (rng.random(200) < 0.1), rng.permutation(base),
                                 np.full(200, 21))
    assert paired[2] - paired[1] < 0.3 * (unpaired[2] - unpaired[1])


def test_identical_curves_groups_detectors_with_identical_counts():
    from types import SimpleNamespace
    from dptbd.evaluation.compare_report import identical_curves
    rng = np.random.default_rng(0)
    det = rng.integers(0, 5, (4, 5, 3))      # (trials, detectors, SNR)
    exc = rng.integers(0, 9, (4, 5, 2))
    det[:, 3] = det[:, 1]                     # detector 3 == detector 1 in every count ...
    exc[:, 3] = exc[:, 1]
    det[:, 2] = det[:, 0]                     # detector 2 == the float model's counts, but a
    exc[:, 2] = exc[:, 0]                     # fixed detector never joins a float curve
    agree = rng.random((4, 5, 4))             # agreement does not split a curve
    counts = {"detections": det, "exceed": exc, "agree_frac": agree, "agree_same": agree}
    names = ["float paper", "a", "b", "c", "d"]
    out = identical_curves(SimpleNamespace(counts=counts), names)
    assert out == {"float paper": "float paper", "a": "a = c", "c": None, "b": "b", "d": "d"}
    det[2, 3, 1] += 1                         # one count differs on one trial: separate curves
    out = identical_curves(SimpleNamespace(counts=counts), names)
    assert out["a"] == "a" and out["c"] == "c"


def test_clustered_wilson():
    # one cluster, or clusters with no extra spread: exactly Wilson
    p, lo, hi, deff = clustered_wilson([30], [100])
    assert (p, (lo, hi), deff) == (0.3, wilson_interval(30, 100), 1.0)
    p, lo, hi, deff = clustered_wilson([30, 30, 30], [100, 100, 100])
    assert deff == 1.0 and (lo, hi) == pytest.approx(wilson_interval(90, 300))
    # all-or-nothing clusters: the interval widens by the design effect (here ~ n_i)
    p, lo, hi, deff = clustered_wilson([100, 0, 100, 0], [100] * 4)
    assert p == 0.5 and deff > 50 and hi - lo > 0.5
    assert all(math.isnan(v) for v in clustered_wilson([0], [0]))


# ---- configurations ---------------------------------------------------------------------------

def test_cosine_lut():
    lut = cosine_weights(1)
    assert lut.shape == (10, 9) and np.all(lut[9] == 1) and np.all(lut[:, 4] == 1)
    assert lut[0, 0] == pytest.approx(1.0) and lut[0, 8] == pytest.approx(0.0)
    assert lut[1, 5] == pytest.approx(0.5) and lut[0, 1] == pytest.approx((1 + 0.5 ** 0.5) / 2)
    assert not DPConfig(weights=lut, weight_frac_bits=8).weights_exact


def test_identical_configurations_share_one_detector():
    spec = build_spec({
        "trials": 1, "sweep": {},
        "config": [{"name": "a", "input_bits": 8, "weight_frac_bits": 0},
                   {"name": "b", "input_bits": 8, "weight_frac_bits": 8, "rounding": "half_up",
                    "energy_bits": 20},               # paper LUT: F, rounding irrelevant; no saturation
                   {"name": "c", "input_bits": 8, "energy_bits": 9},     # may saturate
                   {"name": "d", "lut": "cosine", "weight_frac_bits": 2},
                   {"name": "e", "lut": "cosine", "weight_frac_bits": 2, "rounding": "half_up"}]})
    plan = make_plan(spec)
    det = dict(zip([f.name for f in spec.configs], plan.config_detector))
    assert det["a"] == det["b"] and len({det["a"], det["c"], det["d"], det["e"]}) == 4
    assert len(plan.floats) == 2  # paper and cosine
    assert spec.configs[0].cfg.energy_bits == 11  # "needed" for K = 6, 8-bit pixels
    assert spec.configs[2].saturates


def test_adc_mapping_puts_the_window_on_the_codes():
    for bits in (3, 8, 12):
        gain, offset = cmp.adc_mapping(bits, 30.0, 2.0)
        assert gain * (30.0 - 12.0) + offset == pytest.approx(0.0)           # mu - 6 sigma -> 0
        assert gain * (30.0 + 20.0) + offset == pytest.approx(2 ** bits)     # mu + 10 sigma -> 2**B
        assert gain * 2.0 == pytest.approx(2 ** bits / 16)                   # sigma in LSB


def test_sweep_grid_and_dedup_against_explicit_configs():
    # "mine" is the sweep point 5/8/0 (8 = the worst-case width for K = 6, 5-bit pixels):
    # it is listed once, marked as a sweep member
    spec = build_spec({"trials": 1,
                       "config": [{"name": "mine", "input_bits": 5, "weight_frac_bits": 0}],
                       "sweep": {"input_bits": [4, 5], "energy_headroom": [0, -1],
                                 "weight_frac_bits": [0]}})
    names = [f.name for f in spec.configs]
    assert names == ["mine", "4/7/0 truncate paper", "4/6/0 truncate paper", "5/7/0 truncate paper"]
    assert spec.configs[0].in_sweep and spec.configs[0].explicit
    assert spec.configs[0].cfg.energy_bits == 8 and not spec.configs[0].saturates
    assert spec.configs[2].saturates and not spec.configs[2].explicit


# ---- the Monte Carlo -----------------------------------------------------------------------------

def test_one_and_two_workers_give_identical_counts():
    spec = build_spec(SMALL)
    one = run_compare(spec, workers=1)
    two = run_compare(spec, workers=2)
    assert one.counts.keys() == two.counts.keys()
    for key in one.counts:
        assert np.array_equal(one.counts[key], two.counts[key]), key
    # ... and the chunking does not matter either
    three = run_compare(build_spec(dict(SMALL, chunk=5)), workers=1)
    for key in one.counts:
        assert np.array_equal(one.counts[key], three.counts[key]), key


def test_chunk_equals_whole_scenes_quantised_and_first_level_counts():
    spec = build_spec(SMALL)
    plan = make_plan(spec)
    fast = cmp._chunk(plan, 2, 5)
    frames = [scenes.table1_scenario(s, spec.velocity, frames=spec.frames, size=spec.size,
                                     seed=spec.seed, trials=3, first_trial=2,
                                     dtype=np.float32).frames for s in spec.snr]
    noise = scenes.make_noise((spec.size, spec.size), spec.frames, mu=spec.mu, sigma=spec.sigma,
                              seed=spec.seed, trials=3, first_trial=2, dtype=np.float32)
    slow = measure_frames(plan, frames, noise, first_trial=2)
    for key in fast:
        assert np.array_equal(fast[key], slow[key]), key
    # the float detector's counts are metrics.first_level_counts of the compare rule's masks
    # (candidate_indices: exactly n per image, the tie-break keyed by trial and segment)
    truth = scenes.table1_scenario(1.0, spec.velocity, frames=spec.frames, size=spec.size,
                                   noise=False).truth[0]
    energy = run_float(frames[1], spec.base_cfg).energy
    n_seg = len(plan.ends)
    keys = cmp.image_keys(spec.seed, 2, 3, n_seg).reshape(3, n_seg)
    for n, images in enumerate(energy):
        masks = np.zeros(images.shape, bool)
        for s, image in enumerate(images):
            masks[s].flat[cmp.candidate_indices(image, spec.candidate_count, int(keys[n, s]))] = True
        assert np.all(masks.sum(axis=(1, 2)) == spec.candidate_count)
        ref = first_level_counts(masks, truth.pixel[plan.ends][:, None],
                                 truth.visible[plan.ends][:, None])
        assert fast["detections"][n, 0, 1] == ref.detections
        assert fast["false_points"][n, 0, 1] == ref.false_points


def test_select_kernel_equals_the_plain_rule_under_heavy_ties():
    # small-integer images (many pixels share the n-th largest value) and constant images:
    # the numba kernel keeps exactly min(n, H*W) pixels, the same ones as candidate_indices
    rng = np.random.default_rng(0)
    n_seg, h, w = 3, 8, 8
    near = np.zeros((n_seg, h * w), bool)
    near[:, 10:13] = True
    for case in range(120):
        energy = rng.integers(0, rng.integers(1, 6), (2 * n_seg, h * w)).astype(np.uint32)
        if case % 7 == 0:
            energy[:] = 5
        count = int(rng.integers(1, 70))
        keys = cmp.image_keys(7, 3, 2, n_seg)
        idx = np.zeros((len(energy), count), np.int64)
        n_cand = np.zeros(len(energy), np.int64)
        hit = np.zeros(len(energy), np.bool_)
        near_count = np.zeros(len(energy), np.int64)
        cmp._select(energy, cmp.nth_largest(energy, count), keys, near, n_seg, count, idx,
                    n_cand, hit, near_count)
        for i in range(len(energy)):
            ref = cmp.candidate_indices(energy[i].reshape(h, w), count, int(keys[i]))
            assert n_cand[i] == len(ref) == min(count, h * w)
            assert np.array_equal(idx[i, :n_cand[i]], ref)
            assert near_count[i] == near[i % n_seg][ref].sum() and hit[i] == (near_count[i] > 0)
            # every pixel kept is >= every pixel dropped
            kept = np.zeros(h * w, bool)
            kept[ref] = True
            if 0 < kept.sum() < h * w:
                assert energy[i][kept].min() >= energy[i][~kept].max()


def test_tie_break_is_keyed_by_the_scene_and_spread_over_the_frame():
    flat = np.zeros((16, 16))
    keys = cmp.image_keys(2024, 0, 200, 8)
    assert len(np.unique(keys)) == keys.size                       # one key per image
    assert np.array_equal(keys[8:16], cmp.image_keys(2024, 1, 1, 8))  # a trial's keys, any chunk
    assert not np.array_equal(keys, cmp.image_keys(2025, 0, 200, 8))  # seeded
    rows = np.concatenate([cmp.candidate_indices(flat, 8, int(k)) // 16 for k in keys])
    # a constant image: the 8 kept pixels are spread over the frame, not the first rows
    # (raster order would keep row 0 only); expected fraction in the top half 0.5
    assert 0.46 < np.mean(rows < 8) < 0.54
    assert np.array_equal(cmp.candidate_indices(flat, 8, 5), cmp.candidate_indices(flat, 8, 5))


def test_every_detector_runs_at_exactly_n_candidates_per_image():
    # 2- and 3-bit ADCs put sigma at 0.25 / 0.5 LSB: E takes a handful of values and many
    # pixels tie at the n-th largest. The old rule (E above the (n+1)-th largest,
    # segmentation.candidate_mask) leaves those configurations far fewer candidates than
    # float; the compare rule gives every detector exactly n per image, with and without
    # the target, so the noise-only false points per frame are n for everyone.
    spec = build_spec(dict(SMALL, config=[{"name": "two", "input_bits": 2},
                                          {"name": "three", "input_bits": 3},
                                          {"name": "eight", "input_bits": 8}]))
    res = run_compare(spec, workers=1)
    n = spec.candidate_count
    images = spec.trials * len(res.plan.ends)
    assert n == 5 and res.plan.n_detectors == 4
    assert np.all(res.counts["candidates"] == n * len(res.plan.ends))   # every trial, SNR, detector
    noise_fp = res.counts["false_points"][:, :, -1].sum(axis=0) / images
    assert np.all(noise_fp == n)
    # the old rule on the same noise-only scenes: the coarse detector keeps fewer than n
    from dptbd.model.fast import run_fixed_fast
    plan = res.plan
    noise = scenes.make_noise((spec.size, spec.size), spec.frames, mu=spec.mu, sigma=spec.sigma,
                              seed=spec.seed, trials=spec.trials, dtype=np.float32)
    bits, gain, offset = plan.adcs[plan.fixed_adc[0]]
    assert bits == 2
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        energy = run_fixed_fast(scenes.quantise(noise, bits, gain=gain, offset=offset),
                                plan.fixed[0], threads=1).energy
    old = candidate_mask(energy, n).sum(axis=(-1, -2))
    assert old.mean() < 0.8 * n


def test_agreement_is_one_when_fixed_point_cannot_differ():
    # integer-valued scenes, an identity ADC (gain 1, offset 0, 8 bits hold every value),
    # a LUT exact in F bits and a B_E that cannot saturate: the fixed model computes the
    # float model's numbers exactly, so the candidate lists are identical
    spec = build_spec({
        "trials": 3, "size": 16, "frames": 12, "segment_frames": 4, "false_alarm_rate": 0.02,
        "snr": [2.0, 3.0], "mu": 100.0, "sigma": 3.0, "velocity": [1.0, 1.0], "sweep": {},
        "config": [{"name": "exact", "input_bits": 8, "energy_bits": 16, "adc_gain": 1.0,
                    "adc_offset": 0.0},
                   {"name": "exact plain", "input_bits": 8, "energy_bits": 12, "lut": "plain",
                    "adc_gain": 1.0, "adc_offset": 0.0, "weight_frac_bits": 0}]})
    plan = make_plan(spec)
    noise = np.rint(scenes.make_noise((16, 16), 12, mu=100.0, sigma=3.0, seed=5, trials=3))
    frames = [noise + np.rint(4.0 * s) * np.asarray(scenes.table1_scenario(
        1.0, (1.0, 1.0), frames=12, size=16, mu=0.0, sigma=1.0, noise=False).frames > 0)
        for s in spec.snr]
    out = measure_frames(plan, [f.astype(np.float32) for f in frames], noise.astype(np.float32))
    n_seg = len(plan.ends)
    for d in plan.config_detector:
        assert np.all(out["agree_same"][:, d] == n_seg)
        assert np.all(out["agree_frac"][:, d] == n_seg)
        ref = plan.fixed_float[d - len(plan.floats)]
        assert np.array_equal(out["detections"][:, d], out["detections"][:, ref])
        assert np.array_equal(out["exceed"][:, d], out["exceed"][:, ref])
    assert out["candidates"].sum() > 0


# ---- the command: bad input before any work, files out --------------------------------------

def _parse(argv):
    from dptbd.commands import compare as command
    parser = argparse.ArgumentParser()
    command.add_arguments(parser)
    return command, parser.parse_args(argv)


def _toml(path, text):
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("toml, argv, match", [
    ("frobnicate = 1\n", [], r"unknown parameter\(s\) \['frobnicate'\]"),
    ("[[config]]\ninput_bits = 8\nwidht = 3\n", [], r"unknown configuration key\(s\) \['widht'\]"),
    ("[[config]]\nsegment_frames = 8\n", [], "run-level parameters"),
    ("[[config]]\ninput_bits = 17\n", [], r"input_bits must be in \[1, 16\]"),
    ("[[config]]\ninput_bits = 8\nenergy_bits = 6\n", [], r"energy_bits must be in \[input_bits=8"),
    ("[[config]]\nrounding = 'nearest'\n", [], "rounding must be one of"),
    ("[sweep]\ninput_bits = [8]\nenergy_headroom = [-6]\n", [], r"energy_bits must be in \[input_bits=8"),
    ("", ["--snr"], r"snr must hold at least 2 value\(s\), got \[\] \(an empty list\)"),
    ("", ["--snr", "2.0", "1.5"], r"snr must be strictly increasing, but snr\[1\] = 1.5 <= snr\[0\] = 2"),
    ("snr = []\n", [], "an empty list"),
    ("", ["--trials", "0"], r"trials must be in \[1, inf\], got 0"),
    ("", ["--workers", "0"], "--workers must be >= 1"),
])
def test_bad_input_is_refused_before_any_work(tmp_path, monkeypatch, toml, argv, match):
    def boom(*a, **k):
        raise AssertionError("work started")
    monkeypatch.setattr(cmp, "run_compare", boom)
    monkeypatch.setattr(cmp, "make_plan", boom)
    out = tmp_path / "out"
    command, args = _parse(["--config", _toml(tmp_path / "c.toml", toml), "--out", str(out)] + argv)
    with pytest.raises(ConfigError, match=match):
        command.main(args)
    assert not out.exists()


def test_missing_file_and_existing_output_are_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(cmp, "run_compare", lambda *a, **k: pytest.fail("work started"))
    command, args = _parse(["--config", str(tmp_path / "nope.toml")])
    with pytest.raises(FileNotFoundError, match="no such file"):
        command.main(args)
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "mine.txt").write_text("keep")
    command, args = _parse(["--out", str(tmp_path / "out")])
    with pytest.raises(FileExistsError, match="--force"):
        command.main(args)


def test_command_writes_tables_json_and_figures(tmp_path, capsys):
    toml = """
trials = 4
seed = 3
snr = [1.5, 2.5, 3.5]
size = 16
frames = 12
segment_frames = 4
false_alarm_rate = 0.02
chunk = 2
bootstrap = 40
thresholds = [2.0, 3.0, 4.0]
[[config]]
name = "exact-ish"
input_bits = 10
[sweep]
input_bits = [4, 6]
"""
    out = tmp_path / "out"
    command, args = _parse(["--config", _toml(tmp_path / "c.toml", toml), "--out", str(out),
                            "--workers", "1", "--no-progress"])
    assert command.main(args) == 0
    from dptbd.evaluation.compare_report import DATA_FILES, FIGURES
    for name in DATA_FILES + FIGURES:
        assert (out / name).stat().st_size > 0, name
    summary = json.loads((out / "compare_summary.json").read_text())
    assert summary["run"]["trials"] == 4 and len(summary["configs"]) == 3
    assert summary["run"]["candidate_count"] == 5 and summary["run"]["segments_per_trial"] == 3
    assert {r["verdict"] for r in summary["configs"]} <= {"within", "beyond", "undecided"}
    for name in FIGURES:
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
    printed = capsys.readouterr().out
    assert "loss @Pd=0.5" in printed and "loss @Pd=0.8" in printed

    import csv
    def rows(name):
        with (out / name).open() as fh:
            return list(csv.DictReader(fh))
    detectors = summary["detectors"]
    assert detectors[0] == "float paper" and len(detectors) == 4   # float + 3 fixed behaviours
    pd = rows("compare_pd.csv")
    assert len(pd) == len(detectors) * 3
    for r in pd:
        p, lo, hi = float(r["pd"]), float(r["pd_lo"]), float(r["pd_hi"])
        assert 0 <= lo <= p <= hi <= 1
        assert float(r["pd"]) == int(r["detections"]) / int(r["opportunities"])
        assert int(r["opportunities"]) == 4 * 3       # trials x segments (target always visible)
        assert float(r["candidates_per_frame"]) == 5.0  # exactly n for every detector and SNR
        assert 0 <= float(r["false_points_per_frame"]) <= 5.0
        if r["detector"] == "float paper":
            assert float(r["delta_pd"]) == 0.0
    pfa = rows("compare_pfa.csv")
    assert len(pfa) == len(detectors) * 3
    for d in detectors:
        curve = [float(r["pfa"]) for r in pfa if r["detector"] == d]
        assert len(curve) == 3 and curve == sorted(curve, reverse=True)   # a threshold sweep
    configs = rows("compare_configs.csv")
    # K = 4 here: the worst-case B_E is B_in + 2; F defaults to 8
    assert [r["name"] for r in configs] == ["exact-ish", "4/6/8 truncate paper",
                                            "6/8/8 truncate paper"]
    assert [r["widths"] for r in configs] == ["10/12/8", "4/6/8", "6/8/8"]
    assert all(float(r["noise_candidates_per_frame"]) == 5.0 for r in configs)
    for r, j in zip(configs, summary["configs"]):
        assert r["verdict"] == j["verdict"] and r["name"] in printed
        assert r["verdict"] in printed.split(r["name"] + " |", 1)[1].split("\n", 1)[0]
        for tag in ("pd50", "pd80"):
            lo, v, hi = (j[f"loss_{tag}_{k}"] for k in ("lo", "db", "hi"))
            if all(isinstance(x, (int, float)) for x in (lo, v, hi)):
                assert lo <= v <= hi
    choice = summary["choice"]
    by_name = {r["name"]: r for r in summary["configs"]}
    for key, ok in (("within", {"within"}), ("not_beyond", {"within", "undecided"})):
        if choice[key] is not None:
            assert by_name[choice[key]]["in_sweep"] and by_name[choice[key]]["verdict"] in ok
        else:
            assert not any(r["in_sweep"] and r["verdict"] in ok for r in summary["configs"])
    # the same folder again needs --force
    with pytest.raises(FileExistsError):
        command.main(_parse(["--config", str(tmp_path / "c.toml"), "--out", str(out)])[1])


def test_hardware_cost_is_cached(tmp_path):
    calls = []

    class Cells:
        lut4, dff, bram, carry = 100, 50, 3, 20

    class Result:
        cells = Cells()
        fmax_median_mhz = 101.0
        fmaxes_mhz = (99.0, 101.0, 103.0)
        fits = True
        utilisation = {"ICESTORM_LC": (140, 7680)}
        yosys_seconds = verilog_seconds = 1.0
        runs = ()

    def fake(cfg, **kw):
        calls.append((cfg, kw))
        return Result()

    cfg = DPConfig(width=16, height=16)
    a = sweep.hardware_cost(cfg, cache_dir=tmp_path, synthesize=fake, tools={"yosys": "x"})
    b = sweep.hardware_cost(cfg, cache_dir=tmp_path, synthesize=fake, tools={"yosys": "x"})
    c = sweep.hardware_cost(cfg.replace(energy_bits=12), cache_dir=tmp_path, synthesize=fake,
                            tools={"yosys": "x"})
    assert len(calls) == 2 and not a.cached and b.cached and not c.cached
    # a changed gateware source is a different key: synthesised again, then cached
    d = sweep.hardware_cost(cfg, cache_dir=tmp_path, synthesize=fake, tools={"yosys": "x"},
                            gateware="changed")
    assert len(calls) == 3 and not d.cached
    assert sweep.hardware_cost(cfg, cache_dir=tmp_path, synthesize=fake, tools={"yosys": "x"},
                               gateware="changed").cached
    assert len(sweep.gateware_hash()) == 24
    assert (b.lut4, b.ff, b.bram, b.fmax_median_mhz, b.logic_cells) == (100, 50, 3, 101.0, 140)
    assert calls[0][1]["variant"] == "core" and calls[0][1]["device"] == "hx8k"


# ---- reproducibility, the command line's exit status, synthesis at --synth-size ------------------

def test_same_seed_same_summary_other_seed_other_counts():
    from dptbd.evaluation.compare_report import summarise
    spec = build_spec(SMALL)
    a = summarise(run_compare(spec, workers=1))
    b = summarise(run_compare(spec, workers=2))
    for key in ("pd", "pfa", "configs", "choice", "resolution"):
        assert json.dumps(a[key], default=str) == json.dumps(b[key], default=str), key
    other = run_compare(build_spec(dict(SMALL, seed=8)), workers=1)
    first = run_compare(spec, workers=1)
    assert not np.array_equal(first.counts["exceed"], other.counts["exceed"])


@pytest.mark.parametrize("argv, names", [
    (["--trials", "0"], ["trials", "[1, inf]"]),
    (["--snr"], ["snr", "at least 2"]),
    (["--snr", "2.0", "2.0"], ["snr", "strictly increasing"]),
    (["--bootstrap", "-1"], ["bootstrap", "[0, 1000000]"]),
    (["--workers", "0"], ["--workers", ">= 1"]),
    (["--synth", "--synth-size", "2"], ["--synth-size", "[3, 4096]"]),
    (["--synth", "--synth-seeds", "1", "1"], ["--synth-seeds", "distinct"]),
    (["--synth", "--device", "xc7"], ["--device", "hx8k"]),
])
def test_cli_exits_2_naming_the_parameter(tmp_path, monkeypatch, capsys, argv, names):
    from dptbd import cli
    monkeypatch.setattr(cmp, "run_compare", lambda *a, **k: pytest.fail("work started"))
    out = tmp_path / "out"
    assert cli.main(["compare", "--out", str(out)] + argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("dptbd compare: error:")
    for name in names:
        assert name in err
    assert not out.exists()


def test_cli_exits_2_on_unknown_keys_and_impossible_widths(tmp_path, monkeypatch, capsys):
    from dptbd import cli
    monkeypatch.setattr(cmp, "run_compare", lambda *a, **k: pytest.fail("work started"))
    for text, names in [("[[config]]\nenergy_bitz = 9\n", ["energy_bitz", "allowed"]),
                        ("[sweep]\ninput_bits = [0]\n", ["input_bits", "[1, 16]"]),
                        ("[[config]]\ninput_bits = 8\nweight_frac_bits = -1\n",
                         ["weight_frac_bits"])]:
        path = _toml(tmp_path / "c.toml", text)
        assert cli.main(["compare", "--config", path, "--out", str(tmp_path / "o")]) == 2
        err = capsys.readouterr().err
        for name in names:
            assert name in err, (text, err)
        assert not (tmp_path / "o").exists(), "an output folder was created before the error"


def test_cli_help_quotes_the_real_defaults():
    command, _ = _parse([])
    parser = argparse.ArgumentParser()
    command.add_arguments(parser)
    helps = {a.dest: a.help for a in parser._actions}
    run = cmp.DEFAULT_RUN
    assert f"default {run['trials']}," in helps["trials"]
    assert f"default {run['seed']}," in helps["seed"]
    assert f"default {run['bootstrap']}," in helps["bootstrap"]
    assert "default " + " ".join(f"{x:g}" for x in run["snr"]) + "," in helps["snr"]


def test_synthesis_runs_at_synth_size_and_records_failures(monkeypatch):
    from dptbd.commands import compare as command
    from dptbd.hw.flow.synth import SynthToolError
    spec = build_spec(dict(SMALL, config=SMALL["config"][:2]))
    seen = []

    def fake(cfg, **kw):
        seen.append(cfg)
        if cfg.input_bits == 4:
            raise SynthToolError("nextpnr died")
        return sweep.HardwareCost(lut4=10, ff=5, bram=1, carry=2, fmax_median_mhz=100.0,
                                  fmax_mhz=(100.0,), fits=True, logic_cells=12, device="hx8k",
                                  package="ct256", variant="core", width=cfg.width,
                                  height=cfg.height, seconds=1.0)

    monkeypatch.setattr(sweep, "hardware_cost", fake)
    _, args = _parse(["--synth", "--synth-size", "128", "--no-progress"])
    hw = command.synthesise_all(spec, args, workers=1)
    assert [(c.width, c.height) for c in seen] == [(128, 128)] * 2
    assert [c.input_bits for c in seen] == [8, 4]
    assert hw["eight"].lut4 == 10 and hw["four"].lut4 is None and "nextpnr died" in hw["four"].error
    assert spec.configs[0].cfg.width == 16  # the Monte Carlo's configuration is unchanged


def test_the_toml_examples_in_docs_compare_md_are_valid():
    import pathlib
    import re
    import tomllib
    text = (pathlib.Path(__file__).resolve().parents[2] / "docs" / "compare.md").read_text()
    blocks = re.findall(r"```toml\n(.*?)```", text, re.S)
    assert len(blocks) >= 2
    specs = [build_spec(tomllib.loads(b)) for b in blocks]
    default = build_spec({})
    assert [f.name for f in specs[0].configs] == [f.name for f in default.configs]
    assert len(specs[1].configs) == 1 + 3 + 4 * 2 and specs[1].trials == 2000
