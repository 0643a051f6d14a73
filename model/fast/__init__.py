"""Fused compiled kernel of the fixed-point golden model, bit-exact with ``dptbd.model.fixed``.

``dptbd.model.fixed`` is the readable reference: one numpy pass per operator and move,
``int64`` temporaries, every frame materialised. This module computes the same bits
(``docs/arithmetic.md`` §4-§5) with numba, fused into one loop per output row, and is
checked against the reference bit for bit by ``tests/model/fast/test_init.py``. Public functions
mirror the reference: :func:`fast_segment_start`, :func:`fast_dp_step`,
:func:`run_fixed_fast` (same arguments, results and errors; an optional keyword
``threads``).

Two kernels, chosen per configuration (:func:`kernel_path`):

``"binary"``
    Every weight code is 0 or 2**F (true of the paper's eq (11) LUT and of the plain
    all-ones LUT) and ``E << s`` fits 32 bits, where ``s`` is the width of a move index
    (4 for r = 1, 5 for r = 2; so B_E <= 28 resp. 27). A weighted candidate is then
    exactly E or 0 in both rounding modes (``(E * 2**F + h) >> F = E`` and
    ``(0 + h) >> F = 0`` because ``h < 2**F``), so no multiply is needed:

    * a pixel's state is stored as ``es = (E << s) | (2**s - 1)`` and the one-hot
      direction ``oh = 1 << d``; the planes carry an r-pixel margin of zeros all round;
    * candidate m from predecessor q is the 32-bit key
      ``es[q] & (full_m if oh[q] & bits[m] else tag_m)`` with ``tag_m = 2**s - 1 - m``,
      ``full_m = (~0 << s) | tag_m`` and ``bits[m]`` the LUT column m as a bit mask over
      predecessor directions. That is ``(C << s) | tag_m`` for an in-image predecessor
      and 0 for the zero margin (§4.1: out-of-image predecessors never win, even against
      C = 0, because every in-image key is >= its tag >= 2**s - M > 0);
    * the unsigned max of the keys is the max C and, among equal C, the lowest move
      index (§4.4), with no separate argmax; E and d are decoded from the winning key;
    * the moves are unrolled (9 or 25) into one branch-free loop over a row, which LLVM
      vectorises; the margin means border pixels need no special case;
    * the K - 1 steps of a segment run as a wavefront over rows: step k computes row y
      as soon as step k - 1 has produced rows y - r .. y + r, so intermediate states
      live in (2r + 1)-row ring buffers that stay in cache (the software twin of the
      gateware's line buffers). Only the frames are read and only each segment's
      accumulated image and direction map are written.

``"general"``
    Any LUT and any B_E <= 32: the reference arithmetic literally, ``C = (E * c + h) >> F``
    in ``int64`` with the code looked up per predecessor, packed into 64-bit keys, one
    full-frame step at a time. Slower; used when the binary kernel does not apply.

Independent (trial, segment) pairs are spread over threads (the kernels release the
GIL); each is computed by one thread, so the result does not depend on the thread count.
"""

from __future__ import annotations

import dataclasses
import functools
import warnings
from concurrent.futures import ThreadPoolExecutor

import numba
import numpy as np
from numba import njit
from numba.extending import overload

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.model import fixed
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


# ==== host side: the per-configuration constants ==========================================

@dataclasses.dataclass(frozen=True)
class _Plan:
    """Constants of one configuration, in the types the kernels expect."""

    radius: int
    n_moves: int
    binary: bool           # every weight code is 0 or 2**F
    key_shift: np.uint32   # s: width of the move-index field of a key
    key_low: np.uint32     # 2**s - 1
    key_limit: int         # the binary kernel needs every E < key_limit (E << s fits 32 bits)
    padded_width: int      # W + 2r: row stride of the binary kernel's zero-margined planes
    tags: tuple            # uint32 2**s - 1 - m per move
    fulls: tuple           # uint32 (~0 << s) | tag_m per move
    bits: tuple            # uint32 column masks: bit p of bits[m] <=> code[p, m] != 0
    offsets_flat: np.ndarray  # general kernel: uint64 flat offset of move m's predecessor,
    #                           -dy * W - dx (mod 2**64)
    dys: np.ndarray        # general kernel: int64 dy per move
    dxs: np.ndarray        # general kernel: int64 dx per move
    tags64: np.ndarray     # general kernel: the tags as uint64
    start_onehot: np.uint32
    lut_t: np.ndarray      # int64 (M, M + 1): the codes transposed, [move, predecessor d]
    frac_bits: int
    half: int              # rounding constant added before >> F
    e_max: np.uint32
    start_code: int


@functools.lru_cache(maxsize=64)
def _plan(cfg: DPConfig) -> _Plan:
    cfg.require_paper001_datapath("dptbd.model.fast")
    n_moves = cfg.n_moves
    codes = cfg.weight_codes.astype(np.int64)
    frac = cfg.weight_frac_bits
    s = (n_moves - 1).bit_length()
    moves = cfg.moves
    tags = [(1 << s) - 1 - m for m in range(n_moves)]
    return _Plan(
        radius=cfg.radius, n_moves=n_moves,
        binary=bool(np.all((codes == 0) | (codes == 1 << frac))),
        key_shift=np.uint32(s), key_low=np.uint32((1 << s) - 1), key_limit=1 << (32 - s),
        padded_width=cfg.width + 2 * cfg.radius,
        tags=tuple(np.uint32(t) for t in tags),
        fulls=tuple(np.uint32(((0xFFFFFFFF << s) & 0xFFFFFFFF) | t) for t in tags),
        offsets_flat=(-moves[:, 0] * cfg.width - moves[:, 1]).astype(np.uint64),
        dys=np.ascontiguousarray(moves[:, 0]), dxs=np.ascontiguousarray(moves[:, 1]),
        tags64=np.array(tags, dtype=np.uint64),
        bits=tuple(np.uint32(sum(1 << p for p in range(n_moves + 1) if codes[p, m]))
                   for m in range(n_moves)),
        start_onehot=np.uint32(1 << n_moves),
        lut_t=np.ascontiguousarray(codes.T), frac_bits=frac,
        half=(1 << (frac - 1)) if (cfg.rounding == "half_up" and frac > 0) else 0,
        e_max=np.uint32(cfg.e_max), start_code=cfg.start_code)


def kernel_path(cfg: DPConfig) -> str:
    """The kernel :func:`run_fixed_fast` uses for ``cfg``: ``"binary"`` or ``"general"``."""
    plan = _plan(cfg)
    return "binary" if plan.binary and cfg.e_max < plan.key_limit else "general"


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


# ==== binary kernel: one row of keys ======================================================

@njit
def _first(es, oh, j, bit, full, tag):
    """Key of predecessor ``j``: ``(C << s) | tag`` in the image, 0 in the zero margin."""
    return np.uint32(es[j] & (full if oh[j] & bit else tag))


@njit
def _cand(best, es, oh, j, bit, full, tag):
    key = np.uint32(es[j] & (full if oh[j] & bit else tag))
    return key if key > best else best


def _row_keys(es, oh, rows, width, keys, b, f, t):  # pragma: no cover - see the overload
    """Best key of pixels 0 .. width - 1 of one row.

    ``rows[g]`` is the flat index of column 0 of predecessor row ``y + r - g`` (the rows
    of moves with dy = g - r); per move: column mask ``b``, full mask ``f``, tag ``t``.
    """
    raise NotImplementedError


def _keys_r1(es, oh, rows, width, keys, b, f, t):
    o0 = rows[0] + np.uint64(1)
    o1 = rows[0]
    o2 = rows[0] - np.uint64(1)
    o3 = rows[1] + np.uint64(1)
    o4 = rows[1]
    o5 = rows[1] - np.uint64(1)
    o6 = rows[2] + np.uint64(1)
    o7 = rows[2]
    o8 = rows[2] - np.uint64(1)
    for x in range(np.uint64(width)):
        k = _first(es, oh, o0 + x, b[0], f[0], t[0])
        k = _cand(k, es, oh, o1 + x, b[1], f[1], t[1])
        k = _cand(k, es, oh, o2 + x, b[2], f[2], t[2])
        k = _cand(k, es, oh, o3 + x, b[3], f[3], t[3])
        k = _cand(k, es, oh, o4 + x, b[4], f[4], t[4])
        k = _cand(k, es, oh, o5 + x, b[5], f[5], t[5])
        k = _cand(k, es, oh, o6 + x, b[6], f[6], t[6])
        k = _cand(k, es, oh, o7 + x, b[7], f[7], t[7])
        k = _cand(k, es, oh, o8 + x, b[8], f[8], t[8])
        keys[x] = k


def _keys_r2(es, oh, rows, width, keys, b, f, t):
    o0 = rows[0] + np.uint64(2)
    o1 = rows[0] + np.uint64(1)
    o2 = rows[0]
    o3 = rows[0] - np.uint64(1)
    o4 = rows[0] - np.uint64(2)
    o5 = rows[1] + np.uint64(2)
    o6 = rows[1] + np.uint64(1)
    o7 = rows[1]
    o8 = rows[1] - np.uint64(1)
    o9 = rows[1] - np.uint64(2)
    o10 = rows[2] + np.uint64(2)
    o11 = rows[2] + np.uint64(1)
    o12 = rows[2]
    o13 = rows[2] - np.uint64(1)
    o14 = rows[2] - np.uint64(2)
    o15 = rows[3] + np.uint64(2)
    o16 = rows[3] + np.uint64(1)
    o17 = rows[3]
    o18 = rows[3] - np.uint64(1)
    o19 = rows[3] - np.uint64(2)
    o20 = rows[4] + np.uint64(2)
    o21 = rows[4] + np.uint64(1)
    o22 = rows[4]
    o23 = rows[4] - np.uint64(1)
    o24 = rows[4] - np.uint64(2)
    for x in range(np.uint64(width)):
        k = _first(es, oh, o0 + x, b[0], f[0], t[0])
        k = _cand(k, es, oh, o1 + x, b[1], f[1], t[1])
        k = _cand(k, es, oh, o2 + x, b[2], f[2], t[2])
        k = _cand(k, es, oh, o3 + x, b[3], f[3], t[3])
        k = _cand(k, es, oh, o4 + x, b[4], f[4], t[4])
        k = _cand(k, es, oh, o5 + x, b[5], f[5], t[5])
        k = _cand(k, es, oh, o6 + x, b[6], f[6], t[6])
        k = _cand(k, es, oh, o7 + x, b[7], f[7], t[7])
        k = _cand(k, es, oh, o8 + x, b[8], f[8], t[8])
        k = _cand(k, es, oh, o9 + x, b[9], f[9], t[9])
        k = _cand(k, es, oh, o10 + x, b[10], f[10], t[10])
        k = _cand(k, es, oh, o11 + x, b[11], f[11], t[11])
        k = _cand(k, es, oh, o12 + x, b[12], f[12], t[12])
        k = _cand(k, es, oh, o13 + x, b[13], f[13], t[13])
        k = _cand(k, es, oh, o14 + x, b[14], f[14], t[14])
        k = _cand(k, es, oh, o15 + x, b[15], f[15], t[15])
        k = _cand(k, es, oh, o16 + x, b[16], f[16], t[16])
        k = _cand(k, es, oh, o17 + x, b[17], f[17], t[17])
        k = _cand(k, es, oh, o18 + x, b[18], f[18], t[18])
        k = _cand(k, es, oh, o19 + x, b[19], f[19], t[19])
        k = _cand(k, es, oh, o20 + x, b[20], f[20], t[20])
        k = _cand(k, es, oh, o21 + x, b[21], f[21], t[21])
        k = _cand(k, es, oh, o22 + x, b[22], f[22], t[22])
        k = _cand(k, es, oh, o23 + x, b[23], f[23], t[23])
        k = _cand(k, es, oh, o24 + x, b[24], f[24], t[24])
        keys[x] = k


@overload(_row_keys)
def _row_keys_overload(es, oh, rows, width, keys, b, f, t):
    """The loop unrolled for the window size (9 or 25 moves), chosen at compile time."""
    if b.count == 9:
        return _keys_r1
    if b.count == 25:
        return _keys_r2
    return None


@njit
def _slot(base, z, shift, n_slots, stride, r):
    """Flat index of column 0 of row z in a zero-margined plane of rows (z + shift) mod n_slots."""
    return base + np.uint64(((z + shift) % n_slots) * stride + r)


def _window(base, y, shift, n_slots, stride, r, b):  # pragma: no cover - see the overload
    """``rows`` for :func:`_row_keys` of output row ``y``: rows y + r, ..., y - r."""
    raise NotImplementedError


def _window_r1(base, y, shift, n_slots, stride, r, b):
    return (_slot(base, y + 1, shift, n_slots, stride, r),
            _slot(base, y, shift, n_slots, stride, r),
            _slot(base, y - 1, shift, n_slots, stride, r))


def _window_r2(base, y, shift, n_slots, stride, r, b):
    return (_slot(base, y + 2, shift, n_slots, stride, r),
            _slot(base, y + 1, shift, n_slots, stride, r),
            _slot(base, y, shift, n_slots, stride, r),
            _slot(base, y - 1, shift, n_slots, stride, r),
            _slot(base, y - 2, shift, n_slots, stride, r))


@overload(_window)
def _window_overload(base, y, shift, n_slots, stride, r, b):
    if b.count == 9:
        return _window_r1
    if b.count == 25:
        return _window_r2
    return None


@njit
def _emit_state(keys, px, pi, de, dh, di, width, s, e_max, low):
    """Decode a row of keys, add the pixels saturating (§4.5); store ``es`` and ``oh``.

    Returns the OR of the pixels read (the caller's range check).
    """
    s_mask = np.uint32(31)
    s = s & s_mask  # shift counts < 32 let LLVM keep the shifts 32 bits wide
    seen = np.uint32(0)
    for x in range(np.uint64(width)):  # unsigned indices: no negative-index fix-up
        key = keys[x]
        e = np.uint32(key >> s)
        xx = np.uint32(px[pi + x])
        seen = np.uint32(seen | xx)
        v = e_max if e > np.uint32(e_max - xx) else np.uint32(e + xx)
        de[di + x] = np.uint32((v << s) | low)
        dh[di + x] = np.uint32(np.uint32(1) << ((low - (key & low)) & s_mask))
    return seen


@njit
def _emit_final(keys, px, pi, de, dd, di, width, s, e_max, low):
    """Decode a row of keys, add the pixels saturating (§4.5); store E (uint32), d (uint8).

    Returns the OR of the pixels read.
    """
    s = s & np.uint32(31)
    seen = np.uint32(0)
    for x in range(np.uint64(width)):
        key = keys[x]
        e = np.uint32(key >> s)
        xx = np.uint32(px[pi + x])
        seen = np.uint32(seen | xx)
        de[di + x] = e_max if e > np.uint32(e_max - xx) else np.uint32(e + xx)
        dd[di + x] = np.uint8(low - (key & low))
    return seen


# ==== binary kernel: segments as wavefronts over rows ======================================

@njit(nogil=True, cache=True)
def _binary_kernel(frames, n_frames_total, n_seg, stride, seg_frames, out_e, out_d, height,
                   width, r, group, bits, fulls, tags, s, e_max, low, start_onehot, state_e,
                   state_h, task0, task1, task_step):
    """Tasks ``task0, task0 + task_step, ... < task1``, each one segment written to out[task].

    A run (``state_e`` empty): task = trial * n_seg + segment, frames ``(trials, T, H*W)``.
    A step (``state_e`` has a row per trial, ``seg_frames`` = 2): trial ``task`` starts
    from the zero-margined planes ``state_e[task]``, ``state_h[task]`` and adds frame
    ``frames[task, 1]``.

    Level 0 is the segment's first frame (E = x, d = START) or the given state; level t
    the state after step t. A group of up to ``group`` steps runs as a wavefront: at
    iteration i, level a's row i enters ring 0 and step k of the group computes its row
    i - k*r from ring k - 1, which then holds rows i - k*r - r .. i - k*r + r (the 2r + 1
    rows it keeps, row z in slot z mod (2r + 1)). Rows outside the image read as zeros:
    the rings are zeroed when a group starts (the rows above) and a ring's rows
    H .. H + r - 1 are written as zeros (the rows below). The last step writes the
    output; a group that is not the last hands over through a full-frame plane.

    Returns the OR of every pixel read, for the caller's range check.
    """
    hw = height * width
    wp = width + 2 * r
    ring_rows = 2 * r + 1
    level_size = ring_rows * wp
    full_rows = height + 2 * r
    from_state = state_e.shape[0] > 0
    ring_e = np.zeros(group * level_size, np.uint32)
    ring_h = np.zeros_like(ring_e)
    scratch_e = np.zeros(full_rows * wp if seg_frames - 1 > group else 0, np.uint32)
    scratch_h = np.zeros_like(scratch_e)  # its zero margins are never written
    keys = np.empty(width, np.uint32)
    zero = np.uint32(0)
    seen = np.uint32(0)
    for task in range(task0, task1, task_step):
        if from_state:
            fbase = np.uint64(2 * task * hw)
            full_e = state_e[task]
            full_h = state_h[task]
        else:
            n = task // n_seg
            fbase = np.uint64((n * n_frames_total + (task - n * n_seg) * stride) * hw)
            full_e = scratch_e
            full_h = scratch_h
        obase = np.uint64(task * hw)
        a = 0
        while a < seg_frames - 1:
            nl = min(group, seg_frames - 1 - a)
            for j in range(ring_e.size):  # (a loop: slice assignment is slow to compile)
                ring_e[j] = zero
                ring_h[j] = zero
            for i in range(height + nl * r):
                d0 = _slot(np.uint64(0), i, 0, ring_rows, wp, r)
                if i < height:  # level a, row i -> ring 0
                    if a == 0 and not from_state:
                        src = fbase + np.uint64(i * width)
                        for x in range(np.uint64(width)):
                            xx = np.uint32(frames[src + x])
                            seen = np.uint32(seen | xx)
                            ring_e[d0 + x] = np.uint32((xx << s) | low)
                            ring_h[d0 + x] = start_onehot
                    else:
                        src = _slot(np.uint64(0), i, r, full_rows, wp, r)
                        for x in range(np.uint64(width)):
                            ring_e[d0 + x] = full_e[src + x]
                            ring_h[d0 + x] = full_h[src + x]
                elif i < height + r:
                    for x in range(np.uint64(width)):
                        ring_e[d0 + x] = zero
                for k in range(1, nl + 1):
                    y = i - k * r
                    if y < 0:
                        break
                    if y >= height:
                        if k < nl and y < height + r:
                            d0 = _slot(np.uint64(k * level_size), y, 0, ring_rows, wp, r)
                            for x in range(np.uint64(width)):
                                ring_e[d0 + x] = zero
                        continue
                    rows = _window(np.uint64((k - 1) * level_size), y, 0, ring_rows, wp, r,
                                   bits)
                    _row_keys(ring_e, ring_h, rows, width, keys, bits, fulls, tags)
                    pi = fbase + np.uint64((a + k) * hw + y * width)
                    if a + k == seg_frames - 1:
                        got = _emit_final(keys, frames, pi, out_e, out_d,
                                          obase + np.uint64(y * width), width, s, e_max, low)
                    elif k == nl:
                        got = _emit_state(keys, frames, pi, full_e, full_h,
                                          _slot(np.uint64(0), y, r, full_rows, wp, r), width, s,
                                          e_max, low)
                    else:
                        got = _emit_state(keys, frames, pi, ring_e, ring_h,
                                          _slot(np.uint64(k * level_size), y, 0, ring_rows, wp,
                                                r), width, s, e_max, low)
                    seen = np.uint32(seen | got)
            a += nl
    return seen


# ==== general kernel: any LUT, 64-bit keys, one full-frame step at a time =================

@njit
def _row_keys_general(e_in, d_in, ci, y, height, width, r, keys, offs, dys, dxs, tags64,
                      lut_t, frac, half, s):
    """Best 64-bit key ``(C << s) | tag`` of every pixel of row ``y``, any weight LUT."""
    n_moves = offs.shape[0]
    interior_row = y >= r and y < height - r
    for x in range(width):
        i = ci + np.uint64(x)
        best = np.uint64(0)  # below every in-image key (>= its tag > 0)
        interior = interior_row and x >= r and x < width - r
        for m in range(n_moves):
            if not interior:
                yy = y - dys[m]
                xx = x - dxs[m]
                if yy < 0 or yy >= height or xx < 0 or xx >= width:
                    continue  # out-of-image predecessor: never a candidate (§4.1)
            j = i + offs[m]
            c = (np.int64(e_in[j]) * lut_t[m, d_in[j]] + half) >> frac  # §4.3
            key = (np.uint64(c) << s) | tags64[m]
            if key > best:
                best = key
        keys[x] = best


@njit(nogil=True, cache=True)
def _general_kernel(frames, n_frames_total, n_seg, stride, seg_frames, out_e, out_d, height,
                    width, r, offs, dys, dxs, tags64, lut_t, frac, half, s, e_max, low,
                    start_code, state_e, state_d, task0, task1, task_step):
    """The tasks of :func:`_binary_kernel` (runs or steps), plain (E, d) full-frame states.

    Returns the OR of every pixel read.
    """
    hw = height * width
    from_state = state_e.shape[0] > 0
    e_a = np.empty(hw, np.uint32)
    d_a = np.empty(hw, np.uint8)
    e_b = np.empty(hw, np.uint32)
    d_b = np.empty(hw, np.uint8)
    keys = np.empty(width, np.uint64)
    seen = np.uint32(0)
    for task in range(task0, task1, task_step):
        if from_state:
            fbase = np.uint64(2 * task * hw)
            for p in range(hw):
                e_a[p] = state_e[task, p]
                d_a[p] = state_d[task, p]
        else:
            n = task // n_seg
            fbase = np.uint64((n * n_frames_total + (task - n * n_seg) * stride) * hw)
            for p in range(hw):  # segment start: E = x, d = START
                xx = np.uint32(frames[fbase + np.uint64(p)])
                seen = np.uint32(seen | xx)
                e_a[p] = xx
                d_a[p] = np.uint8(start_code)
        for t in range(1, seg_frames):
            for y in range(height):
                base = np.uint64(y * width)
                pi = fbase + np.uint64(t * hw + y * width)
                if t % 2 == 1:
                    _row_keys_general(e_a, d_a, base, y, height, width, r, keys, offs, dys, dxs,
                                      tags64, lut_t, frac, half, s)
                else:
                    _row_keys_general(e_b, d_b, base, y, height, width, r, keys, offs, dys, dxs,
                                      tags64, lut_t, frac, half, s)
                if t == seg_frames - 1:
                    got = _emit_final(keys, frames, pi, out_e, out_d, np.uint64(task * hw) + base,
                                      width, s, e_max, low)
                elif t % 2 == 1:
                    got = _emit_final(keys, frames, pi, e_b, d_b, base, width, s, e_max, low)
                else:
                    got = _emit_final(keys, frames, pi, e_a, d_a, base, width, s, e_max, low)
                seen = np.uint32(seen | got)
    return seen


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
