"""The records of the DSP stage and their fixed-point layout (paper 001 §3's record structure).

* Fixed point: positions and velocities in 1/16 pixel (:data:`Q_BITS`, :data:`ONE`), ratios
  in 1/256 (``RATIO_BITS``, ``RATIO_ONE``); divisions round half up (:func:`div_round`).
* :data:`CANDIDATE_DTYPE` — one candidate as the DSP receives it (the FPGA's (row, col, E,
  d) plus the start of its backtracked path); :func:`make_candidates` builds them on the
  host, :func:`trim_to_count` is the DSP's input stage (the constant-false-alarm-count rule
  applied to a received list).
* :data:`TRACK_DTYPE` — one track record (states :data:`FREE`, :data:`TENTATIVE`,
  :data:`CONFIRMED`); :data:`POINT_DTYPE` — one point of a track's history.
* :class:`ConfirmedTrack` — a confirmed track as the host reads it out.

The tracker that fills these records is :class:`dptbd.dsp.association.Tracker`; every name
here is importable from :mod:`dptbd.dsp.association` too.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.dsp.errors import AssociationError

__all__ = [
    "Q_BITS",
    "ONE",
    "RATIO_BITS",
    "RATIO_ONE",
    "FREE",
    "TENTATIVE",
    "CONFIRMED",
    "CANDIDATE_DTYPE",
    "TRACK_DTYPE",
    "POINT_DTYPE",
    "ConfirmedTrack",
    "div_round",
    "make_candidates",
    "trim_to_count",
]

#: Fractional bits of positions and velocities: 1/16 pixel.
Q_BITS = 4
#: 1.0 in the records' fixed point (1/16 pixel).
ONE = 1 << Q_BITS
#: Fractional bits of ratios: 1/256.
RATIO_BITS = 8
RATIO_ONE = 1 << RATIO_BITS

#: Record states.
FREE, TENTATIVE, CONFIRMED = 0, 1, 2

#: One candidate point as the DSP receives it: the FPGA's (row, col, E, d) and the start
#: (row0, col0) of its best path in the segment; ``path`` = 1 when row0/col0 are known.
CANDIDATE_DTYPE = np.dtype([
    ("row", np.uint16), ("col", np.uint16), ("energy", np.uint32), ("direction", np.uint8),
    ("row0", np.uint16), ("col0", np.uint16), ("path", np.uint8)])

#: One track record (001 §3's record structure), positions and velocities in Q4 pixels.
TRACK_DTYPE = np.dtype([
    ("state", np.uint8),             # FREE, TENTATIVE or CONFIRMED
    ("id", np.uint32),               # unique track number, from 1
    ("first_seg", np.int32),         # segment of the first point
    ("confirm_seg", np.int32),       # segment in which it passed the output threshold, -1
    ("p_seg", np.int32, (2,)),       # 轨迹最近两点: segments of [older, newest] point
    ("p_row", np.int32, (2,)),       #   rows (Q4)
    ("p_col", np.int32, (2,)),       #   cols (Q4)
    ("v_row", np.int32),             # velocity, Q4 pixels per segment
    ("v_col", np.int32),
    ("pred_row", np.int32),          # 预测点 for the next segment (Q4)
    ("pred_col", np.int32),
    ("count_seg", np.int32),         # segment of the newest hit counted toward confirmation
    ("length", np.uint16),           # 轨迹总长度: segments since the first point, inclusive
    ("hits", np.uint16),             # 总匹配点数
    ("gate", np.uint16),             # 匹配允许偏差距离 (Q4 pixels, Euclidean radius)
    ("counted", np.uint16),          # hits counted toward confirmation (confirm_disjoint)
    ("misses", np.uint8),            # 连续丢失目标点数
    ("n_points", np.uint32),         # points ever written to the history (ring)
])

#: One measured point of a track's history.
POINT_DTYPE = np.dtype([
    ("seg", np.int32), ("row", np.uint16), ("col", np.uint16), ("energy", np.uint32),
    ("row0", np.uint16), ("col0", np.uint16), ("path", np.uint8)])


def div_round(a: int, b: int) -> int:
    """``a / b`` rounded half up (toward +inf) in integers, for ``b > 0``."""
    return (2 * a + b) // (2 * b)


@dataclasses.dataclass(frozen=True)
class ConfirmedTrack:
    """A confirmed track as the host reads it out (not part of the DSP core).

    Attributes
    ----------
    id : int
        Track number.
    first_segment, confirm_segment, last_segment : int
        Segment of the first point, of confirmation (output threshold passed) and of the
        newest point.
    hits, length : int
        Matched points and length in segments (first to last segment counted at the end).
    alive : bool
        Still in the record array at the end of the sequence (else deleted).
    points : numpy.ndarray
        :data:`POINT_DTYPE` records, oldest first (the newest ``max_points`` if the ring
        wrapped).
    """

    id: int
    first_segment: int
    confirm_segment: int
    last_segment: int
    hits: int
    length: int
    alive: bool
    points: np.ndarray


def trim_to_count(records: np.ndarray, count: int) -> np.ndarray:
    """DSP input stage: the constant-false-alarm-count rule applied to a received list.

    Keeps the records whose E exceeds the (count+1)-th largest E of the list (all of them
    when the list holds at most ``count``), in the list's (raster) order: the rule of
    ``docs/arithmetic.md`` §6 applied to the list instead of the image, ties at the
    boundary excluded. When the FPGA's list holds every pixel with E >= the image's
    (count+1)-th largest value, the result is exactly the ideal list of the segment's own
    image. Work: one partial selection over at most ``max_candidates`` records.
    """
    if count < 0:
        raise AssociationError(f"count must be an integer in [0, inf), got {count}")
    if len(records) <= count:
        return records
    energy = np.asarray(records["energy"])
    kth = np.partition(energy, len(energy) - count - 1)[len(energy) - count - 1]
    return records[energy > kth]


def make_candidates(candidates: np.ndarray, paths: np.ndarray | None = None) -> np.ndarray:
    """Host side: FPGA candidate records (row, col, E, d) plus their backtracked paths.

    Parameters
    ----------
    candidates : numpy.ndarray
        Records with fields ``row``, ``col``, ``energy``, ``direction``
        (:func:`dptbd.model.segmentation.candidates`).
    paths : numpy.ndarray, optional
        ``(n, K, 2)`` backtracked paths (:func:`dptbd.dsp.backtrack.candidate_paths`);
        their first point becomes ``(row0, col0)``.

    Returns
    -------
    numpy.ndarray
        :data:`CANDIDATE_DTYPE` records.
    """
    out = np.zeros(len(candidates), dtype=CANDIDATE_DTYPE)
    for name in ("row", "col", "direction"):
        out[name] = candidates[name]
    energy = np.asarray(candidates["energy"])
    if energy.size and (energy.min() < 0 or energy.max() > np.iinfo(np.uint32).max
                        or not np.issubdtype(energy.dtype, np.integer)):
        raise AssociationError("candidate energies must be unsigned 32-bit integers")
    out["energy"] = energy
    if paths is not None:
        paths = np.asarray(paths)
        if paths.shape[0] != len(candidates) or paths.ndim != 3 or paths.shape[2] != 2:
            raise AssociationError(f"paths must have shape ({len(candidates)}, K, 2), "
                                   f"got {paths.shape}")
        out["row0"], out["col0"] = paths[:, 0, 0], paths[:, 0, 1]
        out["path"] = 1
    else:
        out["row0"], out["col0"] = out["row"], out["col"]
    return out
