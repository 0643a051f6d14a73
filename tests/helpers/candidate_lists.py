"""Synthetic candidate lists for the association tests (``tests/dsp/association``): the records
a segment would hand to the DSP (row, col, E, d and the backtracked path start)."""

import numpy as np

from dptbd.dsp.association import CANDIDATE_DTYPE, AssociationConfig, Tracker

K = 6  # frames per segment; stride K


def cand(row, col, energy=1000, row0=None, col0=None):
    """One candidate; its path start defaults to no motion."""
    return (row, col, energy, 4, row if row0 is None else row0, col if col0 is None else col0, 1)


def target_cand(start, vel, s, energy=2000):
    """A target moving at ``vel`` px/frame: its pixel at segment s's last frame and path start."""
    end = s * K + K - 1
    r, c = (round(start[0] + vel[0] * end), round(start[1] + vel[1] * end))
    r0, c0 = (round(start[0] + vel[0] * (end - K + 1)), round(start[1] + vel[1] * (end - K + 1)))
    return cand(r, c, energy, r0, c0)


def records(items):
    return np.array(items, dtype=CANDIDATE_DTYPE)


def clutter(rng, n, avoid=None, size=128):
    out = []
    while len(out) < n:
        r, c = (int(x) for x in rng.integers(0, size, 2))
        if avoid is not None and abs(r - avoid[0]) <= 8 and abs(c - avoid[1]) <= 8:
            continue
        out.append(cand(r, c, int(rng.integers(500, 1500)), int(rng.integers(max(r - 5, 0), r + 6)),
                        int(rng.integers(max(c - 5, 0), c + 6))))
    return out


def tracker(**kw):
    return Tracker(AssociationConfig(**kw), segment_frames=K, segment_stride=K, height=128,
                   width=128)
