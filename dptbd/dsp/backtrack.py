"""Recover the path inside a segment by backtracking the direction maps (paper 001 §2).

001 §2 calls eq (8)/(10) the *backward* method: "从目标的当前位置逆推到目标初始位置的动态规划
方法称为后向法" — the best path ending at a pixel of the segment's last frame is found by
walking back from that pixel through the arrival directions d of every frame of the
segment, down to the segment's first frame. Each pixel's d (``docs/arithmetic.md`` §2)
is the move ``(dy, dx)`` by which the path arrived from its predecessor at
``(y - dy, x - dx)`` in the previous frame.

The gateware streams the new state (E, d) of *every* frame (``docs/arithmetic.md`` §5),
so the DSP can keep the K direction maps of the current segment (K x H x W x B_d bits:
48 KiB for 128 x 128, K = 6, B_d = 4) and backtrack each candidate point. The model
produces the same maps frame by frame with the fused kernel (:mod:`dptbd.model.fast`,
bit-exact with :mod:`dptbd.model.fixed`); :func:`segment_direction_maps` checks that each
segment's last map equals the segment output of ``run_fixed_fast``.

A backtracked path gives the association (:mod:`dptbd.dsp.association`) the heading
of a candidate over its whole segment, and gives a confirmed track a position in every
frame of the segments where it was detected.
"""

from __future__ import annotations

from typing import Iterable

import numpy as np

from dptbd.config import DPConfig

__all__ = ["segment_direction_maps", "backtrack", "candidate_paths", "track_positions"]


def segment_direction_maps(frames: np.ndarray, cfg: DPConfig, *,
                           segment_direction: np.ndarray | None = None,
                           progress: Iterable | None = None) -> np.ndarray:
    """Direction map d after every frame of every whole segment.

    Parameters
    ----------
    frames : numpy.ndarray
        ``(T, H, W)`` integer frames (``docs/arithmetic.md`` §1).
    cfg : DPConfig
        The DP configuration (overlapping segments allowed: each is run on its own).
    segment_direction : numpy.ndarray, optional
        ``(S, H, W)``: the direction maps of the segment outputs (``run_fixed_fast(...)
        .direction``); if given, each segment's last map must equal it, else
        ``RuntimeError`` (the two kernels disagree: a bug, never silently ignored).
    progress : callable, optional
        Wraps the iterable of segment indices (e.g. ``tqdm``).

    Returns
    -------
    numpy.ndarray
        ``uint8`` ``(S, K, H, W)``: ``maps[s, k]`` is d after frame ``s * S_t + k``
        inside segment ``s`` (``maps[s, 0]`` is all ``START``).
    """
    from dptbd.model.fast import fast_dp_step, fast_segment_start

    arr = np.asarray(frames)
    n_seg = cfg.n_segments(arr.shape[0])
    k = cfg.segment_frames
    maps = np.empty((n_seg, k, cfg.height, cfg.width), dtype=np.uint8)
    segments = range(n_seg) if progress is None else progress(range(n_seg))
    for s in segments:
        first = s * cfg.segment_stride
        energy, direction = fast_segment_start(arr[first], cfg)
        maps[s, 0] = direction
        for i in range(1, k):
            energy, direction = fast_dp_step(energy, direction, arr[first + i], cfg, threads=1)
            maps[s, i] = direction
        if segment_direction is not None and not np.array_equal(maps[s, -1], segment_direction[s]):
            raise RuntimeError(
                f"segment {s}: the frame-by-frame direction map differs from the segment "
                f"output of run_fixed_fast (the two model kernels disagree)")
    return maps


def backtrack(maps: np.ndarray, row: int, col: int, cfg: DPConfig) -> np.ndarray:
    """The best path of one segment ending at ``(row, col)`` in its last frame.

    Walks back from the last frame: at frame k the pixel's d is the move ``(dy, dx)``
    (``docs/arithmetic.md`` §2), so the path was at ``(row - dy, col - dx)`` in frame
    k - 1. Stops at the segment's first frame (d = ``START``). Work: K - 1 look-ups.

    Parameters
    ----------
    maps : numpy.ndarray
        ``(K, H, W)`` direction maps of one segment (:func:`segment_direction_maps`).
    row, col : int
        The path's pixel in the segment's last frame.

    Returns
    -------
    numpy.ndarray
        ``int64`` ``(K, 2)``: ``(row, col)`` of the path in frames 0 … K-1 of the segment.
    """
    k = maps.shape[0]
    moves = cfg.moves
    path = np.empty((k, 2), dtype=np.int64)
    r, c = int(row), int(col)
    path[k - 1] = r, c
    for i in range(k - 1, 0, -1):
        d = int(maps[i, r, c])
        if d >= cfg.n_moves:  # START inside a segment cannot happen: the maps are corrupt
            raise ValueError(f"direction START at frame {i} of a segment (only frame 0 has it)")
        r -= int(moves[d, 0])
        c -= int(moves[d, 1])
        path[i - 1] = r, c
    return path


def candidate_paths(candidates: np.ndarray, maps: np.ndarray, cfg: DPConfig) -> np.ndarray:
    """:func:`backtrack` for each candidate record (fields ``row``, ``col``) of one segment.

    Returns
    -------
    numpy.ndarray
        ``int64`` ``(n, K, 2)``.
    """
    out = np.empty((len(candidates), maps.shape[0], 2), dtype=np.int64)
    for i, cand in enumerate(candidates):
        out[i] = backtrack(maps, int(cand["row"]), int(cand["col"]), cfg)
    return out


def track_positions(points: np.ndarray, maps: np.ndarray, cfg: DPConfig
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A position per frame for a track, from its measured points and the direction maps.

    Each measured point (segment ``s``, pixel at the segment's last frame) is backtracked
    through segment ``s``'s maps (:func:`backtrack`), giving a pixel in each of the frames
    ``s * S_t … s * S_t + K - 1``. Where segments overlap (``S_t < K``) the newer segment's
    path wins. Frames between two detected segments (the track missed, "coasted") are
    filled by linear interpolation between the end of one path and the start of the next
    and flagged as not measured.

    Parameters
    ----------
    points : numpy.ndarray
        The track's points, oldest first, with fields ``seg``, ``row``, ``col``
        (:data:`dptbd.dsp.association.POINT_DTYPE`).
    maps : numpy.ndarray
        ``(S, K, H, W)`` direction maps (:func:`segment_direction_maps`).

    Returns
    -------
    frames : numpy.ndarray
        ``int64`` frame indices, increasing and consecutive, first to last frame of the track.
    positions : numpy.ndarray
        ``float64`` ``(n, 2)`` (row, col) per frame.
    measured : numpy.ndarray
        ``bool`` ``(n,)``: True where the position comes from a backtracked path.
    """
    if len(points) == 0:
        return np.zeros(0, np.int64), np.zeros((0, 2)), np.zeros(0, bool)
    k, stride = cfg.segment_frames, cfg.segment_stride
    first = int(points["seg"][0]) * stride
    last = int(points["seg"][-1]) * stride + k - 1
    n = last - first + 1
    pos = np.full((n, 2), np.nan)
    measured = np.zeros(n, dtype=bool)
    for p in points:
        s = int(p["seg"])
        path = backtrack(maps[s], int(p["row"]), int(p["col"]), cfg)
        lo = s * stride - first
        pos[lo:lo + k] = path
        measured[lo:lo + k] = True
    known = np.flatnonzero(measured)
    frames = np.arange(first, last + 1, dtype=np.int64)
    for axis in range(2):
        pos[:, axis] = np.interp(np.arange(n), known, pos[known, axis])
    return frames, pos, measured
