"""Run any set of detectors on the same scenes at the same false-alarm rate: Pd vs SNR.

Two scene families (``docs/detectors.md`` §3):

* ``rd`` — paper 004's range-Doppler magnitudes (:mod:`~dptbd.scenes.range_doppler`):
  scenario 2's target (geometry of 004 §4.1) on a ``crop`` of the 200 x 500 map around
  it, Swerling I, Rayleigh noise; the grid filters get the Doppler-implied range drift;
* ``image`` — paper 000's images (:func:`dptbd.scenes.synthetic.paper000_scenario`): 64 x 64,
  zero-mean Gaussian noise, a constant target moving (+2, -2) cells per frame.

For each detector the threshold is set on ``noise_trials`` noise-only scenes for
``false_alarm_rate`` per decision (:func:`~dptbd.evaluation.detectors.scoring.calibrate`);
then ``trials`` scenes per SNR give Pd = detections / opportunities (scored frames from
``first_frame`` on, the same frames for every detector). Every detector sees the same
seeded scenes. Work is split into (detector, SNR) tasks over ``jobs`` processes, or the
workers of an existing dask cluster (:mod:`dptbd.evaluation.execution`).
"""

from __future__ import annotations

import dataclasses
import math
import os
from typing import Iterable

import numpy as np

from dptbd.evaluation.detectors import adapters, interface, scoring
from dptbd.evaluation.detectors._checks import DetectorError, check_int, check_prob, check_real
from dptbd.evaluation.execution import Execution, check_worker_count, map_tasks
from dptbd.scenes import range_doppler as rd_scenes
from dptbd.scenes import synthetic as image_scenes

__all__ = ["SceneSpec", "CompareResult", "run_comparison", "SCENES"]

SCENES = ("rd", "image")
#: The rd crop of the 200 x 500 map: delay cells 112..175, Doppler cells 124..251 (64 x 128).
RD_CROP = (112, 124, 64, 128)


@dataclasses.dataclass(frozen=True)
class SceneSpec:
    """Which scenes: family, frames, crop and the preset SNR channel of the detectors."""

    kind: str = "rd"
    frames: int = 20
    preset_snr_db: float = 10.0
    crop: tuple[int, int, int, int] = RD_CROP  # (row0, col0, rows, cols) of the 200 x 500 map

    def __post_init__(self) -> None:
        if self.kind not in SCENES:
            raise DetectorError(f"scene must be one of {SCENES}, got {self.kind!r}")
        check_int("frames", self.frames, 2, 1000)
        check_real("preset_snr_db", self.preset_snr_db, -30.0, 60.0)
        r0, c0, h, w = self.crop
        check_int("crop rows", h, 19, 200)
        check_int("crop cols", w, 3, 500)
        check_int("crop row0", r0, 0, 200 - h)
        check_int("crop col0", c0, 0, 500 - w)

    def model(self, snr_db: float | None = None) -> interface.SceneModel:
        snr = self.preset_snr_db if snr_db is None else snr_db
        if self.kind == "rd":
            r0, c0, h, w = self.crop
            drift = rd_scenes.PassiveRadar().range_drift()[c0:c0 + w]
            return interface.SceneModel((h, w), "rayleigh", 1.0, snr, 1, drift)
        return interface.SceneModel((64, 64), "gaussian", 1.0, snr, 2, None)

    def truth(self) -> tuple[np.ndarray, np.ndarray]:
        """``(pixel (T, 2), visible (T,))`` of the target in scene coordinates."""
        if self.kind == "rd":
            r0, c0, h, w = self.crop
            track = rd_scenes.scenario2_track(frames=self.frames) - np.array([r0, c0])
            pix = np.rint(track).astype(np.int64)
            vis = (pix[:, 0] >= 0) & (pix[:, 0] < h) & (pix[:, 1] >= 0) & (pix[:, 1] < w)
            return pix, vis
        sc = image_scenes.paper000_scenario(0.0, frames=self.frames, noise=False)
        return sc.truth[0].pixel, sc.truth[0].visible

    def frames_for(self, snr_db: float | None, trials: int, seed: int, first_trial: int = 0) -> np.ndarray:
        """``(N, T, H, W)`` scenes; ``snr_db=None`` for noise only (same noise as with a target)."""
        if self.kind == "rd":
            r0, c0, h, w = self.crop
            track = None
            if snr_db is not None:
                track = rd_scenes.scenario2_track(frames=self.frames) - np.array([r0, c0])
            sc = rd_scenes.rd_scene((h, w), self.frames, track, snr_db=0.0 if snr_db is None else snr_db,
                                    seed=seed, trials=trials, first_trial=first_trial)
            return sc.frames
        if snr_db is None:
            return image_scenes.make_noise((64, 64), self.frames, seed=seed, trials=trials,
                                           first_trial=first_trial, dtype=np.float32)
        return image_scenes.paper000_scenario(snr_db, frames=self.frames, seed=seed, trials=trials,
                                              first_trial=first_trial, dtype=np.float32).frames


@dataclasses.dataclass(frozen=True)
class CompareResult:
    """Per detector: threshold, noise false alarms and Pd counts per SNR."""

    detectors: tuple[str, ...]
    snrs_db: tuple[float, ...]
    thresholds: dict  # name -> threshold (or {snr: threshold} when matched)
    false_alarms: dict  # name -> Counts (on the calibration scenes)
    detections: dict  # (name, snr) -> Counts
    params: dict
    #: further false-alarm rates per decision (ROC), each calibrated on the same noise-only
    #: scenes: ``roc_thresholds[name][i]`` (or ``{snr: ...}`` when matched),
    #: ``roc_false_alarms[name][i]`` and ``roc_detections[(name, snr)][i]`` at ``roc_pfas[i]``
    roc_pfas: tuple = ()
    roc_thresholds: dict = dataclasses.field(default_factory=dict)
    roc_false_alarms: dict = dataclasses.field(default_factory=dict)
    roc_detections: dict = dataclasses.field(default_factory=dict)


_CHUNK = 10


def _noise_task(args: tuple) -> tuple:
    """Decision statistics of one detector (at one preset channel) on a chunk of noise-only scenes."""
    name, spec, channel, lo, n, seed, params = args
    det = adapters.make_detector(name, spec.model(channel), **params.get(name, {}))
    return name, channel, lo, det.decide(spec.frames_for(None, n, seed + 1, lo)).statistic


def _pd_task(args: tuple) -> tuple:
    """Detections of one detector on the target scenes of one SNR, at each of its thresholds
    (the operating point first, then the ROC levels)."""
    name, spec, snr, channel, thrs, trials, seed, first_frame, gate, params = args
    det = adapters.make_detector(name, spec.model(channel), **params.get(name, {}))
    pixel, visible = spec.truth()
    hits = [scoring.Counts(0, 0) for _ in thrs]
    for lo in range(0, trials, _CHUNK):
        frames = spec.frames_for(snr, min(_CHUNK, trials - lo), seed, lo)
        dec = det.decide(frames)
        for i, thr in enumerate(thrs):
            c = scoring.count_detections(dec, thr, pixel, visible, first_frame=first_frame, gate=gate)
            hits[i] = scoring.Counts(hits[i].hits + c.hits, hits[i].total + c.total)
    return name, snr, hits


def _map(fn, tasks: list, client, progress: bool, desc: str) -> list:
    """``fn`` on every task, results in task order (:func:`~dptbd.evaluation.execution.map_tasks`)."""
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=len(tasks), desc=desc, unit="task")
    try:
        return map_tasks(fn, [(t,) for t in tasks], client, bar=bar)
    finally:
        if bar is not None:
            bar.close()


def run_comparison(detectors: Iterable[str] = adapters.DEFAULT_DETECTORS, *,
                   snrs_db: Iterable[float] = (0.0, 3.0, 6.0, 9.0, 12.0, 15.0),
                   spec: SceneSpec | None = None, trials: int = 20, noise_trials: int = 50,
                   false_alarm_rate: float = 0.01, matched: bool = False, seed: int = 6,
                   first_frame: int | None = None, gate: int = 1, jobs: int = 2,
                   params: dict | None = None, progress: bool = False,
                   scheduler: str | None = None, dashboard: bool = False,
                   roc_pfas: Iterable[float] = ()) -> CompareResult:
    """Pd vs SNR of every detector at the same false-alarm rate per decision.

    Parameters
    ----------
    detectors : iterable of str
        Names from :data:`~dptbd.evaluation.detectors.adapters.DETECTORS`.
    snrs_db : iterable of float
        SNRs in dB (rd: average per-cell SNR; image: paper 000 eq (8)).
    spec : SceneSpec
        Scene family and length; default ``SceneSpec()`` (rd, 20 frames).
    trials, noise_trials : int
        Target scenes per SNR; noise-only scenes for the thresholds.
    false_alarm_rate : float
        Per decision, in (0, 1).
    matched : bool
        Set the preset SNR channel of each detector that has one (``uses_channel``: info,
        grid-bayes, dp-likelihood) to the scene's SNR and recalibrate it per SNR (004's
        matched case); else the channel is ``spec.preset_snr_db`` for all.
    first_frame : int or None
        First scored frame; ``None``: K - 1 of the DPs (7), the same for every detector.
    gate : int
        Chebyshev distance of a correct estimate, cells.
    jobs : int
        Worker processes (1 = in this process); with a scheduler, the number of workers the
        cluster must have.
    scheduler : str or None
        ``tcp://HOST:PORT`` of an existing dask cluster (default: ``DPTBD_SCHEDULER`` if set,
        else local processes; ``docs/distributed.md``).
    dashboard : bool
        Print the dask dashboard's address.
    params : dict
        ``{detector name: {parameter: value}}`` passed to the detector constructors.
    roc_pfas : iterable of float
        Further false-alarm rates per decision, each in (0, 1), calibrated on the same
        noise-only decisions: the points of the ROC (Pd against Pfa), on the same scenes.
    """
    names = adapters.parse_detectors(list(detectors))
    spec = SceneSpec() if spec is None else spec
    if not isinstance(spec, SceneSpec):
        raise DetectorError(f"spec must be a SceneSpec, got {spec!r}")
    snrs = tuple(check_real("snr_db", s, -30.0, 60.0) for s in snrs_db)
    if not snrs:
        raise DetectorError("snrs_db must hold at least one SNR")
    trials = check_int("trials", trials, 1)
    noise_trials = check_int("noise_trials", noise_trials, 1)
    pfa = check_prob("false_alarm_rate", false_alarm_rate)
    jobs = check_worker_count(jobs, "jobs")
    gate = check_int("gate", gate, 0)
    params = {} if params is None else dict(params)
    for key in params:
        adapters.parse_detectors([key])
    k = max([p.get("segment_frames", 8) for n, p in [(n, params.get(n, {})) for n in names]] + [8])
    first = min(k - 1, spec.frames - 1) if first_frame is None else check_int(
        "first_frame", first_frame, 0, spec.frames - 1)
    # fail early, in this process, on bad detector parameters
    for n in names:
        det = adapters.make_detector(n, spec.model(), **params.get(n, {}))
        if getattr(det, "k", 0) > spec.frames:
            raise DetectorError(f"{n}: segment_frames={det.k} is longer than the scenes' frames={spec.frames}")
    roc = tuple(check_prob("roc false_alarm_rate", p) for p in roc_pfas)
    decisions = (spec.frames - first) * noise_trials
    for p in (pfa,) + roc:
        if math.floor(p * decisions) < 1:
            raise DetectorError(f"false_alarm_rate={p:g} needs at least {math.ceil(1 / p)} noise-only "
                                f"decisions, {noise_trials} noise trials give {decisions}; raise noise_trials")
    def channels(name: str) -> tuple:
        matched_here = matched and adapters.DETECTORS[name].uses_channel
        return snrs if matched_here else (spec.preset_snr_db,)

    execution = Execution(workers=jobs, scheduler=scheduler, dashboard=dashboard)
    if execution.address is None:
        execution = dataclasses.replace(execution, workers=min(jobs, os.cpu_count() or 1))
    with execution.client() as client:
        return _run(names, snrs, spec, trials, noise_trials, pfa, matched, seed, first, gate,
                    params, channels, client, progress, roc)


def _run(names, snrs, spec, trials, noise_trials, pfa, matched, seed, first, gate, params,
         channels, client, progress, roc=()) -> CompareResult:
    def channel(name: str, snr: float) -> float:
        return snr if matched and adapters.DETECTORS[name].uses_channel else spec.preset_snr_db

    chunks = [(lo, min(_CHUNK, noise_trials - lo)) for lo in range(0, noise_trials, _CHUNK)]
    noise = _map(_noise_task, [(n, spec, c, lo, m, seed, params) for n in names for c in channels(n)
                               for lo, m in chunks], client, progress, "thresholds")
    cal = []
    for n in names:
        for c in channels(n):
            parts = sorted((lo, st) for nn, cc, lo, st in noise if (nn, cc) == (n, c))
            stat = np.concatenate([st for _, st in parts])
            dec = interface.Decisions(stat, np.zeros(stat.shape + (2,)))
            ts = [scoring.calibrate(stat[:, first:], p) for p in (pfa,) + roc]
            fas = [scoring.count_false_alarms(dec, t, first_frame=first) for t in ts]
            cal.append((n, c, ts, fas))
    thr = {(n, c): ts for n, c, ts, _ in cal}
    levels = 1 + len(roc)
    thresholds: dict = {n: [None] * levels for n in names}
    false_alarms: dict = {n: [scoring.Counts(0, 0)] * levels for n in names}
    for n, c, ts, fas in cal:
        for i in range(levels):
            if len(channels(n)) > 1:
                if thresholds[n][i] is None:
                    thresholds[n][i] = {}
                thresholds[n][i][c] = ts[i]
            else:
                thresholds[n][i] = ts[i]
            prev = false_alarms[n][i]
            false_alarms[n][i] = scoring.Counts(prev.hits + fas[i].hits, prev.total + fas[i].total)
    tasks = []
    for n in names:
        for s in snrs:
            c = channel(n, s)
            tasks.append((n, spec, s, c, thr[(n, c)], trials, seed, first, gate, params))
    found = {(n, s): h for n, s, h in _map(_pd_task, tasks, client, progress, "Pd")}
    info = dict(scene=spec.kind, frames=spec.frames, preset_snr_db=spec.preset_snr_db, crop=spec.crop,
                trials=trials, noise_trials=noise_trials, false_alarm_rate=pfa, matched=matched,
                seed=seed, first_frame=first, gate=gate, params=params)
    if roc:
        info["roc_false_alarm_rates"] = list(roc)
    return CompareResult(names, snrs, {n: t[0] for n, t in thresholds.items()},
                         {n: f[0] for n, f in false_alarms.items()},
                         {k: h[0] for k, h in found.items()}, info, roc,
                         {n: t[1:] for n, t in thresholds.items()},
                         {n: f[1:] for n, f in false_alarms.items()},
                         {k: h[1:] for k, h in found.items()})
