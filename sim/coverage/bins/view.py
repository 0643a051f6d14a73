"""The model's view of a whole run (its positions, energies, whole segments and the lists
that came out whole, concatenated over its resets) and the bins that every kind of run counts
from it: positions by stall band, faults recovered, LUT writes, saturation, lists and ties
(:mod:`dptbd.sim.coverage.bins`)."""

from __future__ import annotations

import dataclasses
from typing import Iterable

import numpy as np

from dptbd.sim.coverage.bins.groups import (LIST_LABELS, LUT_CODES, LUT_STAGES, POSITIONS,
                                            SATURATION, TIES, key)

__all__ = ["View", "view_of", "list_ends", "count_positions", "count_recovered", "count_lut",
           "count_lists", "count_outputs"]


@dataclasses.dataclass
class View:
    """The model's outputs of a run, concatenated over its epochs (resets, soft resets)."""

    row: np.ndarray
    col: np.ndarray
    frame_end: np.ndarray
    energy: np.ndarray
    boundary: np.ndarray           # the word is in a segment's first or last frame
    segments: list                 # (start, stop) of whole segments, stream indices
    lists: list                    # (CandidateList, n) of every list that came out whole


def view_of(cfg, pieces) -> View:
    """``pieces``: (index of the first word, StreamExpectation, lists or None, words of
    the lists that came out or None)."""
    from dptbd.sim.candidate_scoreboard import list_words

    rows, cols, ends, energy, boundary, segments, lists = [], [], [], [], [], [], []
    for start, exp, got_lists, received in pieces:
        rows.append(exp.positions[:, 1])
        cols.append(exp.positions[:, 2])
        ends.append(exp.fields[:, 3])
        energy.append(exp.fields[:, 0])
        edge = np.zeros(len(exp.fields), dtype=bool)
        runs = list(exp.runs)
        for run in runs:
            if run.frame == 0 or run.frame == run.segment_frames - 1:
                edge[run.start:run.stop] = True
        boundary.append(edge)
        for i, run in enumerate(runs):
            k = run.segment_frames
            whole = runs[i:i + k]
            if run.frame == 0 and len(whole) == k and all(
                    r.complete and r.frame == j for j, r in enumerate(whole)):
                segments.append((start + run.start, start + whole[-1].stop))
        if got_lists is None:
            continue
        ends_at = list_ends(cfg, exp.fields, exp.settings)
        real = got_lists[:len(ends_at)]
        sizes = np.cumsum([len(w) for w in list_words(cfg, real)])
        whole_out = int(np.searchsorted(sizes, received, side="right")) \
            if received is not None else len(real)
        lists += [(lst, n) for lst, (_, n) in zip(real[:whole_out], ends_at)]
    cat = (lambda parts, dtype: np.concatenate(parts).astype(dtype) if parts
           else np.zeros(0, dtype=dtype))
    return View(cat(rows, np.int64), cat(cols, np.int64), cat(ends, bool),
                 cat(energy, np.int64), cat(boundary, bool), segments, lists)


def list_ends(cfg, fields: np.ndarray, settings: np.ndarray | None) -> list[tuple[int, int]]:
    """(index of the list's last word, the list's n) of every list that
    :func:`~dptbd.model.segmentation.segment_stream` makes of ``fields`` with ``settings``,
    in order: the same control flow (a segment's K and n taken at its first word, a list
    ending at its scored frame's last pixel or at an ``end_of_segment`` inside the scored
    frame, counters realigned on every ``end_of_segment``), one step per segment."""
    size = cfg.width * cfg.height
    eos = np.flatnonzero(np.asarray(fields)[:, 4])
    n_words = len(fields)
    out, a = [], 0
    while a < n_words:
        k, n = ((int(settings[a][0]), int(settings[a][1])) if settings is not None
                else (cfg.segment_frames, cfg.n_candidates))
        last = a + k * size - 1
        i = int(np.searchsorted(eos, a))
        e = int(eos[i]) if i < len(eos) else None
        if e is not None and e < last:
            if e >= last - size + 1:
                out.append((e, n))
            a = e + 1
        else:
            if last < n_words:
                out.append((last, n))
            a = last + 1
    return out


def count_positions(view: View, cfg, counts: dict, prefix: str) -> None:
    first, last = view.row == 0, view.row == cfg.height - 1
    left, right = view.col == 0, view.col == cfg.width - 1
    masks = {"first row": first, "last row": last, "first column": left, "last column": right,
             "interior": ~(first | last | left | right), "segment boundary frame": view.boundary}
    for name in POSITIONS:
        counts[key("stall", f"{prefix}, {name}")] += int(np.count_nonzero(masks[name]))


def count_recovered(view: View, events: list[tuple[str, int]], counts: dict,
               writes: Iterable[int] = ()) -> None:
    """A fault is recovered when a clean segment (no fault and no write in ``writes``
    inside it) starts at or after it."""
    at = np.array([i for _, i in events] + list(writes), dtype=np.int64)
    clean = [s for s, t in view.segments
             if not np.any((at > s) & (at < t))]
    latest = max(clean, default=-1)
    for fault, i in events:
        if i <= latest:
            counts[key("fault", f"{fault} recovered")] += 1


def _lut_stage(view: View, cfg, index: int) -> str:
    n = len(view.row)
    if index >= n:
        if n == 0 or view.frame_end[n - 1]:
            return LUT_STAGES[0]
        index = n - 1
    elif view.row[index] == 0 and view.col[index] == 0:
        return LUT_STAGES[0]
    row = int(view.row[index])
    return LUT_STAGES[1] if row == 0 else (LUT_STAGES[3] if row == cfg.height - 1
                                           else LUT_STAGES[2])


def count_lut(view: View, cfg, writes, counts: dict) -> None:
    unity = 1 << cfg.weight_frac_bits
    for index, codes in writes:
        counts[key("LUT", _lut_stage(view, cfg, int(index)))] += 1
        codes = np.asarray(codes)
        for label, code in zip(LUT_CODES, (0, unity - 1, unity)):
            counts[key("LUT", label)] += int(np.count_nonzero(codes == code))


def count_lists(view: View, cfg, counts: dict) -> None:
    capacity = cfg.record_capacity
    for lst, n in view.lists:
        hit = {LIST_LABELS[0]: lst.count == 0,
               LIST_LABELS[1]: 0 < n < capacity and lst.count == n,
               LIST_LABELS[2]: lst.count == capacity, LIST_LABELS[3]: bool(lst.overflow)}
        for label, yes in hit.items():
            counts[key("lists", label)] += int(yes)
        t = int(lst.threshold)
        counts[TIES] += int(t < cfg.n_bins and int(lst.histogram[t]) >= 2)


def count_outputs(view: View, cfg, counts: dict) -> None:
    """The bins of the model's outputs: saturated state words, the lists and their ties."""
    counts[SATURATION] += int(np.count_nonzero(view.energy == cfg.e_max))
    count_lists(view, cfg, counts)
