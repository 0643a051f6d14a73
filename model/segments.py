"""Segment bookkeeping shared by the float reference and the fixed-point model.

``docs/arithmetic.md`` §5: segment s covers frames ``s*S_t … s*S_t + K - 1``; its first
frame starts the recursion afresh (E = x, d = START), its last frame's state is the
segment's accumulated image and direction map. With a run-time schedule
(:mod:`dptbd.model.settings`) segment j is ``K_j`` frames long and starts where segment
j - 1 ended (the gateware's segments never overlap).
"""

from __future__ import annotations

import dataclasses
from typing import Callable

import numpy as np

from dptbd.config import DPConfig
from dptbd.model.settings import Schedule, check_schedule, segment_lengths

__all__ = ["SegmentOutput", "check_sequence", "segment_spans", "run_segments"]


@dataclasses.dataclass(frozen=True)
class SegmentOutput:
    """Accumulated images and direction maps, one per whole segment.

    Attributes
    ----------
    energy : numpy.ndarray
        ``(..., S, H, W)``: E after each segment's last frame.
    direction : numpy.ndarray
        ``(..., S, H, W)`` ``uint8``: d after each segment's last frame.
    end_frames : numpy.ndarray
        ``(S,)`` index of each segment's last frame in the input sequence.
    """

    energy: np.ndarray
    direction: np.ndarray
    end_frames: np.ndarray


def check_sequence(frames: np.ndarray, cfg: DPConfig,
                   schedule: Schedule | None = None) -> np.ndarray:
    """Check a sequence's shape ``(..., T, H, W)`` against ``cfg`` (at least one segment: K
    frames, or the ``schedule``'s first K); return it as an array."""
    arr = np.asarray(frames)
    if arr.ndim < 3:
        raise ValueError(
            f"frames must have shape (..., T, H, W) with at least 3 axes, got shape {arr.shape}")
    if arr.shape[-2:] != (cfg.height, cfg.width):
        raise ValueError(
            f"frames are {arr.shape[-2]}x{arr.shape[-1]} (H x W) but the configuration "
            f"is height={cfg.height}, width={cfg.width}")
    first_k = cfg.segment_frames if schedule is None else \
        check_schedule(cfg, schedule)[0].segment_frames
    if arr.shape[-3] < first_k:
        raise ValueError(
            f"a sequence of {arr.shape[-3]} frames is shorter than one segment "
            f"(segment_frames={first_k})")
    return arr


StartFn = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
StepFn = Callable[[np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


def segment_spans(cfg: DPConfig, n_frames: int,
                  schedule: Schedule | None = None) -> list[tuple[int, int]]:
    """``(first frame, K)`` of every whole segment of ``n_frames`` frames: every
    ``segment_stride`` frames, K each; or, with a ``schedule``, consecutive segments of the
    schedule's lengths (:func:`~dptbd.model.settings.check_schedule`)."""
    if schedule is None:
        return [(s * cfg.segment_stride, cfg.segment_frames)
                for s in range(cfg.n_segments(n_frames))]
    lengths = segment_lengths(check_schedule(cfg, schedule), n_frames)
    firsts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(int) if lengths else []
    return [(int(a), k) for a, k in zip(firsts, lengths)]


def run_segments(frames: np.ndarray, cfg: DPConfig, start: StartFn, step: StepFn,
                 energy_dtype, schedule: Schedule | None = None) -> SegmentOutput:
    """Run ``start`` on each segment's first frame and ``step`` on the others
    (segments as :func:`segment_spans` places them)."""
    spans = segment_spans(cfg, frames.shape[-3], schedule)
    n_seg = len(spans)
    lead = frames.shape[:-3]
    energy = np.zeros(lead + (n_seg, cfg.height, cfg.width), dtype=energy_dtype)
    direction = np.zeros(lead + (n_seg, cfg.height, cfg.width), dtype=np.uint8)
    ends = np.zeros(n_seg, dtype=np.int64)
    for s, (first, k) in enumerate(spans):
        e, d = start(frames[..., first, :, :])
        for t in range(first + 1, first + k):
            e, d = step(e, d, frames[..., t, :, :])
        energy[..., s, :, :] = e
        direction[..., s, :, :] = d
        ends[s] = first + k - 1
    return SegmentOutput(energy, direction, ends)
