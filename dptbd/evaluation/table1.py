"""Paper 001's Table 1 setting, reproduced by Monte Carlo (001 §4).

128 x 128 frames, 100 frames, noise mean 30 and variance 3.0, SNR 2.0 and 2.3, velocities
(1, 1), (0.8, -0.4) and (0.4, 0.6), a constant false-alarm count of 0.2 % of the pixels.
For each setting: first-level Pd and mean false points per accumulated frame of the
direction-weighted DP, plain DP and single-frame thresholding, all at the same
candidate count, on the same seeded scenes, in the bit-accurate fixed-point model.

With ``rtl=True`` (``dptbd table1 --rtl``, ``docs/table1.md`` "RTL in the loop") the two DP
detectors are accumulated by the compiled gateware instead
(:func:`dptbd.sim.rtl_trials.accumulate_trials`: every output word and candidate list
checked against the golden model); the gateware needs ``segment_stride == segment_frames``.
"""

from __future__ import annotations

import dataclasses
from typing import Iterator

import numpy as np

from dptbd.config import DPConfig, non_saturating_energy_bits, plain_weights
from dptbd.scenes import synthetic as scenes
from dptbd.scenes.synthetic import ADC_GAIN, INPUT_BITS
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
    (:func:`dptbd.sim.rtl_trials.summary`; None on the model)."""

    rows: list[Table1Row]
    rtl: dict | None = None


def _accumulate(frames: np.ndarray, cfg: DPConfig, rtl=None, label: str = "",
                first: int = 0, tally: list | None = None) -> np.ndarray:
    if rtl is not None:
        from dptbd.sim.rtl_trials import accumulate_trials
        res = accumulate_trials(rtl, frames, first_trial=first, label=label)
        tally[0] = tally[0] + res.tally
        return res.energy
    try:  # the fused kernel when it is there; the plain model gives the same bits
        from dptbd.model.fast import run_fixed_fast as run
    except ImportError:  # pragma: no cover
        from dptbd.model.fixed import run_fixed as run
    return run(frames, cfg).energy


def _setting_counts(snr: float, velocity: tuple[float, float], cfg: DPConfig, trials: int,
                    seed: int, chunk: int, rtl=None, tally=None
                    ) -> Iterator[tuple[str, DetectionCounts]]:
    plain = cfg.replace(weights=plain_weights(cfg.radius))
    rtl_dw, rtl_plain = rtl if rtl is not None else (None, None)
    where = f"SNR {snr:g}, V ({velocity[0]:g}, {velocity[1]:g})"
    count = count_for_rate(FALSE_ALARM_RATE, cfg.width * cfg.height)
    totals = {name: DetectionCounts(0, 0, 0, 0) for name in DETECTORS}
    for first in range(0, trials, chunk):
        scene = scenes.table1_scenario(snr, velocity, size=cfg.width, seed=seed,
                                       trials=min(chunk, trials - first), first_trial=first,
                                       dtype=np.float32)
        frames = scene.quantised(INPUT_BITS, gain=ADC_GAIN)
        ends = cfg.segment_stride * np.arange(cfg.n_segments(scene.n_frames)) + cfg.segment_frames - 1
        images = {
            "direction-weighted DP": _accumulate(
                frames, cfg, rtl_dw, f"configuration 'direction-weighted DP', {where}: ",
                first, tally),
            "plain DP": _accumulate(frames, plain, rtl_plain,
                                    f"configuration 'plain DP', {where}: ", first, tally),
            "single frame": frames[:, ends].astype(np.int64),
        }
        truth = scene.truth[0]
        for name, image in images.items():
            for trial_image in candidate_mask(image, count):
                totals[name] = totals[name] + first_level_counts(
                    trial_image, truth.pixel[ends][:, None], truth.visible[ends][:, None])
    yield from totals.items()


def table1_config(segment_frames: int = 6, segment_stride: int = 4, *,
                  size: int = 128) -> DPConfig:
    """The direction-weighted detector's configuration (the plain one: all-ones LUT)."""
    return DPConfig(width=size, height=size, segment_frames=segment_frames,
                    segment_stride=segment_stride, input_bits=INPUT_BITS,
                    energy_bits=max(16, non_saturating_energy_bits(INPUT_BITS, segment_frames)))


def run_table1(trials: int = 50, *, segment_frames: int = 6, segment_stride: int = 4,
               seed: int = 2003, chunk: int = 10, progress: bool = False, rtl: bool = False,
               settings=SETTINGS, size: int = 128) -> Table1Run:
    """Run the Table 1 settings; ``trials`` seeded scenes per setting.

    ``rtl``: the two DP detectors on the compiled gateware (refused, naming the detector,
    unless ``segment_stride == segment_frames``). ``settings`` and ``size`` (the paper's
    128) are for tests.
    """
    if trials < 1:
        raise ValueError(f"trials must be an integer in [1, inf), got {trials}")
    cfg = table1_config(segment_frames, segment_stride, size=size)
    builds, tally = None, None
    if rtl:
        from dptbd.sim.rtl_trials import RTLTally, check_configs, prepare_builds
        plain = cfg.replace(weights=plain_weights(cfg.radius))
        check_configs([("direction-weighted DP", cfg), ("plain DP", plain)])
        builds = (prepare_builds(cfg), prepare_builds(plain))
        tally = [RTLTally()]
    if progress:
        from tqdm import tqdm
        settings = tqdm(settings, desc="Table 1 settings", unit="setting")
    rows = []
    for snr, velocity in settings:
        for name, counts in _setting_counts(snr, velocity, cfg, trials, seed, chunk,
                                            builds, tally):
            rows.append(Table1Row(snr, velocity, name, counts))
    info = None
    if rtl:
        from dptbd.sim.rtl_trials import summary
        info = summary(tally[0], [("direction-weighted DP", builds[0].segmenter_missing),
                                  ("plain DP", builds[1].segmenter_missing)])
    return Table1Run(rows, info)


def table1_rows(trials: int = 50, *, segment_frames: int = 6, segment_stride: int = 4,
                seed: int = 2003, chunk: int = 10, progress: bool = False) -> list[Table1Row]:
    """Run every Table 1 setting on the golden model; ``trials`` seeded scenes per setting."""
    return run_table1(trials, segment_frames=segment_frames, segment_stride=segment_stride,
                      seed=seed, chunk=chunk, progress=progress).rows
