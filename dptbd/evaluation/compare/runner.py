"""The Monte Carlo of ``dptbd compare``: every detector on one chunk of trials, and the
whole run in chunks on dask workers (:func:`run_compare`, :mod:`dptbd.evaluation.execution`)."""

from __future__ import annotations

import dataclasses
import functools
import math
import time
import warnings
from typing import Sequence

import numpy as np

from dptbd.config import EnergyWidthWarning
from dptbd.scenes import synthetic as scenes
from dptbd.evaluation.compare.plan import Plan, make_plan
from dptbd.evaluation.compare.selection import _Candidates, _candidates, _same_points, image_keys
from dptbd.evaluation.compare.spec import CompareSpec
from dptbd.evaluation.execution import (cluster_workers, default_workers, job_execution,
                                        map_tasks, warmed)

__all__ = ["measure_frames", "CompareResult", "run_compare", "default_workers", "check_rtl",
           "merge_noise_top"]


def _exceedances(energy: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """Per trial: pixels (over all segments) with E strictly above each level."""
    flat = np.sort(energy.reshape(energy.shape[0], -1), axis=1)
    n = flat.shape[1]
    return np.stack([n - np.searchsorted(row, levels, side="right") for row in flat])


def _evaluate(plan: Plan, float_frames: np.ndarray, codes: Sequence[np.ndarray],
              with_target: bool, out: dict, kind: int, first: int) -> None:
    """Run every detector on one batch (one SNR, or noise only) of trials ``first ..`` and
    store per-trial counts."""
    from dptbd.model.fast import run_fixed_fast
    from dptbd.model.fast.floating import run_float_fast

    n_trials = float_frames.shape[0]
    n_seg = len(plan.ends)
    keys = image_keys(plan.spec.seed, first, n_trials, n_seg)
    refs = []
    for i, cfg in enumerate(plan.floats):
        res = run_float_fast(float_frames, cfg)
        cand = _candidates(res.energy, res.direction, plan, keys)
        refs.append(cand)
        _store(out, kind, i, cand, None, with_target, n_trials, n_seg)
        _store_equal_pfa(out, plan, kind, i, res.energy, with_target)
        if not with_target:
            out["exceed"][:, i] = _exceedances(res.energy, plan.levels[i])
    for b, cfg in enumerate(plan.fixed):
        d = len(plan.floats) + b
        if plan.rtl:  # the gateware accumulates, every word checked (docs/compare.md)
            from dptbd.sim.rtl.trials import accumulate_trials
            scene = (f"SNR {plan.spec.snr[kind]:g}" if with_target else "noise only")
            res = accumulate_trials(
                plan.rtl[b], codes[plan.fixed_adc[b]], first_trial=first,
                label=f"configuration {plan.detector_names()[d]!r}, scene {scene}: ")
            out["rtl"] = out["rtl"] + res.tally
        else:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", EnergyWidthWarning)
                res = run_fixed_fast(codes[plan.fixed_adc[b]], cfg, threads=1)
        cand = _candidates(res.energy, res.direction, plan, keys, cfg)
        _store(out, kind, d, cand, refs[plan.fixed_float[b]], with_target, n_trials, n_seg)
        _store_equal_pfa(out, plan, kind, d, res.energy, with_target)
        if not with_target:
            out["exceed"][:, d] = _exceedances(res.energy, plan.levels[d])


def _store_equal_pfa(out, plan: Plan, kind: int, d: int, energy: np.ndarray, with_target: bool) -> None:
    """The equal-Pfa operating point's raw material (``docs/compare.md``): with a target, the
    largest E within the detection gate of every segment (``-inf`` where the target is not
    visible); on noise only, the chunk's :attr:`Plan.noise_keep` largest E (all of them when
    fewer), from which :func:`merge_noise_top` and the report set the thresholds exactly."""
    e = np.asarray(energy)
    if with_target:
        gated = np.where(plan.near[None], e.astype(np.float64), -np.inf)
        out["near_max"][:, d, kind] = gated.max(axis=(2, 3))
    else:
        flat = e.reshape(-1)
        keep = min(plan.noise_keep, flat.size)
        out["noise_top"][d] = np.sort(np.partition(flat, flat.size - keep)[flat.size - keep:])


def merge_noise_top(parts: Sequence[list], keep: int) -> list[np.ndarray]:
    """Per detector, the ``keep`` largest noise-only E of all chunks, ascending: each chunk
    kept its own ``keep`` largest, so these are exactly the largest of the whole run."""
    out = []
    for d in range(len(parts[0])):
        v = np.sort(np.concatenate([p[d] for p in parts]))
        out.append(v[max(0, v.size - keep):])
    return out


def _store(out, kind, d, cand: _Candidates, ref: _Candidates | None, with_target, n_trials, n_seg):
    per = (n_trials, n_seg)
    n_cand = cand.n_cand.reshape(per)
    out["candidates"][:, d, kind] = n_cand.sum(axis=1)
    if with_target:
        out["detections"][:, d, kind] = cand.hit.reshape(per).sum(axis=1)
        out["false_points"][:, d, kind] = (cand.n_cand - cand.near_count).reshape(per).sum(axis=1)
    else:
        out["false_points"][:, d, kind] = n_cand.sum(axis=1)
    if ref is None:  # a float model against itself
        out["agree_frac"][:, d, kind] = n_seg
        out["agree_same"][:, d, kind] = n_seg
        return
    same = np.zeros(len(cand.n_cand), np.int64)
    _same_points(cand.idx, cand.n_cand, cand.direction, ref.idx, ref.n_cand, ref.direction, same)
    larger = np.maximum(cand.n_cand, ref.n_cand)
    frac = np.where(larger == 0, 1.0, same / np.maximum(larger, 1))
    identical = (same == cand.n_cand) & (cand.n_cand == ref.n_cand)
    out["agree_frac"][:, d, kind] = frac.reshape(per).sum(axis=1)
    out["agree_same"][:, d, kind] = identical.reshape(per).sum(axis=1)


def _empty_out(plan: Plan, n: int) -> dict:
    d, s = plan.n_detectors, len(plan.spec.snr)
    out = {
        "detections": np.zeros((n, d, s), np.int64),
        "false_points": np.zeros((n, d, s + 1), np.int64),
        "candidates": np.zeros((n, d, s + 1), np.int64),
        "agree_frac": np.zeros((n, d, s + 1), np.float64),
        "agree_same": np.zeros((n, d, s + 1), np.int64),
        "exceed": np.zeros((n, d, len(plan.spec.thresholds)), np.int64),
        "near_max": np.full((n, d, s, len(plan.ends)), -np.inf),
        "noise_top": [np.zeros(0)] * d,  # not per trial: merged over chunks by run_compare
    }
    if plan.rtl:  # not per trial: summed over chunks by run_compare, not concatenated
        from dptbd.sim.rtl.trials import RTLTally
        out["rtl"] = RTLTally()
    return out


def _chunk(plan: Plan, first: int, stop: int) -> dict:
    """Trials ``first .. stop - 1``: every SNR and the noise-only scene, every detector.

    The noise is drawn once and the target added per SNR; the ADC codes of the noise are
    computed once per ADC and only the target's pixels re-quantised per SNR. This gives the
    same frames as ``table1_scenario(...).frames`` and ``quantise`` of them
    (``tests/evaluation/compare/test_runner.py`` checks it against :func:`measure_frames`).
    """
    spec = plan.spec
    n = stop - first
    noise = scenes.make_noise((spec.size, spec.size), spec.frames, mu=spec.mu, sigma=spec.sigma,
                              seed=spec.seed, trials=n, first_trial=first, dtype=np.float32)
    out = _empty_out(plan, n)
    t, rows, cols = plan.target_t, plan.target_px[:, 0], plan.target_px[:, 1]
    codes = [scenes.quantise(noise, bits, gain=g, offset=o) for bits, g, o in plan.adcs]
    background = noise[:, t, rows, cols].copy()
    background_codes = [c[:, t, rows, cols].copy() for c in codes]
    for kind, amp in enumerate(plan.amplitudes):
        lit = background + np.float32(amp)  # as make_scene draws a target (float32)
        noise[:, t, rows, cols] = lit
        for (bits, g, o), c in zip(plan.adcs, codes):
            c[:, t, rows, cols] = scenes.quantise(lit, bits, gain=g, offset=o)
        _evaluate(plan, noise, codes, True, out, kind, first)
    noise[:, t, rows, cols] = background
    for c, bc in zip(codes, background_codes):
        c[:, t, rows, cols] = bc
    _evaluate(plan, noise, codes, False, out, len(plan.amplitudes), first)
    return out


def measure_frames(plan: Plan, frames_by_snr: Sequence[np.ndarray], noise_only: np.ndarray,
                   first_trial: int = 0) -> dict:
    """Per-trial counts for given float frames (one batch per SNR, plus the noise-only batch)
    of trials ``first_trial ..`` (the index sets the candidates' tie-break keys).

    The straightforward path (each batch quantised whole): for tests and for scenes that
    are not the built-in one. Same output layout as a chunk of :func:`run_compare`.
    """
    n = noise_only.shape[0]
    out = _empty_out(plan, n)
    for kind, frames in enumerate(list(frames_by_snr) + [noise_only]):
        codes = [scenes.quantise(frames, bits, gain=g, offset=o) for bits, g, o in plan.adcs]
        _evaluate(plan, frames, codes, kind < len(frames_by_snr), out, kind, first_trial)
    return out


# ==== the whole run =====================================================================

@dataclasses.dataclass
class CompareResult:
    """Per-trial counts of every detector (see :func:`_empty_out` for the arrays).

    ``counts[name]`` has the trial axis first, trials in index order. ``rtl``: with
    ``run_compare(..., rtl=True)``, what went through the gateware and was checked
    (:func:`dptbd.sim.rtl.trials.summary`), else None. ``noise_top``: per detector, the
    :attr:`Plan.noise_keep` largest noise-only E of the whole run, ascending (the equal-Pfa
    thresholds).
    """

    plan: Plan
    counts: dict
    seconds: float
    workers: int
    rtl: dict | None = None
    noise_top: list | None = None

    @property
    def spec(self) -> CompareSpec:
        return self.plan.spec

    @property
    def segments(self) -> int:
        return len(self.plan.ends)

    @property
    def opportunities(self) -> np.ndarray:
        """``(n_snr, trials)``: (segment, target) pairs per trial at each SNR."""
        n = self.spec.trials
        return np.full((len(self.spec.snr), n), int(self.plan.visible.sum()), dtype=np.int64)

    @property
    def trials_per_second(self) -> float:
        return self.spec.trials / self.seconds if self.seconds > 0 else math.nan


def _warm(plan: Plan) -> None:
    """Compile (or load from numba's cache) every kernel on a tiny batch."""
    spec = plan.spec
    frames = np.full((1, spec.frames, spec.size, spec.size), spec.mu, dtype=np.float32)
    _evaluate(plan, frames, [scenes.quantise(frames, b, gain=g, offset=o) for b, g, o in plan.adcs],
              False, _empty_out(plan, 1), len(spec.snr), 0)


def check_rtl(spec: CompareSpec) -> None:
    """Refuse (``ConfigError`` naming it) a configuration the gateware cannot run."""
    from dptbd.sim.rtl.trials import check_configs

    check_configs((f.name, f.cfg) for f in spec.configs)


def run_compare(spec: CompareSpec, *, workers: int | None = None, progress: bool = False,
                rtl: bool = False, scheduler: str | None = None,
                dashboard: bool = False) -> CompareResult:
    """Run the Monte Carlo: ``spec.trials`` trials in chunks of ``spec.chunk``, one dask task
    per chunk (:mod:`dptbd.evaluation.execution`).

    ``workers``: local worker processes (default: :func:`default_workers`); 1 runs in this
    process. ``scheduler``: ``tcp://HOST:PORT`` of an existing dask cluster (or the
    ``DPTBD_SCHEDULER`` environment variable); ``workers`` is then the number of workers
    it must have (default: whatever it has). ``dashboard``: print the dask dashboard's
    address. The counts depend on none of these. ``progress``: a tqdm bar on stderr.
    ``rtl``: the fixed-point configurations' trials are accumulated by the compiled
    gateware (:func:`dptbd.sim.rtl.trials.accumulate_trials`, every output word checked
    against the golden model) instead of :func:`dptbd.model.fast.run_fixed_fast`; the
    float models stay as they are. The counts are the same (``docs/compare_results.md``,
    "RTL in the loop"). Configurations the gateware does not implement are refused first.
    """
    bounds = [(a, min(a + spec.chunk, spec.trials)) for a in range(0, spec.trials, spec.chunk)]
    # no idle local processes: at most one per task
    execution = job_execution(workers, scheduler=scheduler, dashboard=dashboard,
                              tasks=len(bounds))
    if rtl:
        check_rtl(spec)
    plan = make_plan(spec)
    if rtl:  # build (or find in the cache) every executable here, before the workers start
        from dptbd.sim.rtl.trials import prepare_builds
        plan = dataclasses.replace(plan, rtl=tuple(prepare_builds(cfg) for cfg in plan.fixed))
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=spec.trials, unit="trial", desc="compare", smoothing=0.1)
    try:
        with execution.client() as client, warmed(client, functools.partial(_warm, plan)):
            _warm(plan)  # compile (or load) the kernels here too, once, before the clock
            used = (execution.workers if execution.address is None
                    else len(cluster_workers(client)))
            start = time.perf_counter()
            parts = map_tasks(_chunk, [(plan, a, b) for a, b in bounds], client,
                              sizes=[b - a for a, b in bounds], bar=bar)
            seconds = time.perf_counter() - start
    finally:
        if bar is not None:
            bar.close()
    counts = {k: np.concatenate([p[k] for p in parts], axis=0) for k in parts[0]
              if k not in ("rtl", "noise_top")}
    noise_top = merge_noise_top([p["noise_top"] for p in parts], plan.noise_keep)
    rtl_info = None
    if plan.rtl:
        from dptbd.sim.rtl.trials import summary
        tally = parts[0]["rtl"]
        for p in parts[1:]:
            tally = tally + p["rtl"]
        names = plan.detector_names()[len(plan.floats):]
        rtl_info = summary(tally, [(n, b.segmenter_missing) for n, b in zip(names, plan.rtl)])
    return CompareResult(plan=plan, counts=counts, seconds=seconds, workers=used,
                         rtl=rtl_info, noise_top=noise_top)
