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

from dptbd.evaluation.chain import run_pipeline
from dptbd.dsp.track_metrics import evaluate_tracks
from dptbd.evaluation.family.detection import Variant
from dptbd.evaluation.family.recursive_pipeline import run_recursive_pipeline
from dptbd.evaluation.run.job import prepare
from dptbd.evaluation.run.scenario import default_scenario

__all__ = ["JobOutcome", "job_outcome"]


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


def job_outcome(variant: Variant, seed: int, *, every: int | None = None) -> JobOutcome:
    """Run ``variant`` on the built-in scenario with ``seed`` (ideal lists).

    A recursive variant is scored every ``every`` frames (default: its ``segment_frames``,
    so the DSP gets as many lists as from segments of that K) with paths of
    ``segment_frames`` frames.
    """
    sc = default_scenario()
    sc = sc.replace(seed=seed, lists="ideal", dp={**sc.dp, "segment_frames": variant.segment_frames})
    sc.check()
    inp = prepare(sc)
    if variant.forgetting is None:
        result = run_pipeline(inp.frames, inp.cfg, inp.count, inp.assoc, lists="ideal")
    else:
        cfg = inp.cfg.replace(histogram_shift=None, **variant.family_fields(inp.cfg.radius))
        result = run_recursive_pipeline(
            inp.frames, cfg, inp.count, inp.assoc, path_frames=variant.segment_frames,
            every=variant.segment_frames if every is None else every)
    ev = evaluate_tracks(result.tracks, result.positions, inp.truth, result.cfg,
                         len(result.segments.end_frames))
    return JobOutcome(tuple(t.frames_until_output for t in ev.targets), _hits(result, inp.truth),
                      ev.false_tracks, len(result.segments.end_frames))
