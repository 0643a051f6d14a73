"""Fused compiled kernel of the fixed-point golden model, bit-exact with ``dptbd.model.fixed``.

``dptbd.model.fixed`` is the readable reference: one numpy pass per operator and move,
``int64`` temporaries, every frame materialised. This module computes the same bits
(``docs/arithmetic.md`` §4-§5) with numba, fused into one loop per output row, and is
checked against the reference bit for bit by ``tests/model/fast/test_init.py``. Public functions
mirror the reference: :func:`fast_segment_start`, :func:`fast_dp_step`,
:func:`run_fixed_fast` (same arguments, results and errors; an optional keyword
``threads``).

Two kernels, chosen per configuration (:func:`kernel_path`):

``"binary"`` (:mod:`dptbd.model.fast.binary`)
    Every weight code is 0 or 2**F and ``E << s`` fits 32 bits: no multiply, 32-bit keys,
    the K - 1 steps of a segment as a wavefront over rows.

``"general"`` (:mod:`dptbd.model.fast.general`)
    Any LUT and any B_E <= 32: the reference arithmetic literally, 64-bit keys. Slower;
    used when the binary kernel does not apply.

The per-configuration constants both kernels take are in :mod:`dptbd.model.fast.plan`.

Independent (trial, segment) pairs are spread over threads (the kernels release the
GIL); each is computed by one thread, so the result does not depend on the thread count.
"""

from __future__ import annotations

import warnings
from concurrent.futures import ThreadPoolExecutor

import numba
import numpy as np

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.model import fixed
from dptbd.model.fast.binary import _binary_kernel
from dptbd.model.fast.general import _general_kernel
from dptbd.model.fast.plan import _plan, kernel_path
from dptbd.model.operators import check_pixels
from dptbd.model.segments import SegmentOutput, check_sequence, segment_spans

__all__ = ["fast_segment_start", "fast_dp_step", "run_fixed_fast", "kernel_path"]

ENERGY_DTYPE = fixed.ENERGY_DTYPE
DIRECTION_DTYPE = fixed.DIRECTION_DTYPE

#: Bytes of ring buffer (both planes, all steps) one wavefront group may use.
_RING_BUDGET = 1 << 20
#: Most steps one wavefront group pipelines; longer segments are cut into groups that
#: hand over through one full-frame state.
_MAX_GROUP = 32


def _check_pixels_nocopy(arr: np.ndarray, input_bits: int) -> None:
    """``check_pixels`` without its ``int64`` copy: the same checks and the same errors.

    The dtype test runs on an empty array of ``arr``'s dtype and the range test on the
    array ``[min, max]``; ``check_pixels``'s messages depend on nothing else.
    """
    check_pixels(np.empty(0, dtype=arr.dtype), input_bits)
    if not arr.size:
        return
    hi = arr.max()
    if arr.dtype.kind == "u" and hi < 1 << input_bits:
        return  # unsigned and in range: the minimum only matters for the error message
    check_pixels(np.array([arr.min(), hi], dtype=arr.dtype), input_bits)


def _as_kernel_pixels(arr: np.ndarray) -> np.ndarray:
    """Validated pixels as one C-contiguous uint16 array (lossless: they are < 2**16).

    A single pixel type keeps the number of compiled specialisations (JIT time) down.
    """
    return np.ascontiguousarray(arr, dtype=np.uint16)


# ==== public API ==========================================================================

def _resolve_threads(threads: int | None, n_tasks: int) -> int:
    """Worker threads for ``n_tasks`` independent tasks: ``threads`` or numba's thread count."""
    n = numba.get_num_threads() if threads is None else int(threads)
    if n < 1:
        raise ValueError(f"threads must be an integer in [1, inf), got {threads}")
    return max(1, min(n, n_tasks))


def _spread(kernel, args: tuple, n_tasks: int, threads: int) -> int:
    """Run ``kernel(*args, first, stop, step)`` over tasks 0 .. n_tasks - 1 on ``threads`` threads.

    The kernels release the GIL; task c, c + threads, c + 2 * threads, ... go to thread c.
    Each task writes its own slice of the output, so the result is independent of threads.
    Returns the OR of the kernels' results (the OR of every pixel read).
    """
    if threads == 1:
        return int(kernel(*args, 0, n_tasks, 1))
    with ThreadPoolExecutor(max_workers=threads) as pool:
        jobs = [pool.submit(kernel, *args, c, n_tasks, threads) for c in range(threads)]
        seen = 0
        for job in jobs:
            seen |= int(job.result())
    return seen


def fast_segment_start(pixels: np.ndarray, cfg: DPConfig) -> tuple[np.ndarray, np.ndarray]:
    """Same as :func:`dptbd.model.fixed.segment_start` (E = x, d = START), without int64 copies."""
    cfg.require_paper001_datapath("dptbd.model.fast")
    x = np.asarray(pixels)
    _check_pixels_nocopy(x, cfg.input_bits)
    energy = x.astype(ENERGY_DTYPE)  # x <= 2**B_in - 1 <= E_max: the saturation is a no-op
    direction = np.full(x.shape, cfg.start_code, dtype=DIRECTION_DTYPE)
    return energy, direction


def fast_dp_step(energy: np.ndarray, direction: np.ndarray, pixels: np.ndarray,
                 cfg: DPConfig, *, threads: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Same as :func:`dptbd.model.fixed.dp_step`: one frame of §4 on ``(..., H, W)`` arrays.

    A state outside the model's ranges (E not an integer in [0, 2**32), d not an integer
    in [0, M], shapes other than ``pixels``'s) is handed to the reference ``dp_step``, so
    that whatever it does (a result or an error) is reproduced exactly. ``threads``:
    worker threads over the leading (trial) axes; default ``numba.get_num_threads()``.
    """
    x = np.asarray(pixels)
    _check_pixels_nocopy(x, cfg.input_bits)
    e = np.asarray(energy)
    d = np.asarray(direction)
    if (x.ndim < 2 or x.size == 0 or x.shape[-2:] != (cfg.height, cfg.width)
            or e.shape != x.shape or d.shape != x.shape
            or not np.issubdtype(e.dtype, np.integer) or not np.issubdtype(d.dtype, np.integer)):
        return fixed.dp_step(energy, direction, pixels, cfg)
    plan = _plan(cfg)
    e_hi, d_hi = int(e.max()), int(d.max())
    if int(e.min()) < 0 or e_hi >= 1 << 32 or int(d.min()) < 0 or d_hi > plan.start_code:
        return fixed.dp_step(energy, direction, pixels, cfg)

    height, width = cfg.height, cfg.width
    hw = height * width
    n_trials = x.size // hw
    e32 = np.ascontiguousarray(e, dtype=np.uint32).reshape(n_trials, hw)
    d8 = np.ascontiguousarray(d, dtype=np.uint8).reshape(n_trials, hw)
    frames = np.zeros((n_trials, 2, hw), np.uint16)  # a two-frame segment; frame 0 is unused
    frames[:, 1] = x.reshape(n_trials, hw)
    out_e = np.empty(x.shape, dtype=ENERGY_DTYPE)
    out_d = np.empty(x.shape, dtype=DIRECTION_DTYPE)
    common = (frames.reshape(-1), 2, 1, 1, 2, out_e.reshape(-1), out_d.reshape(-1), height,
              width, plan.radius)
    if plan.binary and e_hi < plan.key_limit:
        r = plan.radius
        shape = (n_trials, height + 2 * r, width + 2 * r)
        es = np.zeros(shape, dtype=np.uint32)  # zero margins: out-of-image predecessors
        oh = np.zeros(shape, dtype=np.uint32)
        es[:, r:r + height, r:r + width] = (e32.reshape(n_trials, height, width)
                                            << plan.key_shift) | plan.key_low
        oh[:, r:r + height, r:r + width] = np.left_shift(
            np.uint32(1), d8.reshape(n_trials, height, width).astype(np.uint32))
        args = common + (1, plan.bits, plan.fulls, plan.tags, plan.key_shift, plan.e_max,
                         plan.key_low, plan.start_onehot, es.reshape(n_trials, -1),
                         oh.reshape(n_trials, -1))
        _spread(_binary_kernel, args, n_trials, _resolve_threads(threads, n_trials))
    else:
        args = common + (plan.offsets_flat, plan.dys, plan.dxs, plan.tags64, plan.lut_t,
                         plan.frac_bits, plan.half, plan.key_shift, plan.e_max, plan.key_low,
                         plan.start_code, e32, d8)
        _spread(_general_kernel, args, n_trials, _resolve_threads(threads, n_trials))
    return out_e, out_d


def _run_schedule(arr: np.ndarray, cfg: DPConfig, schedule, threads) -> SegmentOutput:
    """A run-time schedule: each run of consecutive segments of one K is one kernel call on
    its frames (a configuration with that K)."""
    spans = segment_spans(cfg, arr.shape[-3], schedule)
    runs: list[tuple[int, int, int]] = []          # (first frame, K, segments)
    for first, k in spans:
        if runs and runs[-1][1] == k and runs[-1][0] + runs[-1][1] * runs[-1][2] == first:
            runs[-1] = (runs[-1][0], k, runs[-1][2] + 1)
        else:
            runs.append((first, k, 1))
    parts = []
    for first, k, count in runs:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EnergyWidthWarning)   # warned for cfg already
            cfg_k = cfg.replace(segment_frames=k)
        parts.append(run_fixed_fast(arr[..., first:first + k * count, :, :], cfg_k,
                                    threads=threads))
    lead = arr.shape[:-3]
    empty = np.zeros(lead + (0, cfg.height, cfg.width))
    energy = np.concatenate([p.energy for p in parts], axis=-3) if parts else \
        empty.astype(ENERGY_DTYPE)
    direction = np.concatenate([p.direction for p in parts], axis=-3) if parts else \
        empty.astype(DIRECTION_DTYPE)
    ends = np.array([first + k - 1 for first, k in spans], dtype=np.int64)
    return SegmentOutput(energy, direction, ends)


def run_fixed_fast(frames: np.ndarray, cfg: DPConfig, *, threads: int | None = None,
                   schedule=None) -> SegmentOutput:
    """Same as :func:`dptbd.model.fixed.run_fixed`: accumulate ``(..., T, H, W)`` per segment.

    Bit-exact with the reference and raises the same errors for the same bad input.
    ``threads``: worker threads over the independent (trial, segment) pairs; default
    ``numba.get_num_threads()``. The result does not depend on it. ``schedule``: run-time
    settings per segment, as for the reference (each run of one K is one kernel call).
    """
    arr = check_sequence(frames, cfg, schedule)
    if schedule is not None:
        check_pixels(arr, cfg.input_bits)
        return _run_schedule(arr, cfg, schedule, threads)
    # uint8/uint16 pixels are range-checked by the kernel as it reads them (an OR of all of
    # them); any other dtype is checked here, before the lossless cast to uint16
    fused_check = arr.dtype in (np.uint8, np.uint16)
    if not fused_check:
        _check_pixels_nocopy(arr, cfg.input_bits)
    plan = _plan(cfg)
    lead = arr.shape[:-3]
    n_frames = arr.shape[-3]
    height, width = cfg.height, cfg.width
    n_trials = int(np.prod(lead, dtype=np.int64))
    n_seg = cfg.n_segments(n_frames)
    k = cfg.segment_frames
    stride = cfg.segment_stride
    ends = np.arange(n_seg, dtype=np.int64) * stride + k - 1
    out_e = np.empty(lead + (n_seg, height, width), dtype=ENERGY_DTYPE)
    out_d = np.empty(lead + (n_seg, height, width), dtype=DIRECTION_DTYPE)
    n_tasks = n_trials * n_seg
    if n_tasks == 0 or k == 1:
        if fused_check:
            _check_pixels_nocopy(arr, cfg.input_bits)
        # every frame is its own segment start: E = x, d = START
        out_e[...] = arr[..., ::stride, :, :][..., :n_seg, :, :]
        out_d[...] = cfg.start_code
        return SegmentOutput(out_e, out_d, ends)
    px = _as_kernel_pixels(arr)
    n_threads = _resolve_threads(threads, n_tasks)
    common = (px.reshape(-1), n_frames, n_seg, stride, k, out_e.reshape(-1), out_d.reshape(-1),
              height, width, plan.radius)
    if kernel_path(cfg) == "binary":
        ring_level = 2 * (2 * plan.radius + 1) * plan.padded_width * 4  # one step's rings
        group = int(max(1, min(k - 1, _MAX_GROUP, _RING_BUDGET // ring_level)))
        no_state = np.zeros((0, 0), np.uint32)
        args = common + (group, plan.bits, plan.fulls, plan.tags, plan.key_shift, plan.e_max,
                         plan.key_low, plan.start_onehot, no_state, no_state)
        seen = _spread(_binary_kernel, args, n_tasks, n_threads)
    else:
        args = common + (plan.offsets_flat, plan.dys, plan.dxs, plan.tags64, plan.lut_t,
                         plan.frac_bits, plan.half, plan.key_shift, plan.e_max, plan.key_low,
                         plan.start_code, np.zeros((0, 0), np.uint32), np.zeros((0, 0), np.uint8))
        seen = _spread(_general_kernel, args, n_tasks, n_threads)
    if fused_check:
        covered = (n_seg - 1) * stride + k  # the kernel read frames 0 .. covered - 1
        trailing = arr[..., covered:, :, :]
        if seen >> cfg.input_bits or (trailing.size and int(trailing.max()) >> cfg.input_bits):
            _check_pixels_nocopy(arr, cfg.input_bits)  # raises the reference's error
    return SegmentOutput(out_e, out_d, ends)
