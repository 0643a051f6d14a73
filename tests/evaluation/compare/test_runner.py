"""The Monte Carlo (:mod:`dptbd.evaluation.compare.runner`): counts independent of the worker
count and the chunking, a chunk equal to whole scenes quantised, exactly n candidates for
every detector, agreement where fixed point cannot differ, reproducible summaries."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from dptbd.scenes import synthetic as scenes
from dptbd.evaluation.compare import runner, selection
from dptbd.evaluation.compare.plan import make_plan
from dptbd.evaluation.compare.report import summarise
from dptbd.evaluation.compare.runner import measure_frames, run_compare
from dptbd.evaluation.compare.spec import build_spec
from dptbd.evaluation.execution import ExecutionError
from dptbd.evaluation.metrics import first_level_counts
from dptbd.model.reference import run_float
from dptbd.model.segmentation import candidate_mask


def test_one_and_two_workers_give_identical_counts_and_summaries(small_compare):
    """The same seed: the same counts and summary on one and on two workers, and with
    another chunking; another seed: other counts."""
    spec = build_spec(small_compare)
    one = run_compare(spec, workers=1)
    two = run_compare(spec, workers=2)
    assert one.counts.keys() == two.counts.keys()
    for key in one.counts:
        assert np.array_equal(one.counts[key], two.counts[key]), key
    a, b = summarise(one), summarise(two)
    for key in ("pd", "pfa", "configs", "choice", "resolution"):
        assert json.dumps(a[key], default=str) == json.dumps(b[key], default=str), key
    # ... and the chunking does not matter either
    three = run_compare(build_spec(dict(small_compare, chunk=5)), workers=1)
    for key in one.counts:
        assert np.array_equal(one.counts[key], three.counts[key]), key
    other = run_compare(build_spec(dict(small_compare, seed=8)), workers=1)
    assert not np.array_equal(one.counts["exceed"], other.counts["exceed"])


def test_chunk_equals_whole_scenes_quantised_and_first_level_counts(small_compare):
    spec = build_spec(small_compare)
    plan = make_plan(spec)
    fast = runner._chunk(plan, 2, 5)
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
    keys = selection.image_keys(spec.seed, 2, 3, n_seg).reshape(3, n_seg)
    for n, images in enumerate(energy):
        masks = np.zeros(images.shape, bool)
        for s, image in enumerate(images):
            masks[s].flat[selection.candidate_indices(image, spec.candidate_count, int(keys[n, s]))] = True
        assert np.all(masks.sum(axis=(1, 2)) == spec.candidate_count)
        ref = first_level_counts(masks, truth.pixel[plan.ends][:, None],
                                 truth.visible[plan.ends][:, None])
        assert fast["detections"][n, 0, 1] == ref.detections
        assert fast["false_points"][n, 0, 1] == ref.false_points


def test_every_detector_runs_at_exactly_n_candidates_per_image(small_compare):
    # 2- and 3-bit ADCs put sigma at 0.25 / 0.5 LSB: E takes a handful of values and many
    # pixels tie at the n-th largest. The old rule (E above the (n+1)-th largest,
    # segmentation.candidate_mask) leaves those configurations far fewer candidates than
    # float; the compare rule gives every detector exactly n per image, with and without
    # the target, so the noise-only false points per frame are n for everyone.
    spec = build_spec(dict(small_compare, config=[{"name": "two", "input_bits": 2},
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


def test_worker_count_out_of_range_is_refused():
    with pytest.raises(ExecutionError, match=r"^workers must be an integer in \[1, 1024\], got 0$"):
        run_compare(build_spec({"trials": 1, "sweep": {}, "config": [{"input_bits": 4}]}),
                    workers=0)


@pytest.mark.parametrize("tie_rule", ["gateware", "gateware-bins"])
def test_gateware_rules_one_and_two_workers_identical_at_most_n(small_compare, tie_rule):
    # 2- and 3-bit ADCs tie heavily: under the gateware rules they keep fewer than n
    # candidates; the float model (no ties) keeps exactly n; the counts do not depend on
    # the workers
    spec = build_spec(dict(small_compare, tie_rule=tie_rule,
                           config=[{"name": "two", "input_bits": 2},
                                   {"name": "three", "input_bits": 3},
                                   {"name": "eight", "input_bits": 8}]))
    one = run_compare(spec, workers=1)
    two = run_compare(spec, workers=2)
    for key in one.counts:
        assert np.array_equal(one.counts[key], two.counts[key]), key
    per_trial = spec.candidate_count * len(one.plan.ends)
    cand = one.counts["candidates"]
    assert np.all(cand[:, 0] == per_trial)                      # the float model
    assert np.all(cand <= per_trial) and cand[:, 1].mean() < 0.8 * per_trial   # 2 bits
    # the random rule on the same scenes gives every detector exactly n
    random = run_compare(build_spec(dict(small_compare, config=spec_configs(spec))), workers=1)
    assert np.all(random.counts["candidates"] == per_trial)


def spec_configs(spec) -> list[dict]:
    """The [[config]] tables of a spec's configurations (name and input bits)."""
    return [{"name": f.name, "input_bits": f.cfg.input_bits} for f in spec.configs]


def test_gateware_bins_runs_each_histogram_with_its_own_shift(small_compare):
    # the same DP bits with s = 0 and s = 3: two detectors under gateware-bins, each with the
    # counts of a run of that configuration alone (no shared s)
    configs = [{"name": "s0", "input_bits": 8, "histogram_shift": 0},
               {"name": "s3", "input_bits": 8, "histogram_shift": 3}]
    both = run_compare(build_spec(dict(small_compare, tie_rule="gateware-bins", config=configs)),
                       workers=1)
    assert both.plan.n_detectors == 3 and [c.bin_shift for c in both.plan.fixed] == [0, 3]
    for d, cfg in ((1, configs[0]), (2, configs[1])):
        alone = run_compare(build_spec(dict(small_compare, tie_rule="gateware-bins",
                                            config=[cfg])), workers=1)
        for key in ("detections", "false_points", "candidates", "agree_same"):
            assert np.array_equal(both.counts[key][:, d], alone.counts[key][:, 1]), key
    # s = 3 (bins 8 values wide) ties more, so it keeps fewer candidates than s = 0
    assert both.counts["candidates"][:, 2].sum() < both.counts["candidates"][:, 1].sum()


def test_equal_pfa_thresholds_are_the_noise_quantile_and_free_of_the_chunking(small_compare):
    from dptbd.evaluation.pfa import pixel_threshold

    spec = build_spec(dict(small_compare, pfa=[0.01, 0.002]))
    result = run_compare(spec, workers=1)
    rows = summarise(result)["equal_pfa"]
    names = result.plan.detector_names()
    assert [(r["detector"], r["pfa"], r["snr"]) for r in rows] == [
        (n, p, s) for n in names for p in (0.01, 0.002) for s in spec.snr]
    # the float detector (index 0), independently: every noise-only E of the run
    noise = scenes.make_noise((spec.size, spec.size), spec.frames, mu=spec.mu, sigma=spec.sigma,
                              seed=spec.seed, trials=spec.trials, dtype=np.float32)
    cfg = result.plan.floats[0]
    e_noise = run_float(noise, cfg).energy
    plan = result.plan
    for p in (0.01, 0.002):
        thr = pixel_threshold(e_noise, p)
        mine = [r for r in rows if r["detector"] == names[0] and r["pfa"] == p]
        above = int((e_noise > thr).sum())
        assert above <= int(p * e_noise.size)
        assert all(r["threshold"] == thr and r["noise_false_alarms"] == above
                   and r["noise_pixels"] == e_noise.size
                   and r["false_alarms_per_map"] == above / (spec.trials * len(plan.ends)) for r in mine)
        for r, snr in zip(mine, spec.snr):
            frames = scenes.table1_scenario(snr, spec.velocity, frames=spec.frames, size=spec.size,
                                            seed=spec.seed, trials=spec.trials,
                                            dtype=np.float32).frames
            e = run_float(frames, cfg).energy
            hits = int(np.sum(np.any((e > thr) & plan.near[None], axis=(2, 3))))
            assert (r["detections"], r["opportunities"]) == (hits, spec.trials * int(plan.visible.sum()))
    chunked = summarise(run_compare(build_spec(dict(small_compare, pfa=[0.01, 0.002], chunk=5)),
                                    workers=1))["equal_pfa"]
    assert json.dumps(chunked) == json.dumps(rows)
