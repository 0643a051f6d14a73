"""The keys both kernels of :mod:`dptbd.model.fast` compute: a candidate as ``(C << s) | tag``
with ``tag = 2**s - 1 - m``, so that the unsigned max of the keys is the max C and, among
equal C, the lowest move index (``docs/arithmetic.md`` §4.4); and the decoding of a row of
winning keys into a segment's final (E, d).
"""

import numpy as np
from numba import njit


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
