"""What makes a variant's false tracks through the DSP association.

On the built-in scenario (:mod:`~dptbd.evaluation.family.association`), every confirmed track
that belongs to no target (:func:`dptbd.dsp.track_metrics.evaluate_tracks`) is classified
by its points (one per list it matched, at the list's last frame t):

* **on target**: within ``radius`` pixels (Chebyshev; 2, ``evaluate_tracks``' own) of a
  target's pixel at t;
* **wake**: otherwise within ``near`` pixels (3) of a target's visible positions of the
  ``history`` frames (40) before t — on and around a target's past track;
* **elsewhere**: neither.

The track's *kind* is the class of most of its points (a tie goes to the class nearer the
target: on target, then wake). Beside it, per track: the pairs of its hits in consecutive
lists, and of them the *chained* pairs, whose later candidate's backtracked path starts
within one move (the DP's ``radius``) of the earlier hit: the DP followed one path from the
earlier hit to the later one.

:func:`descent_counts` measures on a noise-only scene how often a list's candidate
*descends* from a candidate of a list ``lag`` frames earlier: its DP path, backtracked to
the frame after the earlier list, lies within one move of one of the earlier list's
candidates (of the recursion: the same noise peak carried on by its memory). Chance is the
fraction of the image within one move of the earlier list's candidates (``coverage``).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.config import DPConfig
from dptbd.dsp.backtrack import candidate_paths, segment_direction_maps
from dptbd.errors import DptbdError, check_int
from dptbd.evaluation.chain import PipelineResult
from dptbd.evaluation.family.association import JobRun
from dptbd.evaluation.family.detection import Variant
from dptbd.evaluation.metrics import near_mask
from dptbd.evaluation.stats import wilson_interval
from dptbd.model.family.fast import fast_family_start, fast_family_step
from dptbd.model.fast import run_fixed_fast
from dptbd.model.segmentation import candidates as map_candidates

__all__ = ["KINDS", "FalseTrack", "Descent", "classify_points", "false_tracks", "descent_counts",
           "check_descent_lags", "noise_scene", "recursive_config", "rate_ratio"]

#: Kinds of false track, nearest the target first.
KINDS = ("on target", "wake", "elsewhere")


@dataclasses.dataclass(frozen=True)
class FalseTrack:
    """One false track: its id, its points by class (:data:`KINDS` order), its kind, its
    hits in consecutive lists (``pairs``) and of them the ``chained`` ones, and the median
    Chebyshev step between consecutive hits (pixels per list)."""

    track_id: int
    points: tuple[int, int, int]
    kind: str
    pairs: int
    chained: int
    step: float


def classify_points(rows: np.ndarray, cols: np.ndarray, frames: np.ndarray, truth, *,
                    radius: int = 2, near: int = 3, history: int = 40) -> np.ndarray:
    """Class index (0 on target, 1 wake, 2 elsewhere; :data:`KINDS`) of the points
    ``(rows[i], cols[i])`` in frames ``frames[i]`` against the targets' ``truth``."""
    out = np.full(len(rows), 2, dtype=np.int64)
    for i, (r, c, t) in enumerate(zip(rows, cols, frames)):
        r, c, t = int(r), int(c), int(t)
        for tt in truth:
            if tt.visible[t] and max(abs(r - tt.pixel[t][0]), abs(c - tt.pixel[t][1])) <= radius:
                out[i] = 0
                break
            past = [u for u in range(max(t - history, 0), t) if tt.visible[u]]
            if past and np.any(np.max(np.abs(tt.pixel[past] - (r, c)), axis=1) <= near):
                out[i] = min(out[i], 1)
    return out


def false_tracks(run: JobRun, *, radius: int = 2, near: int = 3, history: int = 40
                 ) -> list[FalseTrack]:
    """Every false track of ``run`` (:func:`~dptbd.evaluation.family.association.job_run`),
    classified (module docstring)."""
    result: PipelineResult = run.result
    move = result.cfg.radius
    out = []
    for tr in result.tracks:
        if run.evaluation.track_target[tr.id] >= 0:
            continue
        p = tr.points
        seg = p["seg"].astype(np.int64)
        rows, cols = p["row"].astype(np.int64), p["col"].astype(np.int64)
        cls = classify_points(rows, cols, result.segments.end_frames[seg], run.truth,
                              radius=radius, near=near, history=history)
        counts = tuple(int(np.count_nonzero(cls == k)) for k in range(3))
        kind = KINDS[max(range(3), key=lambda k: (counts[k], -k))]
        consecutive = np.flatnonzero(np.diff(seg) == 1)
        chained = sum(max(abs(int(p["row0"][i + 1]) - rows[i]),
                          abs(int(p["col0"][i + 1]) - cols[i])) <= move for i in consecutive)
        steps = np.maximum(np.abs(np.diff(rows)), np.abs(np.diff(cols))) / np.maximum(np.diff(seg), 1)
        out.append(FalseTrack(int(tr.id), counts, kind, len(consecutive), int(chained),
                              float(np.median(steps)) if len(steps) else float("nan")))
    return out


@dataclasses.dataclass(frozen=True)
class Descent:
    """Descent counts at ``lags`` (frames): ``descended[i]`` of ``candidates[i]`` later
    candidates descend from the list ``lags[i]`` frames earlier; summed over the
    ``pairs[i]`` pairs of lists, ``coverage[i]``: the fraction of the image within one move
    of the earlier list's candidates (chance), and ``background[i]``: the fraction of *all*
    pixels of the later map whose path descends (chance for a pixel of the DP, whose paths
    converge on the earlier map's strong pixels). Sums with ``+`` (same lags)."""

    lags: tuple[int, ...]
    descended: tuple[int, ...]
    candidates: tuple[int, ...]
    coverage: tuple[float, ...]
    background: tuple[float, ...]
    pairs: tuple[int, ...]

    def __add__(self, other: "Descent") -> "Descent":
        if self.lags != other.lags:
            raise DptbdError(f"descent counts of lags {self.lags} and {other.lags} cannot be added")
        add = lambda a, b: tuple(x + y for x, y in zip(a, b))  # noqa: E731
        return Descent(self.lags, add(self.descended, other.descended),
                       add(self.candidates, other.candidates), add(self.coverage, other.coverage),
                       add(self.background, other.background), add(self.pairs, other.pairs))


def check_descent_lags(lags, frames: int = 100) -> tuple[int, ...]:
    """``lags`` as distinct ascending integers in [1, frames - 1]; refused otherwise."""
    out = tuple(check_int(f"lags[{i}]", lag, 1, frames - 1) for i, lag in enumerate(lags))
    if not out:
        raise DptbdError(f"lags must hold at least one lag in [1, {frames - 1}]")
    if len(set(out)) != len(out) or list(out) != sorted(out):
        raise DptbdError(f"lags must be distinct and ascending, got {list(out)}")
    return out


def _descent(energy: np.ndarray, directions: np.ndarray, cfg: DPConfig, count: int,
             pairs, lags: tuple[int, ...]) -> Descent:
    """``energy[t]``/``directions[t]``: the maps whose last frame is t (``directions`` every
    frame the paths need); ``pairs[i]``: the (earlier, later) frames of lag ``lags[i]``."""
    h, w = energy.shape[-2:]
    desc, cand, cov, bg, n_pairs = [], [], [], [], []
    rows0, cols0 = (a.ravel() for a in np.indices((h, w)))
    top = {}

    def candidates_at(t):
        if t not in top:
            top[t] = map_candidates(energy[t], directions[t], count)
        return top[t]

    for lag, frame_pairs in zip(lags, pairs):
        d = c = 0
        cv = b = 0.0
        for t1, t2 in frame_pairs:
            early = candidates_at(t1)
            mask = near_mask((h, w), np.stack([early["row"], early["col"]], axis=1).astype(np.int64),
                             cfg.radius)
            late = candidates_at(t2)
            maps = directions[t2 - lag + 1:t2 + 1].copy()
            maps[0] = cfg.start_code
            start = candidate_paths(late, maps, cfg)[:, 0]   # the path at frame t1 + 1
            d += int(np.count_nonzero(mask[start[:, 0], start[:, 1]]))
            c += len(late)
            cv += float(mask.mean())
            r, q = rows0.copy(), cols0.copy()   # every pixel's path, back to frame t1 + 1
            for i in range(lag - 1, 0, -1):
                move = cfg.moves[maps[i, r, q]]
                r, q = r - move[:, 0], q - move[:, 1]
            b += float(mask[r, q].mean())
        desc.append(d)
        cand.append(c)
        cov.append(cv)
        bg.append(b)
        n_pairs.append(len(frame_pairs))
    return Descent(lags, tuple(desc), tuple(cand), tuple(cov), tuple(bg), tuple(n_pairs))


def descent_counts(frames: np.ndarray, cfg: DPConfig, count: int, *, lags, first: int = 7
                   ) -> Descent:
    """:class:`Descent` of one sequence ``frames (T, H, W)`` of ADC codes, each map's
    ``count`` largest pixels the candidates.

    A recursive ``cfg`` (``docs/arithmetic.md`` §8.6) has a map every frame: every pair
    (t, t + lag) with ``first`` <= t, t + lag < T. A segment ``cfg`` (stride K) has a map
    at the end of each segment and paths of K frames: only ``lags`` = (K,), the pairs of
    consecutive segments.
    """
    arr = np.asarray(frames)
    n_t = arr.shape[0]
    lags = check_descent_lags(lags, n_t)
    if cfg.recursive:
        e, d = fast_family_start(arr[0], cfg)
        energy = np.empty((n_t,) + e.shape, dtype=e.dtype)
        directions = np.empty((n_t,) + d.shape, dtype=np.uint8)
        energy[0], directions[0] = e, d
        for t in range(1, n_t):
            e, d = fast_family_step(e, d, arr[t], cfg)
            energy[t], directions[t] = e, d
        pairs = [[(t, t + lag) for t in range(first, n_t - lag)] for lag in lags]
        return _descent(energy, directions, cfg, count, pairs, lags)
    k = cfg.segment_frames
    if cfg.segment_stride != k or lags != (k,):
        raise DptbdError(f"segments of K = {k} (stride K) have paths of K frames: lags must be "
                         f"[{k}], got {list(lags)}")
    out = run_fixed_fast(arr, cfg)
    maps = segment_direction_maps(arr, cfg, segment_direction=out.direction)
    ends = out.end_frames.astype(np.int64)
    energy = np.zeros((n_t,) + arr.shape[1:], dtype=out.energy.dtype)
    directions = np.zeros((n_t,) + arr.shape[1:], dtype=np.uint8)
    energy[ends] = out.energy
    for s, t in enumerate(ends):
        directions[t - k + 1:t + 1] = maps[s]
    pairs = [[(int(a), int(b)) for a, b in zip(ends[:-1], ends[1:])]]
    return _descent(energy, directions, cfg, count, pairs, lags)


def noise_scene(seed: int):
    """The built-in scenario of ``seed`` without its targets, prepared as ``dptbd run``
    prepares it (ideal lists): a :class:`dptbd.evaluation.run.job.RunInput`."""
    from dptbd.evaluation.run.job import prepare
    from dptbd.evaluation.run.scenario import default_scenario

    sc = default_scenario().replace(seed=seed, lists="ideal", targets=())
    sc.check()
    return prepare(sc)


def recursive_config(variant: Variant, cfg: DPConfig) -> DPConfig:
    """The recursive variant's configuration on the scenario's ``cfg`` (as
    :func:`~dptbd.evaluation.family.association.job_run` builds it)."""
    if variant.forgetting is None:
        raise DptbdError(f"recursive_config needs a recursive variant, got {variant.label!r}")
    return cfg.replace(histogram_shift=None, **variant.family_fields(cfg.radius))


def rate_ratio(a: int, b: int) -> tuple[float, float, float]:
    """Ratio a / b of two event counts over equally many runs, with its 95 % interval:
    given a + b events, a is binomial with p = r / (1 + r); the Wilson interval of p mapped
    to r (an infinite upper end when b = 0)."""
    a = check_int("a", a, 0)
    b = check_int("b", b, 0)
    if a + b == 0:
        raise DptbdError("rate_ratio needs at least one event, got a = b = 0")
    lo, hi = wilson_interval(a, a + b)
    ratio = lambda p: p / (1.0 - p) if p < 1.0 else float("inf")  # noqa: E731
    return (a / b if b else float("inf")), ratio(lo), ratio(hi)
