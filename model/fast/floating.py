"""Compiled float reference of the direction-weighted DP, bit-identical to ``run_float``.

:func:`dptbd.model.reference.run_float` is the readable float64 reference (one numpy pass
per move). :func:`run_float_fast` computes the same float64 numbers with one numba loop
per pixel, faster, for the Monte Carlo of
``dptbd compare`` (:mod:`dptbd.evaluation.compare`). ``tests/model/fast/test_floating.py`` checks it
against ``run_float`` bit for bit.

Same operations in the same order as the reference, so the results are identical, not
merely close: candidate ``m`` of pixel ``(y, x)`` is ``w[d(q), m] * E(q)`` (one float64
multiply) for the predecessor ``q = (y - dy, x - dx)`` inside the image; the best is the
first (lowest move index) maximum; the new energy is ``best + x``; a segment's first frame
is ``E = x``, ``d = START``. Predecessors outside the image read a NaN margin: ``w * NaN``
is NaN, and NaN never compares greater, so such a candidate never wins (the reference's
``-inf``), while the centre move is always in the image.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
from numba import njit

from dptbd.config import DPConfig
from dptbd.model.reference import _check_real
from dptbd.model.segments import SegmentOutput, check_sequence

__all__ = ["run_float_fast"]


@njit(nogil=True, cache=True)
def _float_kernel(frames, n_frames_total, n_seg, stride, seg_frames, height, width, r,
                  offs, lut_t, start_code, out_e, out_d, task0, task1, task_step):
    """Segments ``task0, task0 + task_step, ... < task1``; task = trial * n_seg + segment.

    ``frames``: float64 ``(trials * T * H * W,)``; ``offs[m]``: flat offset of move m's
    predecessor in the NaN-margined plane (row stride W + 2r); ``lut_t[m, p]``: weight
    of move m after direction p. One row at a time, move by move (outer) over the row
    (inner, branch-free): the running best of a pixel is replaced only by a strictly
    greater candidate, so the lowest move index wins ties.
    """
    n_moves = offs.shape[0]
    wp = width + 2 * r
    plane = (height + 2 * r) * wp
    hw = height * width
    e_a = np.full(plane, np.nan)
    e_b = np.full(plane, np.nan)
    d_a = np.full(plane, start_code, np.uint8)
    d_b = np.full(plane, start_code, np.uint8)
    best = np.empty(width)
    move = np.empty(width, np.int64)
    wbuf = np.empty(width)
    for task in range(task0, task1, task_step):
        n = task // n_seg
        fbase = (n * n_frames_total + (task - n * n_seg) * stride) * hw
        obase = task * hw
        for y in range(height):  # segment start: E = x, d = START
            for x in range(width):
                i = (y + r) * wp + x + r
                e_a[i] = frames[fbase + y * width + x]
                d_a[i] = start_code
        for t in range(1, seg_frames):
            src_e, src_d = (e_a, d_a) if t % 2 == 1 else (e_b, d_b)
            dst_e, dst_d = (e_b, d_b) if t % 2 == 1 else (e_a, d_a)
            last = t == seg_frames - 1
            pbase = fbase + t * hw
            for y in range(height):
                row = (y + r) * wp + r
                for x in range(width):
                    best[x] = -np.inf
                    move[x] = 0
                for m in range(n_moves):
                    o = row + offs[m]
                    lut_m = lut_t[m]
                    for x in range(width):
                        wbuf[x] = lut_m[src_d[o + x]]
                    for x in range(width):
                        c = wbuf[x] * src_e[o + x]  # NaN (outside the image) never wins
                        gt = c > best[x]
                        best[x] = c if gt else best[x]
                        move[x] = m if gt else move[x]
                prow = pbase + y * width
                if last:
                    orow = obase + y * width
                    for x in range(width):
                        out_e[orow + x] = best[x] + frames[prow + x]
                        out_d[orow + x] = move[x]
                else:
                    for x in range(width):
                        dst_e[row + x] = best[x] + frames[prow + x]
                        dst_d[row + x] = move[x]


def run_float_fast(frames: np.ndarray, cfg: DPConfig, *, threads: int = 1) -> SegmentOutput:
    """Same as :func:`dptbd.model.reference.run_float`: float64 accumulation of ``(..., T, H, W)``.

    Bit-identical results and the same errors for bad input. ``threads``: Python threads
    over the independent (trial, segment) pairs (the kernel releases the GIL); the result
    does not depend on it.
    """
    if threads < 1:
        raise ValueError(f"threads must be an integer in [1, inf), got {threads}")
    arr = _check_real(check_sequence(frames, cfg))
    lead = arr.shape[:-3]
    n_frames = arr.shape[-3]
    height, width, r = cfg.height, cfg.width, cfg.radius
    n_trials = int(np.prod(lead, dtype=np.int64))
    n_seg = cfg.n_segments(n_frames)
    ends = np.arange(n_seg, dtype=np.int64) * cfg.segment_stride + cfg.segment_frames - 1
    out_e = np.empty(lead + (n_seg, height, width), dtype=np.float64)
    out_d = np.empty(lead + (n_seg, height, width), dtype=np.uint8)
    n_tasks = n_trials * n_seg
    if n_tasks == 0:
        return SegmentOutput(out_e, out_d, ends)
    if cfg.segment_frames == 1:
        out_e[...] = arr[..., ::cfg.segment_stride, :, :][..., :n_seg, :, :]
        out_d[...] = cfg.start_code
        return SegmentOutput(out_e, out_d, ends)
    moves = cfg.moves
    wp = width + 2 * r
    offs = (-moves[:, 0] * wp - moves[:, 1]).astype(np.int64)
    lut_t = np.ascontiguousarray(cfg.weight_array.T)
    flat = np.ascontiguousarray(arr, dtype=np.float64).reshape(-1)
    args = (flat, n_frames, n_seg, cfg.segment_stride, cfg.segment_frames, height, width, r,
            offs, lut_t, cfg.start_code, out_e.reshape(-1), out_d.reshape(-1))
    threads = min(threads, n_tasks)
    if threads == 1:
        _float_kernel(*args, 0, n_tasks, 1)
    else:
        with ThreadPoolExecutor(max_workers=threads) as pool:
            jobs = [pool.submit(_float_kernel, *args, c, n_tasks, threads) for c in range(threads)]
            for job in jobs:
                job.result()
    return SegmentOutput(out_e, out_d, ends)
