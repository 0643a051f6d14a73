"""The DSP association fed by the recursive DP (``docs/arithmetic.md`` §8.6).

The recursive DP gives a detection map every frame, but the DSP association of 001 §3
(:class:`dptbd.dsp.association.Tracker`) steps once per *list*, each candidate carrying the
path backtracked over a window of frames. This module feeds it the recursive DP's maps of
frames ``t_s = L - 1 + s * E`` (``every`` = E frames apart), each candidate's path
backtracked along the recursion's stored directions over the last ``path_frames`` = L
frames. To the tracker, :func:`dptbd.dsp.backtrack.track_positions` and
:func:`dptbd.dsp.track_metrics.evaluate_tracks` this looks like segments of K = L frames
at stride E (:func:`recursive_view`); with E = L = K the DSP receives exactly as many lists,
of the same length, as from K-frame segments. Lists are the ideal rule (each map's n
largest pixels; the gateware segmenter's histogram shift is calibrated for K-frame sums,
``docs/arithmetic.md`` §6.6, not for a recursion's E ≈ P / (1 - alpha)).
"""

from __future__ import annotations

import numpy as np

from dptbd.config import DPConfig
from dptbd.dsp.association import AssociationConfig, make_candidates
from dptbd.dsp.backtrack import candidate_paths, track_positions
from dptbd.dsp.c_tracker import tracker_class
from dptbd.evaluation.chain import PipelineResult
from dptbd.errors import check_int
from dptbd.model.family.fast import fast_family_start, fast_family_step
from dptbd.model.segmentation import candidates as map_candidates
from dptbd.model.segments import SegmentOutput

__all__ = ["associate_lists", "independent_lists", "recursive_lists", "recursive_view",
           "run_recursive_pipeline"]


def recursive_view(cfg: DPConfig, path_frames: int, every: int) -> DPConfig:
    """The segment layout the DSP sees: K = ``path_frames``, stride ``every`` (<= K)."""
    if not cfg.recursive:
        raise ValueError("run_recursive_pipeline needs a configuration with recursive=True")
    path_frames = check_int("path_frames", path_frames, 1, 65535)
    every = check_int("every", every, 1, path_frames, hi_name="path_frames=")
    return cfg.replace(recursive=False, segment_frames=path_frames, segment_stride=every)


def recursive_lists(frames: np.ndarray, cfg: DPConfig, *, path_frames: int, every: int
                    ) -> tuple[SegmentOutput, np.ndarray]:
    """``(segments, maps)``: the recursive DP's maps of the frames ``t_s = L - 1 + s * E`` on
    ``frames (T, H, W)`` and each one's direction maps of its last L frames (``maps[s, 0]``
    is ``START``: a path stops L - 1 moves back)."""
    recursive_view(cfg, path_frames, every)
    arr = np.asarray(frames)
    n_t = arr.shape[0]
    if n_t < path_frames:
        raise ValueError(f"the sequence has {n_t} frame(s), fewer than path_frames={path_frames}")
    ends = np.arange(path_frames - 1, n_t, every)
    directions = np.empty((n_t, cfg.height, cfg.width), dtype=np.uint8)
    energy, direction = fast_family_start(arr[0], cfg)
    directions[0] = direction
    kept_e = np.empty((len(ends), cfg.height, cfg.width), dtype=energy.dtype)
    where = {int(t): s for s, t in enumerate(ends)}
    if 0 in where:
        kept_e[0] = energy
    for t in range(1, n_t):
        energy, direction = fast_family_step(energy, direction, arr[t], cfg)
        directions[t] = direction
        if t in where:
            kept_e[where[t]] = energy
    maps = np.stack([directions[t - path_frames + 1:t + 1] for t in ends])
    maps[:, 0] = cfg.start_code
    return SegmentOutput(kept_e, directions[ends], ends.astype(np.int64)), maps


def associate_lists(segments: SegmentOutput, maps: np.ndarray, view: DPConfig, count: int,
                    assoc: AssociationConfig, *, dsp: str = "python") -> PipelineResult:
    """The DSP association on lists of ``count`` ideal candidates of ``segments`` with the
    paths of ``maps``, laid out as ``view`` (:func:`recursive_view`)."""
    tracker = tracker_class(dsp)(assoc, segment_frames=view.segment_frames,
                                 segment_stride=view.segment_stride,
                                 height=view.height, width=view.width, radius=view.radius)
    cands = []
    for s in range(len(segments.end_frames)):
        raw = map_candidates(segments.energy[s], segments.direction[s], count)
        c = make_candidates(raw, candidate_paths(raw, maps[s], view))
        tracker.step(c)
        cands.append(c)
    tracks = tracker.confirmed_tracks()
    positions = {tr.id: track_positions(tr.points, maps, view) for tr in tracks}
    return PipelineResult(view, assoc, count, segments, maps, cands, tracks, positions,
                          dict(tracker.stats), "ideal", dsp)


def run_recursive_pipeline(frames: np.ndarray, cfg: DPConfig, count: int,
                           assoc: AssociationConfig, *, path_frames: int, every: int,
                           dsp: str = "python") -> PipelineResult:
    """Run the recursive DP on ``frames (T, H, W)`` and the DSP association on its maps.

    Returns a :class:`dptbd.evaluation.chain.PipelineResult` whose ``cfg`` is
    :func:`recursive_view` (``segments.end_frames`` = the scored frames; ``maps[s, 0]`` is
    ``START``: a path stops L - 1 moves back).
    """
    view = recursive_view(cfg, path_frames, every)
    segments, maps = recursive_lists(frames, cfg, path_frames=path_frames, every=every)
    return associate_lists(segments, maps, view, count, assoc, dsp=dsp)


def independent_lists(sequences, cfg: DPConfig, *, path_frames: int, every: int
                      ) -> tuple[SegmentOutput, np.ndarray]:
    """Like :func:`recursive_lists`, but list s comes from the recursion on its own sequence
    ``sequences[s]`` (``(T_s, H, W)``, at least ``L + s * E`` frames; later frames are not
    used): each list has the recursion's statistics, consecutive lists share no noise (the
    control that breaks their correlation)."""
    recursive_view(cfg, path_frames, every)
    energy, direction, maps = [], [], []
    ends = path_frames - 1 + every * np.arange(len(sequences))
    for s, t in enumerate(ends):
        seq = np.asarray(sequences[s])
        if seq.ndim != 3 or seq.shape[0] <= t:
            raise ValueError(f"independent_lists: sequence {s} must be (T, H, W) with T > {t} "
                             f"frames, got shape {seq.shape}")
        seg, m = recursive_lists(seq[:t + 1], cfg, path_frames=path_frames, every=every)
        energy.append(seg.energy[s])
        direction.append(seg.direction[s])
        maps.append(m[s])
    return (SegmentOutput(np.stack(energy), np.stack(direction), ends.astype(np.int64)),
            np.stack(maps))
