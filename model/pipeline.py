"""The whole chain of paper 001 on one sequence: FPGA stage, then DSP stage.

001 §5: "方向加权的动态规划算法可采用高速FPGA器件实现，二级关联部分可以采用高速DSP实现" —
the direction-weighted DP runs on an FPGA, the second-level association on a DSP.

* **FPGA stage** — the bit-accurate golden model of the DP (``run_fixed_fast``, eqs (8)–(11),
  ``docs/arithmetic.md`` §1–§5) and the constant-false-alarm-count histogram threshold
  (§6, :func:`dptbd.model.segmentation.candidates`): at most n candidate records
  (row, col, E, d) per accumulated frame.
* **Between the stages** — the direction maps of every frame of each segment (the
  gateware streams every frame's state), used to backtrack each candidate's path
  (:mod:`dptbd.model.backtrack`).
* **DSP stage** — the fixed-capacity track association of 001 §3
  (:class:`dptbd.model.association.Tracker`), one step per segment.
"""

from __future__ import annotations

import dataclasses
from typing import Callable, Iterable

import numpy as np

from dptbd.config import DPConfig
from dptbd.model.association import AssociationConfig, ConfirmedTrack, Tracker, make_candidates
from dptbd.model.backtrack import candidate_paths, segment_direction_maps, track_positions
from dptbd.model.segmentation import candidates as segment_candidates
from dptbd.model.segments import SegmentOutput

__all__ = ["PipelineResult", "run_pipeline"]


@dataclasses.dataclass
class PipelineResult:
    """Everything the two stages produced for one sequence.

    Attributes
    ----------
    cfg, assoc : DPConfig, AssociationConfig
        The parameters.
    count : int
        n, candidates per accumulated frame.
    segments : SegmentOutput
        Accumulated images, direction maps and end frames of every segment.
    maps : numpy.ndarray
        ``(S, K, H, W)`` direction map after every frame of every segment.
    candidates : list of numpy.ndarray
        Per segment, :data:`dptbd.model.association.CANDIDATE_DTYPE` records.
    tracks : list of ConfirmedTrack
        Every track the DSP confirmed.
    positions : dict
        Track id -> ``(frames, positions, measured)`` (:func:`track_positions`).
    stats : dict
        The tracker's counters.
    """

    cfg: DPConfig
    assoc: AssociationConfig
    count: int
    segments: SegmentOutput
    maps: np.ndarray
    candidates: list
    tracks: list[ConfirmedTrack]
    positions: dict
    stats: dict


def _accumulate(frames: np.ndarray, cfg: DPConfig) -> SegmentOutput:
    try:
        from dptbd.model.fast import run_fixed_fast as run
    except ImportError:  # pragma: no cover - numba missing: the reference gives the same bits
        from dptbd.model.fixed import run_fixed as run
    return run(frames, cfg)


def run_pipeline(frames: np.ndarray, cfg: DPConfig, count: int, assoc: AssociationConfig, *,
                 progress: Callable[..., Iterable] | None = None) -> PipelineResult:
    """Run the FPGA stage and the DSP stage on integer frames ``(T, H, W)``.

    Parameters
    ----------
    frames : numpy.ndarray
        Unsigned ``cfg.input_bits``-bit integer frames.
    cfg : DPConfig
        DP parameters; frame size must match.
    count : int
        n, the constant false-alarm count per accumulated frame (<= ``assoc.max_candidates``).
    assoc : AssociationConfig
        Association parameters.
    progress : callable, optional
        ``progress(iterable, desc=..., total=...)`` wrapper (``tqdm``) for the per-segment loops.
    """
    if count > assoc.max_candidates:
        raise ValueError(f"the segmentation keeps up to {count} candidates per accumulated frame "
                         f"but the association's input buffer holds max_candidates="
                         f"{assoc.max_candidates}; raise it or lower the false-alarm rate")
    segments = _accumulate(frames, cfg)
    wrap = (lambda it, desc: it) if progress is None else \
        (lambda it, desc: progress(it, desc=desc, leave=False))
    maps = segment_direction_maps(frames, cfg, segment_direction=segments.direction,
                                  progress=lambda it: wrap(it, "direction maps"))
    tracker = Tracker(assoc, segment_frames=cfg.segment_frames, segment_stride=cfg.segment_stride,
                      height=cfg.height, width=cfg.width, radius=cfg.radius)
    cands = []
    for s in wrap(range(len(segments.end_frames)), "association"):
        raw = segment_candidates(segments.energy[s], segments.direction[s], count)
        c = make_candidates(raw, candidate_paths(raw, maps[s], cfg))
        tracker.step(c)
        cands.append(c)
    tracks = tracker.confirmed_tracks()
    positions = {tr.id: track_positions(tr.points, maps, cfg) for tr in tracks}
    return PipelineResult(cfg, assoc, count, segments, maps, cands, tracks, positions,
                          dict(tracker.stats))
