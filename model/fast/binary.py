"""The binary kernel of :mod:`dptbd.model.fast` (:func:`~dptbd.model.fast.kernel_path`
``"binary"``).

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
"""

import numpy as np
from numba import njit
from numba.extending import overload

from dptbd.model.fast.keys import _emit_final


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
