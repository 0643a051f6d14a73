"""Which property of a candidate list makes false tracks through the DSP association.

On noise-only scenes (:func:`noise_lists`: the built-in scenario without its targets, as
:func:`~dptbd.evaluation.family.association.job_run` runs it) every confirmed track is
false. A variant's lists are replayed through the association after one property of the
candidates is replaced (:data:`SWAPS`, :func:`swap`), the rest kept:

* ``"none"``: the lists as the variant made them;
* ``"uniform"``: each list's *distinct* candidates (those the association's cluster
  suppression keeps, :func:`distinct`) put at uniformly drawn positions at least
  ``merge_radius + 1`` apart (Chebyshev; none is suppressed), each keeping its energy and
  heading offset (``row - row0``, ``col - col0``; the path start clipped to the image) —
  the spatial distribution beyond one pixel removed, the distinct count kept;
* ``"translated"``: each list's distinct candidates shifted together by one uniformly drawn
  offset, wrapped around the image (each keeping its energy and heading offset) — where the
  list lies and how near the border randomised, the distances between its candidates kept
  (up to the wrap);
* ``"zero-headings"``: every path start at its candidate (no heading);
* ``"random-headings"``: heading offsets drawn uniformly in [-(K - 1), K - 1]² (path start
  clipped to the image);
* ``"headings-of"``: candidate j of list s takes the heading offset of candidate
  ``j mod m`` of list s of another variant's lists (``source``, m candidates) — positions
  of one variant, headings of the other;
* ``"energy-ranks"``: energies replaced by their ranks (order kept);
* ``"alternate-seed"``: every odd-numbered list taken from ``source`` (the same variant's
  lists on another seed): consecutive lists share no noise, each list keeps its own
  statistics and its place in the sequence.

:func:`associate` replays lists through :class:`~dptbd.dsp.association.Tracker` and counts,
beside the confirmed tracks, how far every track got (:class:`Seeding`: tracks reaching
1, 2, 3, … hits). :func:`pair_counts` and :func:`coverage` describe a list's geometry: the
Chebyshev distances between its distinct candidates, and the fraction of the image a
new track's seed gate around one of them covers. :func:`seed_swaps` is one seed's share of
``benchmarks/bench_family_association.py --list-swaps``: every variant and list length with
every swap, and the lists' geometry.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.config import DPConfig
from dptbd.dsp.association import FREE, AssociationConfig, Tracker
from dptbd.errors import DptbdError, check_int
from dptbd.evaluation.family.association import job_run
from dptbd.evaluation.family import detection as fd
from dptbd.evaluation.family.detection import Variant

__all__ = ["SWAPS", "NoiseLists", "Seeding", "noise_lists", "distinct", "pair_counts",
           "coverage", "uniform_positions", "swap", "associate", "PAIR_TOP", "OTHER_SEED",
           "seed_swaps"]

#: The replaced properties (module docstring).
SWAPS = ("none", "uniform", "translated", "zero-headings", "random-headings", "headings-of",
         "energy-ranks", "alternate-seed")


@dataclasses.dataclass(frozen=True)
class NoiseLists:
    """One variant's candidate lists on one noise-only seed: the segment layout the DSP
    sees (``view``), the association's parameters and the lists (``CANDIDATE_DTYPE``)."""

    view: DPConfig
    assoc: AssociationConfig
    candidates: tuple


@dataclasses.dataclass(frozen=True)
class Seeding:
    """One replay: ``false_tracks`` (confirmed tracks, all false on noise only) and
    ``reached[h - 1]``: tracks that reached ``h`` hits (``reached[0]``: tracks started),
    for h = 1 … ``len(reached)`` (the last entry: that many hits or more). Sums with ``+``."""

    false_tracks: int
    reached: tuple

    def __add__(self, other: "Seeding") -> "Seeding":
        if len(self.reached) != len(other.reached):
            raise DptbdError(f"seeding counts of {len(self.reached)} and {len(other.reached)} "
                             "hit levels cannot be added")
        return Seeding(self.false_tracks + other.false_tracks,
                       tuple(a + b for a, b in zip(self.reached, other.reached)))


def noise_lists(variant: Variant, seed: int, count: int) -> NoiseLists:
    """``variant``'s lists of ``count`` ideal candidates on the built-in scenario of ``seed``
    without its targets (a recursive variant: lists every ``segment_frames`` frames)."""
    run = job_run(variant, seed, noise_only=True, count=count)
    return NoiseLists(run.result.cfg, run.result.assoc, tuple(run.result.candidates))


def _chebyshev(r: np.ndarray, c: np.ndarray) -> np.ndarray:
    r, c = r.astype(np.int64), c.astype(np.int64)
    return np.maximum(np.abs(r[:, None] - r[None, :]), np.abs(c[:, None] - c[None, :]))


def distinct(cands: np.ndarray, merge_radius: int) -> np.ndarray:
    """The candidates the association's cluster suppression keeps: no stronger one (ties:
    an earlier one) within ``merge_radius`` (Chebyshev; 0 keeps all)."""
    n = len(cands)
    if merge_radius <= 0 or n == 0:
        return cands.copy()
    e = cands["energy"].astype(np.int64)
    idx = np.arange(n)
    stronger = (e[:, None] > e[None, :]) | ((e[:, None] == e[None, :]) & (idx[:, None] < idx[None, :]))
    beaten = (_chebyshev(cands["row"], cands["col"]) <= merge_radius) & stronger
    np.fill_diagonal(beaten, False)
    return cands[~beaten.any(axis=0)]


def pair_counts(cands: np.ndarray, top: int) -> np.ndarray:
    """Pairs of ``cands`` at each Chebyshev distance 0 … ``top`` (the last entry: ``top`` or
    more)."""
    top = check_int("top", top, 1)
    d = _chebyshev(cands["row"], cands["col"])[np.triu_indices(len(cands), 1)]
    return np.bincount(np.minimum(d, top), minlength=top + 1)


def coverage(cands: np.ndarray, shape: tuple[int, int], gate: float) -> float:
    """Fraction of the image within ``gate`` pixels (Euclidean, the association's gate) of a
    candidate of ``cands``."""
    h, w = shape
    yy, xx = np.indices((h, w))
    mask = np.zeros((h, w), dtype=bool)
    for r, c in zip(cands["row"].astype(np.int64), cands["col"].astype(np.int64)):
        mask |= (yy - r) ** 2 + (xx - c) ** 2 <= gate * gate
    return float(mask.mean())


def uniform_positions(n: int, shape: tuple[int, int], rng: np.random.Generator, *,
                      apart: int = 2) -> np.ndarray:
    """``(n, 2)`` positions drawn uniformly on the image ``shape``, every two at least
    ``apart`` pixels apart (Chebyshev; rejection sampling)."""
    h, w = shape
    if n * (2 * apart - 1) ** 2 > h * w // 4:
        raise DptbdError(f"{n} positions {apart} pixels apart do not fit loosely in {h} x {w}")
    out = np.empty((n, 2), dtype=np.int64)
    k = 0
    while k < n:
        p = rng.integers(0, (h, w))
        if k == 0 or np.max(np.abs(out[:k] - p), axis=1).min() >= apart:
            out[k] = p
            k += 1
    return out


def _with_offsets(cands: np.ndarray, rows, cols, dr, dc, shape) -> np.ndarray:
    out = cands.copy()
    rows, cols = np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64)
    out["row"], out["col"] = rows, cols
    out["row0"] = np.clip(rows - dr, 0, shape[0] - 1)
    out["col0"] = np.clip(cols - dc, 0, shape[1] - 1)
    return out


def _offsets(cands: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return (cands["row"].astype(np.int64) - cands["row0"].astype(np.int64),
            cands["col"].astype(np.int64) - cands["col0"].astype(np.int64))


def swap(lists: NoiseLists, how: str, rng: np.random.Generator | None = None,
         source: NoiseLists | None = None) -> NoiseLists:
    """``lists`` with one property replaced (``how`` in :data:`SWAPS`, module docstring);
    ``rng`` for ``"uniform"``, ``"translated"`` and ``"random-headings"``, ``source`` (as
    many lists) for ``"headings-of"`` and ``"alternate-seed"``."""
    if how not in SWAPS:
        raise DptbdError(f"swap must be one of {', '.join(map(repr, SWAPS))}, got {how!r}")
    if how in ("uniform", "translated", "random-headings") and rng is None:
        raise DptbdError(f"swap {how!r} needs a random generator (rng)")
    if how in ("headings-of", "alternate-seed") and (
            source is None or len(source.candidates) != len(lists.candidates)):
        have = "none" if source is None else f"{len(source.candidates)} lists"
        raise DptbdError(f"swap {how!r} needs a source of {len(lists.candidates)} lists, "
                         f"got {have}")
    shape = (lists.view.height, lists.view.width)
    span = lists.view.segment_frames - 1
    out = []
    for s, c in enumerate(lists.candidates):
        if how == "alternate-seed":
            out.append((source.candidates[s] if s % 2 else c).copy())
            continue
        if how == "none" or len(c) == 0:
            out.append(c.copy())
            continue
        if how == "uniform":
            c = distinct(c, lists.assoc.merge_radius)
            pos = uniform_positions(len(c), shape, rng, apart=lists.assoc.merge_radius + 1)
            out.append(_with_offsets(c, pos[:, 0], pos[:, 1], *_offsets(c), shape))
        elif how == "translated":
            c = distinct(c, lists.assoc.merge_radius)
            dy, dx = rng.integers(0, shape)
            out.append(_with_offsets(c, (c["row"].astype(np.int64) + dy) % shape[0],
                                     (c["col"].astype(np.int64) + dx) % shape[1], *_offsets(c),
                                     shape))
        elif how == "zero-headings":
            out.append(_with_offsets(c, c["row"], c["col"], 0, 0, shape))
        elif how == "random-headings":
            dr, dc = rng.integers(-span, span + 1, (2, len(c)))
            out.append(_with_offsets(c, c["row"], c["col"], dr, dc, shape))
        elif how == "headings-of":
            src = source.candidates[s]
            if len(src) == 0:
                raise DptbdError(f"swap 'headings-of': source list {s} is empty")
            sr, sc = _offsets(src)
            j = np.arange(len(c)) % len(src)
            out.append(_with_offsets(c, c["row"], c["col"], sr[j], sc[j], shape))
        else:   # energy-ranks
            r = c.copy()
            r["energy"] = _dense_ranks(c["energy"])
            out.append(r)
    return dataclasses.replace(lists, candidates=tuple(out))


def _dense_ranks(e: np.ndarray) -> np.ndarray:
    """Ranks of ``e`` that keep every comparison (equal values: equal ranks)."""
    return np.searchsorted(np.unique(e), e).astype(np.uint32)


class _RecordingTracker(Tracker):
    """The association, noting the hits of every track it frees."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.final_hits: list[int] = []

    def _delete(self, i: int) -> None:
        self.final_hits.append(int(self.tracks["hits"][i]))
        super()._delete(i)


def associate(lists: NoiseLists, *, levels: int = 5) -> Seeding:
    """Replay ``lists`` through the association (:class:`Seeding`, hit levels 1 …
    ``levels``)."""
    levels = check_int("levels", levels, 1)
    v = lists.view
    tr = _RecordingTracker(lists.assoc, segment_frames=v.segment_frames,
                           segment_stride=v.segment_stride, height=v.height, width=v.width,
                           radius=v.radius)
    for c in lists.candidates:
        tr.step(c)
    live = tr.tracks["state"] != FREE
    hits = np.array(tr.final_hits + tr.tracks["hits"][live].astype(np.int64).tolist(),
                    dtype=np.int64)
    reached = tuple(int(np.count_nonzero(hits >= h)) for h in range(1, levels + 1))
    return Seeding(len(tr.confirmed_tracks()), reached)


#: :func:`seed_swaps` counts pairs of distinct candidates at Chebyshev distance 0 … this
#: (the last: this or more).
PAIR_TOP = 8
#: ``"alternate-seed"`` takes every other list of the recursion from the seed this far on
#: (segments' consecutive lists share no noise by construction: disjoint frames).
OTHER_SEED = 1_000_000


def seed_swaps(alpha: float, seed: int, seg_counts: tuple, rec_counts: tuple) -> dict:
    """One noise-only ``seed``: segments K = 6 at each of ``seg_counts`` and the recursion
    (``alpha``, lists every 6 frames) at each of ``rec_counts`` (list lengths), each with
    every swap of :data:`SWAPS`, and the lists' geometry.

    Returns ``{(kind, n): (row, geometry)}``, ``kind`` ``"seg"`` or ``"rec"``: ``row`` maps
    each swap to its :class:`Seeding` (``"alternate-seed"`` for the recursion only; the
    segments take their ``"headings-of"`` from the recursion's longest lists, the recursion
    from the segments' shortest); ``geometry`` is, for the lists as made and for their
    ``"uniform"`` swap, (distinct candidates, lists, :func:`pair_counts` summed over the
    lists with top :data:`PAIR_TOP`, :func:`coverage` of the seed gate summed over them).
    """
    rec = fd.recursive(alpha, segment_frames=6)
    keys = [("seg", n) for n in seg_counts] + [("rec", n) for n in rec_counts]
    lists = {key: noise_lists(fd.segments(6) if key[0] == "seg" else rec, seed, key[1])
             for key in keys}
    sources = {"seg": lists[("rec", max(rec_counts))], "rec": lists[("seg", min(seg_counts))]}
    out = {}
    for key, lst in lists.items():
        row = {}
        for how in SWAPS:
            if how == "alternate-seed":
                if key[0] == "rec":
                    row[how] = associate(swap(lst, how, source=noise_lists(
                        rec, seed + OTHER_SEED, key[1])))
                continue
            rng = np.random.default_rng([seed, key[1], SWAPS.index(how)])
            swapped = swap(lst, how, rng, source=sources[key[0]])
            if how == "uniform":
                uniform = swapped                   # its geometry is measured below
            row[how] = associate(swapped)
        gate = lst.assoc.seed_gate
        shape = (lst.view.height, lst.view.width)
        geo = []
        for ls_ in (lst, uniform):
            ds = [distinct(c, lst.assoc.merge_radius) for c in ls_.candidates]
            geo.append((sum(len(d) for d in ds), len(ds),
                        sum(pair_counts(d, PAIR_TOP) for d in ds),
                        sum(coverage(d, shape, gate) for d in ds)))
        out[key] = (row, geo)
    return out
