"""The general kernel of :mod:`dptbd.model.fast` (:func:`~dptbd.model.fast.kernel_path`
``"general"``).

Any LUT and any B_E <= 32: the reference arithmetic literally, ``C = (E * c + h) >> F``
in ``int64`` with the code looked up per predecessor, packed into 64-bit keys, one
full-frame step at a time. Slower; used when the binary kernel does not apply.
"""

import numpy as np
from numba import njit

from dptbd.model.fast.keys import _emit_final


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
