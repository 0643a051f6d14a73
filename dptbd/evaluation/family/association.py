"""K-frame segments against the recursive DP through the DSP association.

On ``dptbd run``'s built-in scenario (001's second experiment: 128 x 128, 100 frames,
SNR 2.0, two targets; :func:`dptbd.evaluation.run.scenario.default_scenario`) with one seed,
prepared exactly as ``dptbd run`` prepares it (:func:`dptbd.evaluation.run.job.prepare`),
one variant runs through the FPGA stage and the DSP stage:

* segments of K frames (stride K): :func:`dptbd.evaluation.chain.run_pipeline`;
* the recursive DP with forgetting factor alpha, scored every ``every`` frames with paths
  backtracked over ``path_frames``:
  :func:`dptbd.evaluation.family.recursive_pipeline.run_recursive_pipeline`.

Both with the ideal lists (each map's n = 33 largest pixels: equal false points per map)
and the scenario's association parameters. Per target: frames until output (None: never
confirmed) and first-level detections per map; per run: false tracks
(:func:`dptbd.dsp.track_metrics.evaluate_tracks`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.dsp.track_metrics import TrackEvaluation, evaluate_tracks
from dptbd.errors import DptbdError, check_int
from dptbd.evaluation.chain import PipelineResult, run_pipeline
from dptbd.evaluation.family.detection import Variant
from dptbd.evaluation.family.recursive_pipeline import (associate_lists, independent_lists,
                                                        recursive_lists, recursive_view)
from dptbd.evaluation.run.job import prepare
from dptbd.evaluation.run.scenario import default_scenario
from dptbd.scenes import synthetic as scenes

__all__ = ["JobOutcome", "JobRun", "LISTS", "job_outcome", "job_run"]

#: Where a recursive variant's lists come from: ``"recursion"`` (one recursion over the
#: sequence, the lists every ``every`` frames of it) or ``"independent"`` (list s from a
#: recursion over its own sequence: the same targets, noise of its own seed, drawn from
#: ``SeedSequence([seed, s + 1])``; each list has the recursion's statistics, consecutive
#: lists share no noise).
LISTS = ("recursion", "independent")


@dataclasses.dataclass(frozen=True)
class JobRun:
    """One variant through both stages on one seed: the pipeline's result, the targets'
    truth (empty on a noise-only scene) and the evaluation of its confirmed tracks."""

    result: PipelineResult
    truth: tuple
    evaluation: TrackEvaluation


@dataclasses.dataclass(frozen=True)
class JobOutcome:
    """One variant on one seed of the built-in scenario.

    ``frames_until_output[j]``: frames from target j's appearance to the end of the map in
    which its track was confirmed (None: never confirmed); ``hits[j]`` = (maps with a
    candidate within one pixel of target j, maps in which it was visible); ``false_tracks``:
    confirmed tracks that belong to no target; ``maps``: lists the DSP received.
    """

    frames_until_output: tuple
    hits: tuple
    false_tracks: int
    maps: int


def _hits(result, truth) -> tuple:
    out = []
    for tt in truth:
        det = opp = 0
        for s, end in enumerate(result.segments.end_frames):
            if not tt.visible[end]:
                continue
            opp += 1
            c = result.candidates[s]
            if len(c):
                dist = np.maximum(np.abs(c["row"].astype(np.int64) - tt.pixel[end][0]),
                                  np.abs(c["col"].astype(np.int64) - tt.pixel[end][1]))
                det += bool(np.any(dist <= 1))
        out.append((det, opp))
    return tuple(out)


def job_run(variant: Variant, seed: int, *, every: int | None = None, noise_only: bool = False,
            lists: str = "recursion", count: int | None = None) -> JobRun:
    """Run ``variant`` on the built-in scenario with ``seed`` (ideal lists).

    A recursive variant is scored every ``every`` frames (default: its ``segment_frames``,
    so the DSP gets as many lists as from segments of that K) with paths of
    ``segment_frames`` frames, its lists from ``lists`` (:data:`LISTS`); ``noise_only``
    drops the targets (the noise is the same: it does not depend on them), so every
    confirmed track is false; ``count`` replaces the list length n (default: the
    scenario's, 33).
    """
    if lists not in LISTS:
        raise DptbdError(f"lists must be one of {', '.join(map(repr, LISTS))}, got {lists!r}")
    sc = default_scenario()
    sc = sc.replace(seed=seed, lists="ideal", dp={**sc.dp, "segment_frames": variant.segment_frames},
                    targets=() if noise_only else sc.targets)
    sc.check()
    inp = prepare(sc)
    if count is not None:
        inp = dataclasses.replace(inp, count=check_int("count", count, 1, inp.assoc.max_candidates))
    if variant.forgetting is None:
        if lists != "recursion":
            raise DptbdError(f"lists={lists!r} needs a recursive variant, got {variant.label!r}")
        result = run_pipeline(inp.frames, inp.cfg, inp.count, inp.assoc, lists="ideal")
    else:
        cfg = inp.cfg.replace(histogram_shift=None, **variant.family_fields(inp.cfg.radius))
        k = variant.segment_frames
        step = k if every is None else every
        view = recursive_view(cfg, k, step)
        if lists == "recursion":
            segs, maps = recursive_lists(inp.frames, cfg, path_frames=k, every=step)
        else:
            n_lists = len(range(k - 1, inp.frames.shape[0], step))
            own = [_own_noise(sc, seed, s, k + s * step) for s in range(n_lists)]
            segs, maps = independent_lists(own, cfg, path_frames=k, every=step)
        result = associate_lists(segs, maps, view, inp.count, inp.assoc)
    ev = evaluate_tracks(result.tracks, result.positions, inp.truth, result.cfg,
                         len(result.segments.end_frames))
    return JobRun(result, tuple(inp.truth), ev)


def _own_noise(sc, seed: int, s: int, frames: int) -> np.ndarray:
    """The first ``frames`` frames of list s's own sequence (``lists="independent"``):
    ``sc``'s targets on noise of the seed drawn from ``SeedSequence([seed, s + 1])``,
    quantised as ``prepare`` quantises them."""
    own = int(np.random.SeedSequence([seed, s + 1]).generate_state(1, np.uint64)[0])
    targets = [t.target(sc.snr, sc.sigma) for t in sc.targets]
    scene = scenes.make_scene((sc.height, sc.width), frames, targets, mu=sc.mu,
                              sigma=sc.sigma, seed=own)
    return scenes.quantise(scene.frames, sc.adc_bits, gain=sc.adc_gain, offset=sc.adc_offset)


def job_outcome(variant: Variant, seed: int, *, every: int | None = None,
                noise_only: bool = False, lists: str = "recursion",
                count: int | None = None) -> JobOutcome:
    """:func:`job_run`'s outcome: per target frames until output and first-level hits,
    false tracks, lists."""
    run = job_run(variant, seed, every=every, noise_only=noise_only, lists=lists, count=count)
    result, ev = run.result, run.evaluation
    return JobOutcome(tuple(t.frames_until_output for t in ev.targets), _hits(result, run.truth),
                      ev.false_tracks, len(result.segments.end_frames))
