"""Paper 000's simulations (§5.1, §5.2) and its SNR-gain claim, reproduced.

* §5.1: 64 x 64, 20 frames, SNR 4.08 dB (eq (8), A = 1.6), start (12, 52), v = (-2, 2)
  (:func:`dptbd.scenes.synthetic.paper000_scenario`), amplitude DP eq (15) and eq (24),
  thresholds V_T = 30 and 32.
* §5.2: the same set-up at SNR 6 dB (A = 2) with V_T = 322, "alpha" = 0.85, "delta" = 1,
  and at 3 dB with V_T = 178, "alpha" = 0.55: the likelihood-difference DP eqs (19)-(23).
  We read the printed alpha and delta as eq (20)'s epsilon and sigma (``docs/detectors.md``
  §1.2); eq (22)'s own coefficient is then unstated and taken as 1.

For each case and seed: the target's value ``h_20`` at its true last cell, the largest
value elsewhere (outside the 3 x 3 gate), and the false tracks above each V_T (cells
outside the gate, and the local maxima among them: distinct track ends).

:func:`snr_gain` measures Pd vs SNR at the same per-cell false-alarm probability for the
DPs and single-frame detection, and the SNR at which each reaches a given Pd.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Iterable

import numpy as np

from dptbd.scenes import synthetic as scenes
from dptbd.evaluation.detectors import cfar, merits, transitions, unified
from dptbd.evaluation.detectors._checks import DetectorError, check_int, check_prob, check_real

__all__ = ["CASES", "Case", "CaseResult", "run_case", "peak_mask", "gate_mask",
           "map_statistics", "quantile_threshold", "detected", "snr_gain", "GainResult",
           "crossing_snr", "GAIN_DETECTORS"]

RADIUS = 2
MERITS = ("amplitude", "likelihood")


@dataclasses.dataclass(frozen=True)
class Case:
    """One of paper 000's simulations.

    ``merit`` is ``"amplitude"`` or ``"likelihood"``; ``snr_db`` in [-30, 60]; the V_T
    ``thresholds`` a non-empty sequence of finite reals (refused by name otherwise).
    """

    label: str
    section: str
    snr_db: float
    merit: str  # "amplitude" or "likelihood"
    penalty: bool
    thresholds: tuple[float, ...]
    epsilon: float = 0.85
    sigma: float = 1.0
    alpha: float = 1.0
    paper: str = ""

    def __post_init__(self) -> None:
        if self.merit not in MERITS:
            raise DetectorError(f"merit must be one of {MERITS}, got {self.merit!r}")
        check_real("snr_db", self.snr_db, -30.0, 60.0)
        if isinstance(self.thresholds, (str, bytes)) or not hasattr(self.thresholds, "__iter__"):
            raise DetectorError(f"thresholds (V_T) must be a sequence of finite reals, got {self.thresholds!r}")
        vts = tuple(check_real("thresholds (V_T)", v) for v in self.thresholds)
        if not vts:
            raise DetectorError("thresholds (V_T) must hold at least one threshold")
        object.__setattr__(self, "thresholds", vts)

    def merit_fn(self) -> merits.Merit:
        if self.merit == "amplitude":
            return merits.amplitude_merit()
        a = scenes.amplitude_from_snr_db(self.snr_db, 1.0)
        return merits.likelihood_difference_merit(a, self.epsilon, self.sigma)

    def transition(self, radius: int = RADIUS) -> np.ndarray:
        if self.penalty:
            return transitions.velocity_log_penalty(radius, self.alpha)
        return transitions.no_penalty(radius)


#: Paper 000's cases (§5.1, §5.2).
CASES = (
    Case("5.1 eq (15)", "§5.1", 4.08, "amplitude", False, (30.0, 32.0),
         paper="V_T = 30: several false tracks and the target track (Fig. 2a); "
               "V_T = 32: two false tracks and the target track (Fig. 2b)"),
    Case("5.1 eq (24)", "§5.1", 4.08, "amplitude", True, (30.0, 32.0),
         paper="(as above; §5.1 does not say whether the eq (22) penalty was used)"),
    Case("5.2 6 dB", "§5.2", 6.0, "likelihood", True, (322.0,), epsilon=0.85,
         paper="V_T = 322: target track and some false tracks that cannot be removed (Fig. 3a)"),
    Case("5.2 3 dB", "§5.2", 3.0, "likelihood", True, (178.0,), epsilon=0.55,
         paper="V_T = 178: target track and some false tracks that cannot be removed (Fig. 3b)"),
)


def peak_mask(values: np.ndarray) -> np.ndarray:
    """Cells not smaller than any of their 8 neighbours: the ends of distinct tracks.

    Neighbouring cells of a strong path share most of it (each takes the max over the same
    predecessors), so "false tracks" are counted as local maxima of ``h_T``, not cells.
    """
    v = np.asarray(values, dtype=np.float64)
    pad = np.pad(v, 1, constant_values=-np.inf)
    height, width = v.shape
    ok = np.ones(v.shape, dtype=bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dy or dx:
                ok &= v >= pad[1 + dy:1 + dy + height, 1 + dx:1 + dx + width]
    return ok


def gate_mask(shape: tuple[int, int], cell: tuple[int, int]) -> np.ndarray:
    """``bool (H, W)``: the 3 x 3 gate around ``cell`` (the target's true last cell)."""
    y, x = (int(v) for v in cell)
    gate = np.zeros(shape, dtype=bool)
    gate[max(y - 1, 0):y + 2, max(x - 1, 0):x + 2] = True
    return gate


def map_statistics(value: np.ndarray, cell: tuple[int, int], thresholds: Iterable[float]) -> dict:
    """What :func:`run_case` measures on one final map ``h_T`` ``(H, W)``.

    ``target``: h_T at ``cell``; ``noise_max``: the largest h_T outside the 3 x 3 gate;
    ``target_rank``: cells outside the gate with h_T >= the target's; ``two_track_level``:
    the third-highest local maximum outside the gate (the V_T leaving two false tracks);
    ``false_cells`` / ``false_tracks``: V_T -> cells / local maxima above V_T outside the gate.
    """
    value = np.asarray(value, dtype=np.float64)
    gate = gate_mask(value.shape, cell)
    tv = float(value[tuple(int(v) for v in cell)])
    outside = np.where(gate, -np.inf, value)
    peaks = np.sort(outside[peak_mask(value) & ~gate])[::-1]
    return dict(target=tv, noise_max=float(outside.max()),
                target_rank=int(np.count_nonzero(outside >= tv)),
                two_track_level=float(peaks[2]) if peaks.size > 2 else float("-inf"),
                false_cells={v: int(np.count_nonzero(outside > v)) for v in thresholds},
                false_tracks={v: int(np.count_nonzero(peaks > v)) for v in thresholds})


def quantile_threshold(values: np.ndarray, pfa: float) -> float:
    """The per-cell threshold exceeded by a fraction ``pfa`` of ``values`` (noise-only cells):
    the ``(size - floor(pfa * size))``-th smallest value."""
    vals = np.asarray(values, dtype=np.float64).ravel()
    k = int(math.floor(pfa * vals.size))
    if k < 1:
        raise DetectorError(f"pfa={pfa:g} needs more than {vals.size} noise cells")
    return float(np.partition(vals, vals.size - k - 1)[vals.size - k - 1])


@dataclasses.dataclass(frozen=True)
class CaseResult:
    """Per-seed measurements of one case (arrays of length = seeds)."""

    case: Case
    mode: str
    target: np.ndarray  # h_T at the target's true last cell
    noise_max: np.ndarray  # largest h_T outside the 3 x 3 gate
    false_cells: dict  # V_T -> (seeds,) cells above V_T outside the gate
    false_tracks: dict  # V_T -> (seeds,) local maxima (track ends) above V_T outside the gate
    two_track_level: np.ndarray  # the V_T that leaves exactly two false tracks: 3rd-highest peak outside the gate
    target_rank: np.ndarray  # cells outside the gate with h_T >= the target's value
    on_track: np.ndarray  # fraction of frames the backtracked path from the target cell is within 1 cell of the truth


def run_case(case: Case, seeds: Iterable[int] = range(1), *, mode: str = "datapath",
             radius: int = RADIUS) -> CaseResult:
    """Run one of 000's simulations on ``seeds`` (one scene each, seed = scene seed).

    ``radius`` is the DP window (2: 000's target moves 2 cells per frame; 1 only to show
    how much of the noise paths' value is the window's selection bias).
    """
    seeds = [check_int("seed", s, 0) for s in seeds]
    if not seeds:
        raise DetectorError("seeds must hold at least one seed")
    radius = check_int("radius", radius, 1, 2)
    merit, q = case.merit_fn(), case.transition(radius)
    target, noise_max, rank, on_track = [], [], [], []
    cells = {v: [] for v in case.thresholds}
    tracks = {v: [] for v in case.thresholds}
    level2 = []
    for seed in seeds:
        sc = scenes.paper000_scenario(case.snr_db, seed=seed)
        truth = sc.truth[0]
        res = unified.run_unified(sc.frames, merit, q, radius=radius, mode=mode, history=True)
        y, x = truth.pixel[-1]
        stats = map_statistics(res.value, (y, x), case.thresholds)
        target.append(stats["target"])
        noise_max.append(stats["noise_max"])
        rank.append(stats["target_rank"])
        path = unified.backtrack(res, (y, x))
        on_track.append(float(np.mean(np.max(np.abs(path - truth.pixel), axis=1) <= 1)))
        level2.append(stats["two_track_level"])
        for v in case.thresholds:
            cells[v].append(stats["false_cells"][v])
            tracks[v].append(stats["false_tracks"][v])
    return CaseResult(case, mode, np.array(target), np.array(noise_max),
                      {v: np.array(c) for v, c in cells.items()},
                      {v: np.array(g) for v, g in tracks.items()}, np.array(level2),
                      np.array(rank), np.array(on_track))


# ---- SNR gain over single-frame detection --------------------------------------------------

@dataclasses.dataclass(frozen=True)
class GainResult:
    """Pd per detector and SNR at a per-cell false-alarm probability."""

    snrs_db: tuple[float, ...]
    pd: dict  # name -> (n_snr,) Pd
    detections: dict  # name -> (n_snr,) counts
    trials: int
    pfa: float
    thresholds: dict


GAIN_DETECTORS = ("single frame (known noise)", "CA-CFAR 16/2", "DP eq (15)", "DP eq (24)",
                  "DP eqs (19)-(23)")


def _maps(name: str, frames: np.ndarray, snr_db: float, epsilon: float) -> np.ndarray:
    """The per-cell statistic of the last frame, ``(N, H, W)``."""
    if name == "single frame (known noise)":
        return frames[:, -1].astype(np.float64)
    if name == "CA-CFAR 16/2":
        last = frames[:, -1].astype(np.float64)
        ratio = cfar.ca_cfar_ratio(np.abs(last), n_ref=16, n_guard=2, axis=-2)
        return np.where(last > 0, ratio, 0.0)
    if name == "DP eq (15)":
        return unified.run_unified(frames, merits.amplitude_merit(),
                                   transitions.no_penalty(RADIUS)).value
    if name == "DP eq (24)":
        return unified.run_unified(frames, merits.amplitude_merit(),
                                   transitions.velocity_log_penalty(RADIUS, 1.0)).value
    merit = merits.likelihood_difference_merit(scenes.amplitude_from_snr_db(snr_db, 1.0),
                                               epsilon, 1.0)
    return unified.run_unified(frames, merit, transitions.velocity_log_penalty(RADIUS, 1.0)).value


def snr_gain(snrs_db: Iterable[float] = tuple(range(-2, 13)), *, trials: int = 200,
             noise_trials: int = 200, pfa: float = 1e-3, epsilon: float = 0.85, seed: int = 5000,
             chunk: int = 50, detectors: Iterable[str] = GAIN_DETECTORS) -> GainResult:
    """Pd vs SNR on 000's scene (64 x 64, 20 frames, v = (+2, -2)) at a per-cell Pfa.

    Each detector's threshold is the per-cell (1 - pfa) quantile of its last-frame map on
    ``noise_trials`` noise-only scenes; the target is detected when a cell within one cell
    of its true last position is above it. The likelihood-difference DP uses the true
    amplitude (matched) with ``epsilon`` and sigma = 1, so its threshold is set per SNR.
    """
    snrs = tuple(float(s) for s in snrs_db)
    trials = check_int("trials", trials, 1)
    noise_trials = check_int("noise_trials", noise_trials, 1)
    pfa = check_prob("pfa", pfa)
    names = tuple(detectors)
    for n in names:
        if n not in GAIN_DETECTORS:
            raise DetectorError(f"unknown detector {n!r}; known: {GAIN_DETECTORS}")

    def batches(snr: float | None, n: int, base: int):
        for lo in range(0, n, chunk):
            m = min(chunk, n - lo)
            if snr is None:
                yield scenes.make_noise((64, 64), 20, seed=base, trials=m, first_trial=lo)
            else:
                sc = scenes.paper000_scenario(snr, seed=base, trials=m, first_trial=lo)
                yield sc.frames

    truth = scenes.paper000_scenario(0.0, noise=False).truth[0].pixel[-1]
    y, x = truth
    thresholds: dict = {}

    def threshold(name: str, snr: float) -> float:
        key = (name, snr) if name == "DP eqs (19)-(23)" else (name, None)
        if key not in thresholds:
            vals = np.concatenate([_maps(name, f, snr, epsilon).ravel()
                                   for f in batches(None, noise_trials, seed + 1)])
            thresholds[key] = quantile_threshold(vals, pfa)
        return thresholds[key]

    pd = {n: np.zeros(len(snrs)) for n in names}
    det = {n: np.zeros(len(snrs), dtype=np.int64) for n in names}
    for i, snr in enumerate(snrs):
        frames_list = list(batches(snr, trials, seed))
        for n in names:
            thr = threshold(n, snr)
            hits = 0
            for f in frames_list:
                m = _maps(n, f, snr, epsilon)
                hits += int(np.count_nonzero(detected(m, (y, x), thr)))
            det[n][i] = hits
            pd[n][i] = hits / trials
    return GainResult(snrs, pd, det, trials, pfa, {f"{k[0]}@{k[1]}": v for k, v in thresholds.items()})


def detected(maps: np.ndarray, cell: tuple[int, int], threshold: float) -> np.ndarray:
    """``bool (N,)``: a cell of the 3 x 3 gate around ``cell`` is above ``threshold`` in each
    map ``(N, H, W)`` (the target is detected)."""
    y, x = (int(v) for v in cell)
    return np.any(np.asarray(maps)[:, max(y - 1, 0):y + 2, max(x - 1, 0):x + 2] > threshold,
                  axis=(1, 2))


def crossing_snr(snrs_db: Iterable[float], pd: Iterable[float], level: float = 0.5) -> float:
    """The SNR where a Pd curve first reaches ``level`` (linear interpolation); NaN if never."""
    s = np.asarray(list(snrs_db), dtype=np.float64)
    p = np.asarray(list(pd), dtype=np.float64)
    above = np.nonzero(p >= level)[0]
    if not above.size:
        return float("nan")
    i = above[0]
    if i == 0:
        return float(s[0])
    return float(s[i - 1] + (level - p[i - 1]) * (s[i] - s[i - 1]) / (p[i] - p[i - 1]))
