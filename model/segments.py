"""Segment bookkeeping shared by the float reference and the fixed-point model.

``docs/arithmetic.md`` §5: segment s covers frames ``s*S_t … s*S_t + K - 1``; its first
frame starts the recursion afresh (E = x, d = START), its last frame's state is the
segment's accumulated image and direction map.
"""

from __future__ import annotations

import dataclasses
from typing import Callable

import numpy as np

from dptbd.config import DPConfig

__all__ = ["SegmentOutput", "check_sequence", "run_segments"]


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


def check_sequence(frames: np.ndarray, cfg: DPConfig) -> np.ndarray:
    """Check a sequence's shape ``(..., T, H, W)`` against ``cfg``; return it as an array."""
    arr = np.asarray(frames)
    if arr.ndim < 3:
        raise ValueError(
            f"frames must have shape (..., T, H, W) with at least 3 axes, got shape {arr.shape}")
    if arr.shape[-2:] != (cfg.height, cfg.width):
        raise ValueError(
            f"frames are {arr.shape[-2]}x{arr.shape[-1]} (H x W) but the configuration "
            f"is height={cfg.height}, width={cfg.width}")
    if arr.shape[-3] < cfg.segment_frames:
        raise ValueError(
            f"a sequence of {arr.shape[-3]} frames is shorter than one segment "
            f"(segment_frames={cfg.segment_frames})")
    return arr


StartFn = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
StepFn = Callable[[np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


def run_segments(frames: np.ndarray, cfg: DPConfig, start: StartFn, step: StepFn,
                 energy_dtype) -> SegmentOutput:
    """Run ``start`` on each segment's first frame and ``step`` on the others."""
    n_seg = cfg.n_segments(frames.shape[-3])
    lead = frames.shape[:-3]
    energy = np.zeros(lead + (n_seg, cfg.height, cfg.width), dtype=energy_dtype)
    direction = np.zeros(lead + (n_seg, cfg.height, cfg.width), dtype=np.uint8)
    ends = np.zeros(n_seg, dtype=np.int64)
    for s in range(n_seg):
        first = s * cfg.segment_stride
        e, d = start(frames[..., first, :, :])
        for t in range(first + 1, first + cfg.segment_frames):
            e, d = step(e, d, frames[..., t, :, :])
        energy[..., s, :, :] = e
        direction[..., s, :, :] = d
        ends[s] = first + cfg.segment_frames - 1
    return SegmentOutput(energy, direction, ends)
