"""Histogram segmentation for a constant false-alarm count (paper 001 §2, last paragraph).

``docs/arithmetic.md`` §6: on an accumulated image keep the pixels whose E is strictly
greater than the (n+1)-th largest E, i.e. the histogram threshold "the smallest level
whose count from the top does not exceed n". At most n candidates; ties at the
boundary are excluded, never broken arbitrarily. Works on float and integer images
alike, with any leading (segment, trial) axes.

The second half is the bit-exact model of the gateware segmenter (``dptbd.hw.segmenter``,
§6.1 - §6.5): a histogram of ``min(E >> s, 2**b - 1)`` with saturating counters, the
threshold bin taken from the *previous* segment's histogram, at most C records per segment
in raster order and a trailer (:func:`segment_fixed`, :func:`segment_sequence` for whole
images, :func:`segment_stream` for any ``states`` stream). Each takes the gateware's run-time
settings (:mod:`dptbd.model.settings`): segment j's s bins its scored frame, its n thresholds
its histogram for list j + 1.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.config import DPConfig
from dptbd.errors import check_int, check_real
from dptbd.model.settings import Schedule, check_schedule, settings_of_segment

__all__ = ["candidate_dtype", "count_for_rate", "threshold_level", "candidate_mask", "candidates",
           "TRAILER_FIELDS", "CandidateList", "histogram_bins", "histogram_fixed",
           "threshold_bin", "segment_fixed", "segment_sequence", "segment_stream"]


def candidate_dtype(energy_dtype) -> np.dtype:
    """One candidate point record, as the FPGA hands it to the DSP: (row, col, E, d).

    E keeps the accumulated image's dtype (``uint32`` fixed point, ``float64`` float).
    """
    return np.dtype([("row", np.uint16), ("col", np.uint16),
                     ("energy", np.dtype(energy_dtype)), ("direction", np.uint8)])


def count_for_rate(rate: float, n_pixels: int) -> int:
    """The candidate count n for a false-alarm rate: ``round(rate * n_pixels)`` (half up).

    0.2 % of 128 x 128 gives 33 (paper 001 quotes "0.2 %, i.e. 35 false points").
    """
    rate = check_real("false-alarm rate", rate, 0.0, 1.0)
    n_pixels = check_int("n_pixels", n_pixels, 1)
    return int(np.floor(rate * n_pixels + 0.5))


def threshold_level(image: np.ndarray, count: int) -> np.ndarray:
    """The (n+1)-th largest value of each image (``-inf`` when n >= H*W).

    Parameters
    ----------
    image : numpy.ndarray
        ``(..., H, W)`` accumulated images.
    count : int
        n, the largest number of candidates wanted per image.
    """
    flat = np.asarray(image).reshape(np.shape(image)[:-2] + (-1,))
    n_pix = flat.shape[-1]
    count = check_int("candidate count", count, 0)
    if count >= n_pix:
        return np.full(flat.shape[:-1], -np.inf)
    kth = n_pix - count - 1  # ascending position of the (n+1)-th largest
    return np.partition(flat, kth, axis=-1)[..., kth]


def candidate_mask(image: np.ndarray, count: int) -> np.ndarray:
    """Boolean ``(..., H, W)``: the pixels kept by the threshold (at most ``count`` per image)."""
    level = threshold_level(image, count)
    return np.asarray(image) > level[..., None, None]


def candidates(energy: np.ndarray, direction: np.ndarray, count: int) -> np.ndarray:
    """The candidate point list of ONE accumulated image, in raster order.

    Returns
    -------
    numpy.ndarray
        Records of :func:`candidate_dtype`: (row, col, E, d).
    """
    energy = np.asarray(energy)
    if energy.ndim != 2 or np.shape(direction) != energy.shape:
        raise ValueError(
            f"energy and direction must be two images of the same shape (H, W), "
            f"got {energy.shape} and {np.shape(direction)}")
    rows, cols = np.nonzero(candidate_mask(energy, count))
    out = np.zeros(len(rows), dtype=candidate_dtype(energy.dtype))
    out["row"], out["col"] = rows, cols
    out["energy"] = energy[rows, cols]
    out["direction"] = np.asarray(direction)[rows, cols]
    return out


# ---------------------------------------------------------------------------------------
# Bit-exact model of the gateware segmenter (docs/arithmetic.md §6.2 - §6.5)
# ---------------------------------------------------------------------------------------

#: Fields of a list's trailer word, in layout order (``dptbd.hw.candidate_layout``).
#: The trailer word's fields, in order.
TRAILER_FIELDS = ("count", "threshold", "overflow", "primed", "aligned", "missed")


@dataclasses.dataclass(frozen=True)
class CandidateList:
    """What the segmenter emits for one segment: its records, then a trailer.

    Attributes
    ----------
    records : numpy.ndarray
        :func:`candidate_dtype` (``uint32`` E) records in raster order, at most C of them.
    count : int
        Records emitted, ``len(records)``.
    threshold : int
        The threshold bin T the records were selected with (``2**b``: none selected).
    overflow : bool
        More than C pixels reached T; the ones after the C-th in raster order were dropped.
    primed : bool
        T came from a histogram (False for the first segment after reset: T = 2**b).
    aligned : bool
        The list's frame ended with ``end_of_segment`` exactly where the segmenter's
        counters expected (always True for a well-formed stream).
    missed : bool
        An ``end_of_segment`` arrived outside a scored frame since the previous list (a
        segment was lost to a resynchronisation); always False for a well-formed stream.
    histogram : numpy.ndarray
        ``(2**b,)`` saturated bin counts of this list's frame: the next list's threshold
        comes from it.
    """

    records: np.ndarray
    count: int
    threshold: int
    overflow: bool
    primed: bool
    aligned: bool
    missed: bool
    histogram: np.ndarray

    @property
    def trailer(self) -> dict[str, int]:
        """The trailer word's fields (:data:`~.segmentation.TRAILER_FIELDS`) as integers."""
        return {name: int(getattr(self, name)) for name in TRAILER_FIELDS}


def histogram_bins(energy: np.ndarray, cfg: DPConfig, shift: int | None = None) -> np.ndarray:
    """The histogram bin of each E: ``min(E >> s, 2**b - 1)`` (``int64``), §6.2; ``shift``
    is a run-time s (default: the build value ``cfg.bin_shift``)."""
    e = np.asarray(energy).astype(np.int64)
    if e.size and (e.min() < 0 or e.max() > cfg.e_max):
        raise ValueError(f"energy must be in [0, E_max = {cfg.e_max}]")
    return np.minimum(e >> (cfg.bin_shift if shift is None else shift), cfg.n_bins - 1)


def histogram_fixed(energy: np.ndarray, cfg: DPConfig, shift: int | None = None) -> np.ndarray:
    """Saturating bin counts of one accumulated image, ``(2**b,)`` ``int64``, §6.2.

    Each counter is ``bin_count_bits`` = bitlen(C + 1) wide and saturates at
    ``2**bin_count_bits - 1`` (>= C + 1 >= n + 1). ``shift``: as :func:`histogram_bins`.
    """
    counts = np.bincount(histogram_bins(energy, cfg, shift).ravel(), minlength=cfg.n_bins)
    return np.minimum(counts, (1 << cfg.bin_count_bits) - 1).astype(np.int64)


def threshold_bin(histogram: np.ndarray, cfg: DPConfig, count: int | None = None) -> int:
    """The threshold bin T of a histogram: the scan of §6.3, bin 2**b - 1 down to 0.

    ``cum`` starts at 0 and becomes ``min(cum + h[a], n + 1)`` at bin a; T is the last
    (smallest) a with ``cum <= n``, or ``2**b`` if already the top bin has cum > n. This is
    the smallest T with ``sum(h[T:]) <= n``: at most n pixels of the histogram's image
    have a bin >= T, and every pixel of the bin T - 1 is excluded (ties are never broken).
    ``count`` is a run-time n (default: the build value ``cfg.n_candidates``).
    """
    h = np.asarray(histogram, dtype=np.int64)
    if h.shape != (cfg.n_bins,):
        raise ValueError(f"histogram must have {cfg.n_bins} bins, got shape {h.shape}")
    n = cfg.n_candidates if count is None else count
    cum = 0
    threshold = cfg.n_bins
    for a in range(cfg.n_bins - 1, -1, -1):
        cum = min(cum + int(h[a]), n + 1)
        if cum > n:
            break
        threshold = a
    return threshold


def segment_fixed(energy: np.ndarray, direction: np.ndarray, cfg: DPConfig,
                  prev_hist: np.ndarray | None = None, *, shift: int | None = None,
                  prev_count: int | None = None) -> CandidateList:
    """The segmenter's list for ONE accumulated image (§6.4), bit for bit.

    Parameters
    ----------
    energy, direction : numpy.ndarray
        ``(H, W)`` accumulated image and direction map of the segment.
    prev_hist : numpy.ndarray or None
        The previous list's :attr:`CandidateList.histogram` (the threshold comes from the
        *previous* segment, §6.1); ``None`` for the first segment after reset, which
        selects nothing (T = 2**b, ``primed`` False).
    shift : int or None
        This segment's run-time s (default ``cfg.bin_shift``).
    prev_count : int or None
        The previous segment's run-time n, which thresholds ``prev_hist`` (default
        ``cfg.n_candidates``).

    Returns
    -------
    CandidateList
        The pixels with ``bin(E) >= T``, the first C of them in raster order; the trailer
        fields; this image's histogram for the next segment.
    """
    energy = np.asarray(energy)
    if energy.shape != (cfg.height, cfg.width) or np.shape(direction) != energy.shape:
        raise ValueError(
            f"energy and direction must both have shape (H, W) = ({cfg.height}, {cfg.width}), "
            f"got {energy.shape} and {np.shape(direction)}")
    bins = histogram_bins(energy, cfg, shift)
    primed = prev_hist is not None
    threshold = threshold_bin(prev_hist, cfg, prev_count) if primed else cfg.n_bins
    rows, cols = np.nonzero(bins >= threshold)          # raster order
    capacity = cfg.record_capacity
    overflow = len(rows) > capacity
    rows, cols = rows[:capacity], cols[:capacity]
    records = np.zeros(len(rows), dtype=candidate_dtype(np.uint32))
    records["row"], records["col"] = rows, cols
    records["energy"] = energy[rows, cols]
    records["direction"] = np.asarray(direction)[rows, cols]
    return CandidateList(records, len(records), threshold, bool(overflow), primed, True, False,
                         histogram_fixed(energy, cfg, shift))


def segment_sequence(energy: np.ndarray, direction: np.ndarray, cfg: DPConfig,
                     schedule: Schedule | None = None) -> list[CandidateList]:
    """The lists of consecutive segments ``(S, H, W)`` after a reset: each thresholded with
    the previous segment's histogram (and that segment's n), the first one unprimed (empty).
    ``schedule``: run-time settings per segment (:mod:`dptbd.model.settings`)."""
    entries = check_schedule(cfg, schedule)
    out: list[CandidateList] = []
    prev = None
    prev_count = None
    for j, (e, d) in enumerate(zip(np.asarray(energy), np.asarray(direction))):
        settings = settings_of_segment(entries, j)
        lst = segment_fixed(e, d, cfg, prev, shift=settings.histogram_shift,
                            prev_count=prev_count)
        out.append(lst)
        prev, prev_count = lst.histogram, settings.candidate_count
    return out


def segment_stream(states, cfg: DPConfig, settings=None) -> list[CandidateList]:
    """The segmenter's lists for ANY ``states`` stream, word by word (§6.5), bit for bit.

    ``states`` is an iterable of ``(E, d, end_of_line, end_of_frame, end_of_segment)`` in
    stream order from reset (e.g. an ``(N, 5)`` array). This is the gateware's control
    flow literally: position counters, the scored frame k = K - 1, realignment on
    ``end_of_segment``, the list end at the counters' last pixel or at an
    ``end_of_segment`` in a scored frame. For a well-formed stream (whole frames, no
    resynchronisation) it equals :func:`segment_sequence` of the segments' images.

    ``settings``: ``(N, 3)`` run-time (K, n, s) per word, those of the segment the DP input
    was in when it accepted that word's pixel; the segmenter takes them at the first word
    after reset and after each ``end_of_segment`` (the first word of a segment, counters at
    (0, 0, 0)), and n at the list end for the scan. A segment its counters start without
    ``end_of_segment`` (misaligned after a resynchronisation) keeps the settings it has
    (§6.5a). ``None``: the build values throughout.
    """
    width, height = cfg.width, cfg.height
    top = cfg.n_bins - 1
    saturate = (1 << cfg.bin_count_bits) - 1
    capacity = cfg.record_capacity
    k_frames, count, shift = (cfg.segment_frames, cfg.n_candidates, cfg.bin_shift)
    list_count = count
    col = row = k = 0
    primed, threshold = False, cfg.n_bins
    hist = np.zeros(cfg.n_bins, dtype=np.int64)
    records: list[tuple[int, int, int, int]] = []
    overflow = missed = False
    out: list[CandidateList] = []
    taking = True                                       # reset or after an end_of_segment
    for index, word in enumerate(states):
        energy, direction, _eol, _eof, eos = (int(v) for v in word)
        if settings is not None and taking:             # a segment's first word
            k_frames, count, shift = (int(v) for v in settings[index])
        taking = bool(eos)
        if k == k_frames - 1:                           # scored frame
            b = min(energy >> shift, top)
            hist[b] = min(hist[b] + 1, saturate)
            if b >= threshold:
                if len(records) < capacity:
                    records.append((row, col, energy, direction))
                else:
                    overflow = True
            last = row == height - 1 and col == width - 1
            if last or eos:
                rec = np.array(records, dtype=np.int64).reshape(-1, 4)
                arr = np.zeros(len(rec), dtype=candidate_dtype(np.uint32))
                for f, name in enumerate(("row", "col", "energy", "direction")):
                    arr[name] = rec[:, f]
                out.append(CandidateList(arr, len(arr), threshold, overflow, primed,
                                         bool(last and eos), missed, hist.copy()))
                list_count = count
                threshold, primed = threshold_bin(hist, cfg, list_count), True
                hist[:] = 0
                records, overflow, missed = [], False, False
        elif eos:
            missed = True
        if eos:
            col = row = k = 0
        else:
            col += 1
            if col == width:
                col, row = 0, row + 1
                if row == height:
                    row, k = 0, (k + 1) % k_frames
    return out
