"""Track-level metrics of the DSP stage against ground truth (paper 001 §4, Table 1).

001's Table 1 has, besides the first-level columns (:mod:`dptbd.evaluation.metrics`), two
track columns: "结果输出所用帧数" (frames until the result is output) and "检测出轨迹长度"
(length of the detected track). Definitions used here:

* A confirmed track **belongs to** target j when at least ``min_fraction`` of its measured
  points (one per detected segment, at the segment's last frame) lie within Chebyshev
  ``radius`` pixels of target j's true pixel in that frame; if several targets qualify,
  the one with the largest fraction (then the lowest index). A confirmed track that
  belongs to no target is a **false track**.
* **Segments until confirmation**: accumulated frames processed from the first segment
  that ends after the target appears, up to and including the segment in which its first
  track passed the output threshold. **Frames until output**: input frames from the
  target's first visible frame to the last frame of that segment, inclusive.
* **Track length**: frames in which some track of the target has a position (backtracked
  in detected segments, interpolated across missed ones;
  :func:`dptbd.dsp.backtrack.track_positions`), whole and after the output frame. 001's rows satisfy "frames until
  output + length" ≈ 100 (e.g. 45 + 52, 49 + 48), which suggests its length counts the
  frames after output; both are reported.
* **Position error**: Euclidean distance between a track's backtracked (measured) pixel
  and the target's true (sub-pixel) position in the same frame; RMS and maximum.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from dptbd.config import DPConfig

__all__ = ["TargetTrackResult", "TrackEvaluation", "evaluate_tracks"]


@dataclasses.dataclass(frozen=True)
class TargetTrackResult:
    """Track metrics of one target (``None`` where it has no confirmed track)."""

    target: int
    track_ids: tuple[int, ...]
    confirm_segment: int | None
    segments_until_confirmation: int | None
    frames_until_output: int | None
    track_frames: int
    track_frames_after_output: int
    rms_error: float
    max_error: float
    measured_frames: int


@dataclasses.dataclass(frozen=True)
class TrackEvaluation:
    """Track metrics of a run."""

    targets: tuple[TargetTrackResult, ...]
    track_target: dict            # track id -> target index, or -1 (false track)
    confirmed_tracks: int
    false_tracks: int


def _segment_of_frame(frame: int, cfg: DPConfig, n_seg: int) -> int:
    """First segment whose last frame is >= ``frame``."""
    for s in range(n_seg):
        if s * cfg.segment_stride + cfg.segment_frames - 1 >= frame:
            return s
    return n_seg


def evaluate_tracks(tracks, positions: dict, truth, cfg: DPConfig, n_segments: int, *,
                    radius: float = 2.0, min_fraction: float = 0.5) -> TrackEvaluation:
    """Assign confirmed tracks to targets and measure them.

    Parameters
    ----------
    tracks : list of ConfirmedTrack
        :meth:`dptbd.dsp.association.Tracker.confirmed_tracks`.
    positions : dict
        Track id -> ``(frames, positions, measured)`` (:func:`dptbd.dsp.backtrack.track_positions`).
    truth : sequence of TargetTruth
        Ground truth of each target (:class:`dptbd.scenes.synthetic.TargetTruth`).
    cfg : DPConfig
        Segment layout (K, S_t).
    n_segments : int
        Accumulated frames in the run.
    radius, min_fraction : float
        Chebyshev distance in pixels and the fraction of a track's points that must be
        that close to a target for the track to belong to it.
    """
    k, stride = cfg.segment_frames, cfg.segment_stride
    owner: dict[int, int] = {}
    for tr in tracks:
        best, best_frac = -1, 0.0
        ends = tr.points["seg"].astype(np.int64) * stride + k - 1
        for j, tt in enumerate(truth):
            pix = tt.pixel[ends]
            vis = tt.visible[ends]
            near = vis & (np.abs(pix[:, 0] - tr.points["row"].astype(np.int64)) <= radius) \
                & (np.abs(pix[:, 1] - tr.points["col"].astype(np.int64)) <= radius)
            frac = float(np.count_nonzero(near)) / max(len(tr.points), 1)
            if frac >= min_fraction and frac > best_frac:
                best, best_frac = j, frac
        owner[tr.id] = best
    results = []
    for j, tt in enumerate(truth):
        mine = [tr for tr in tracks if owner[tr.id] == j]
        visible = np.flatnonzero(tt.visible)
        if not mine or visible.size == 0:
            results.append(TargetTrackResult(j, tuple(tr.id for tr in mine), None, None, None,
                                             0, 0, math.nan, math.nan, 0))
            continue
        appear = int(visible[0])
        first = min(mine, key=lambda tr: (tr.confirm_segment, tr.id))
        conf = first.confirm_segment
        conf_end = conf * stride + k - 1
        covered: set[int] = set()
        errors = []
        for tr in mine:
            frames, pos, measured = positions[tr.id]
            covered.update(int(f) for f in frames)
            if len(frames):
                err = np.hypot(*(pos[measured] - tt.position[frames[measured]]).T)
                errors.extend(err.tolist())
        err = np.asarray(errors)
        results.append(TargetTrackResult(
            target=j, track_ids=tuple(tr.id for tr in mine), confirm_segment=conf,
            segments_until_confirmation=conf - _segment_of_frame(appear, cfg, n_segments) + 1,
            frames_until_output=conf_end - appear + 1,
            track_frames=len(covered),
            track_frames_after_output=sum(1 for f in covered if f > conf_end),
            rms_error=float(np.sqrt(np.mean(err ** 2))) if err.size else math.nan,
            max_error=float(err.max()) if err.size else math.nan,
            measured_frames=int(err.size)))
    false = sum(1 for tid in owner if owner[tid] < 0)
    return TrackEvaluation(tuple(results), owner, len(tracks), false)
