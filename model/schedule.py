"""When the DP restarts: K-frame segments (§5) or a recursion that never resets (§8.6).

Shared by the family's fixed-point model, its float counterpart and its numba kernel.
"""

from __future__ import annotations

import numpy as np

from dptbd.config import DPConfig
from dptbd.model.segments import SegmentOutput, StartFn, StepFn, run_segments

__all__ = ["run_recursive", "run_schedule"]


def run_recursive(frames: np.ndarray, start: StartFn, step: StepFn, energy_dtype) -> SegmentOutput:
    """``start`` on frame 0, ``step`` on every later frame; the state of every frame is an output.

    Returns a :class:`~dptbd.model.segments.SegmentOutput` with one map per frame
    (``end_frames = 0 … T-1``): the recursive DP's detection map of each frame.
    """
    n_t = frames.shape[-3]
    lead = frames.shape[:-3]
    shape = lead + (n_t,) + frames.shape[-2:]
    energy = np.zeros(shape, dtype=energy_dtype)
    direction = np.zeros(shape, dtype=np.uint8)
    e, d = start(frames[..., 0, :, :])
    energy[..., 0, :, :], direction[..., 0, :, :] = e, d
    for t in range(1, n_t):
        e, d = step(e, d, frames[..., t, :, :])
        energy[..., t, :, :], direction[..., t, :, :] = e, d
    return SegmentOutput(energy, direction, np.arange(n_t, dtype=np.int64))


def run_schedule(frames: np.ndarray, cfg: DPConfig, start: StartFn, step: StepFn,
                 energy_dtype) -> SegmentOutput:
    """:func:`run_recursive` when ``cfg.recursive``, else :func:`~dptbd.model.segments.run_segments`."""
    if cfg.recursive:
        return run_recursive(frames, start, step, energy_dtype)
    return run_segments(frames, cfg, start, step, energy_dtype)
