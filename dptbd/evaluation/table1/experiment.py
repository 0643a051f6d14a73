"""Paper 001's Table 1 setting, reproduced by Monte Carlo (001 §4).

128 x 128 frames, 100 frames, noise mean 30 and variance 3.0, SNR 2.0 and 2.3, velocities
(1, 1), (0.8, -0.4) and (0.4, 0.6), a constant false-alarm count of 0.2 % of the pixels.
For each setting: first-level Pd and mean false points per accumulated frame of the
direction-weighted DP, plain DP and single-frame thresholding, all at the same
candidate count, on the same seeded scenes, in the bit-accurate fixed-point model.

With ``rtl=True`` (``dptbd table1 --rtl``, ``docs/table1.md`` "RTL in the loop") the two DP
detectors are accumulated by the compiled gateware instead
(:func:`dptbd.sim.rtl.trials.accumulate_trials`: every output word and candidate list
checked against the golden model); the gateware needs ``segment_stride == segment_frames``.

The trials run as tasks of ``chunk`` trials of one setting on
:mod:`dptbd.evaluation.execution` (in this process, local worker processes or a dask
cluster, ``docs/distributed.md``); every scene is seeded by the base seed and its trial
index, so the rows are the same on any number of workers.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
from tqdm import tqdm

from dptbd.config import DPConfig, non_saturating_energy_bits
from dptbd.weights import plain_weights
from dptbd.errors import check_int
from dptbd.scenes import synthetic as scenes
from dptbd.scenes.synthetic import ADC_GAIN, INPUT_BITS
from dptbd.evaluation.execution import job_execution, map_tasks, warmed
from dptbd.evaluation.metrics import DetectionCounts, first_level_counts
from dptbd.model.segmentation import candidate_mask, count_for_rate

__all__ = ["PAPER_TABLE1", "SETTINGS", "DETECTORS", "Table1Row", "Table1Run", "table1_config",
           "run_table1", "table1_rows"]

#: Paper 001 Table 1: (SNR, velocity) -> (detections of 24, Pd, mean false points,
#: frames until output, detected track length).
PAPER_TABLE1 = {
    (2.3, (1.0, 1.0)): (19, 0.79, 34.4, 40, 60),
    (2.3, (0.8, -0.4)): (18, 0.75, 33.5, 44, 56),
    (2.3, (0.4, 0.6)): (18, 0.75, 32.3, 48, 52),
    (2.0, (1.0, 1.0)): (13, 0.55, 35.2, 60, 25),
    (2.0, (0.8, -0.4)): (17, 0.71, 34.2, 45, 52),
    (2.0, (0.4, 0.6)): (19, 0.79, 34.2, 49, 48),
}
SETTINGS = tuple(PAPER_TABLE1)
DETECTORS = ("direction-weighted DP", "plain DP", "single frame")
FALSE_ALARM_RATE = 0.002


@dataclasses.dataclass(frozen=True)
class Table1Row:
    """One (SNR, velocity, detector) line of the reproduction."""

    snr: float
    velocity: tuple[float, float]
    detector: str
    counts: DetectionCounts


@dataclasses.dataclass(frozen=True)
class Table1Run:
    """The rows, and with ``rtl=True`` what went through the gateware
    (:func:`dptbd.sim.rtl.trials.summary`; None on the model)."""

    rows: list[Table1Row]
    rtl: dict | None = None


def _accumulate(frames: np.ndarray, cfg: DPConfig, rtl=None, label: str = "",
                first: int = 0):
    """E after every segment of ``frames``, and the RTL's tally (None on the model)."""
    if rtl is not None:
        from dptbd.sim.rtl.trials import accumulate_trials
        res = accumulate_trials(rtl, frames, first_trial=first, label=label)
        return res.energy, res.tally
    try:  # the fused kernel when it is there; the plain model gives the same bits
        from dptbd.model.fast import run_fixed_fast as run
    except ImportError:  # pragma: no cover
        from dptbd.model.fixed import run_fixed as run
    return run(frames, cfg).energy, None


def _trials_counts(snr: float, velocity: tuple[float, float], cfg: DPConfig, seed: int,
                   first: int, stop: int, rtl=None) -> tuple[dict, object]:
    """One task: trials ``first .. stop - 1`` of one setting, every detector.

    Returns ``({detector: DetectionCounts}, RTL tally or None)``. A pure function of its
    arguments (each trial's scene is seeded by ``seed`` and its index), so it gives the
    same counts on any worker."""
    plain = cfg.replace(weights=plain_weights(cfg.radius))
    rtl_dw, rtl_plain = rtl if rtl is not None else (None, None)
    where = f"SNR {snr:g}, V ({velocity[0]:g}, {velocity[1]:g})"
    count = count_for_rate(FALSE_ALARM_RATE, cfg.width * cfg.height)
    scene = scenes.table1_scenario(snr, velocity, size=cfg.width, seed=seed,
                                   trials=stop - first, first_trial=first, dtype=np.float32)
    frames = scene.quantised(INPUT_BITS, gain=ADC_GAIN)
    ends = cfg.segment_stride * np.arange(cfg.n_segments(scene.n_frames)) + cfg.segment_frames - 1
    dw, tally_dw = _accumulate(frames, cfg, rtl_dw,
                               f"configuration 'direction-weighted DP', {where}: ", first)
    pl, tally_pl = _accumulate(frames, plain, rtl_plain, f"configuration 'plain DP', {where}: ",
                               first)
    images = {"direction-weighted DP": dw, "plain DP": pl,
              "single frame": frames[:, ends].astype(np.int64)}
    truth = scene.truth[0]
    totals = {}
    for name, image in images.items():
        total = DetectionCounts(0, 0, 0, 0)
        for trial_image in candidate_mask(image, count):
            total = total + first_level_counts(
                trial_image, truth.pixel[ends][:, None], truth.visible[ends][:, None])
        totals[name] = total
    return totals, (None if rtl is None else tally_dw + tally_pl)


def _warm(cfg: DPConfig, seed: int) -> None:
    """Load every kernel of a task (numba's on-disk cache) on one trial of one setting."""
    snr, velocity = SETTINGS[0]
    _trials_counts(snr, velocity, cfg, seed, 0, 1)


def table1_config(segment_frames: int = 6, segment_stride: int = 4, *,
                  size: int = 128) -> DPConfig:
    """The direction-weighted detector's configuration (the plain one: all-ones LUT)."""
    return DPConfig(width=size, height=size, segment_frames=segment_frames,
                    segment_stride=segment_stride, input_bits=INPUT_BITS,
                    energy_bits=max(16, non_saturating_energy_bits(INPUT_BITS, segment_frames)))


def run_table1(trials: int = 50, *, segment_frames: int = 6, segment_stride: int = 4,
               seed: int = 2003, chunk: int = 10, progress: bool = False, rtl: bool = False,
               settings=SETTINGS, size: int = 128, workers: int | None = 1,
               scheduler: str | None = None, dashboard: bool = False) -> Table1Run:
    """Run the Table 1 settings; ``trials`` seeded scenes per setting.

    One task per ``chunk`` trials of one setting (about a second at 128 x 128), on the
    execution layer :mod:`dptbd.evaluation.execution`: ``workers`` local worker processes
    (1: in this process; None: every core), or the cluster at ``scheduler`` (or
    ``DPTBD_SCHEDULER``), which must then have ``workers`` workers (None: any);
    ``dashboard`` prints the dask dashboard's address. The rows depend on none of these.

    ``rtl``: the two DP detectors on the compiled gateware (refused, naming the detector,
    unless ``segment_stride == segment_frames``); the executables are built (or taken from
    the cache) here and their paths sent with the tasks. ``settings`` and ``size`` (the
    paper's 128) are for tests.
    """
    trials = check_int("trials", trials, 1)
    chunk = check_int("chunk", chunk, 1)
    settings = list(settings)
    tasks = [(snr, velocity, first, min(first + chunk, trials))
             for snr, velocity in settings for first in range(0, trials, chunk)]
    execution = job_execution(workers, scheduler=scheduler, dashboard=dashboard,
                              tasks=len(tasks))
    cfg = table1_config(segment_frames, segment_stride, size=size)
    builds = None
    if rtl:
        from dptbd.sim.rtl.trials import check_configs, prepare_builds
        plain = cfg.replace(weights=plain_weights(cfg.radius))
        check_configs([("direction-weighted DP", cfg), ("plain DP", plain)])
        builds = (prepare_builds(cfg), prepare_builds(plain))
    with execution.client() as client, warmed(client, functools.partial(_warm, cfg, seed)):
        # the bar after the cluster's start (and its dashboard line)
        with tqdm(total=trials * len(settings), desc="Table 1", unit="trial",
                  disable=not progress) as bar:
            parts = map_tasks(_trials_counts,
                              [(snr, vel, cfg, seed, a, b, builds) for snr, vel, a, b in tasks],
                              client, sizes=[b - a for *_, a, b in tasks], bar=bar)
    totals: dict = {}
    for (snr, velocity, _, _), (counts, _) in zip(tasks, parts):
        setting = totals.setdefault((snr, velocity), {n: DetectionCounts(0, 0, 0, 0)
                                                      for n in DETECTORS})
        for name in DETECTORS:
            setting[name] = setting[name] + counts[name]
    rows = [Table1Row(snr, velocity, name, counts)
            for (snr, velocity), by_name in totals.items() for name, counts in by_name.items()]
    info = None
    if rtl:
        from dptbd.sim.rtl.trials import RTLTally, summary
        tally = RTLTally()
        for _, part in parts:
            tally = tally + part
        info = summary(tally, [("direction-weighted DP", builds[0].segmenter_missing),
                               ("plain DP", builds[1].segmenter_missing)])
    return Table1Run(rows, info)


def table1_rows(trials: int = 50, *, segment_frames: int = 6, segment_stride: int = 4,
                seed: int = 2003, chunk: int = 10, progress: bool = False,
                workers: int | None = 1) -> list[Table1Row]:
    """Run every Table 1 setting on the golden model; ``trials`` seeded scenes per setting."""
    return run_table1(trials, segment_frames=segment_frames, segment_stride=segment_stride,
                      seed=seed, chunk=chunk, progress=progress, workers=workers).rows
