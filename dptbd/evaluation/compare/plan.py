"""The plan a worker runs: the configurations grouped into detectors, the ADCs, the target's
truth and the thresholds in each detector's units."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from dptbd.config import DPConfig
from dptbd.scenes import synthetic as scenes
from dptbd.evaluation.metrics import near_mask
from dptbd.evaluation.compare.spec import CompareSpec, FixedSpec

__all__ = ["Plan", "detector_key", "make_plan"]


@dataclasses.dataclass(frozen=True)
class Plan:
    """What a worker needs: the detectors, the ADCs, the target's truth. Picklable.

    Detectors ``0 .. len(floats) - 1`` are the float models (one per distinct LUT),
    then the fixed behaviours (configurations that compute identical bits and select the
    same candidates from them share one: :func:`detector_key`).
    """

    spec: CompareSpec
    floats: tuple[DPConfig, ...]
    fixed: tuple[DPConfig, ...]
    fixed_float: tuple[int, ...]      # the float detector each fixed behaviour is compared with
    fixed_adc: tuple[int, ...]        # index into adcs
    adcs: tuple[tuple[int, float, float], ...]  # (B_in, gain, offset)
    config_detector: tuple[int, ...]  # detector index of each spec.configs entry
    amplitudes: tuple[float, ...]
    target_t: np.ndarray              # frames in which the target is drawn …
    target_px: np.ndarray             # … and its (row, col) there
    ends: np.ndarray                  # last frame of each segment
    near: np.ndarray                  # (S, H, W) detection gate per segment
    near_flat: np.ndarray             # (S, H*W) the same, flattened
    visible: np.ndarray               # (S,) target visible at the segment's end
    levels: np.ndarray                # (D, n_thr) thresholds in each detector's E units
    rtl: tuple = ()                   # RTL in the loop: dptbd.sim.rtl.trials.RTLBuilds per
    #                                   fixed behaviour (empty: the golden model)
    noise_keep: int = 0               # noise-only E values each chunk keeps per detector for
    #                                   the equal-Pfa thresholds: floor(max pfa * all noise
    #                                   pixels) + 1, enough for an exact merge

    @property
    def n_detectors(self) -> int:
        return len(self.floats) + len(self.fixed)

    def detector_names(self) -> list[str]:
        names = []
        for i, cfg in enumerate(self.floats):
            luts = sorted({f.lut for f in self.spec.configs if f.float_key() == tuple(cfg.weights)})
            names.append("float " + "/".join(luts))
        for b in range(len(self.fixed)):
            d = len(self.floats) + b
            names.append(" = ".join(f.name for f, k in zip(self.spec.configs, self.config_detector)
                                    if k == d))
        return names


def detector_key(f: FixedSpec, tie_rule: str) -> tuple:
    """Configurations with the same key are one detector: same candidates on every scene.

    The DP bits (:meth:`FixedSpec.behaviour_key`), and under the ``gateware-bins`` rule
    the histogram too: that rule selects on ``min(E >> s, 2**b - 1)``
    (:func:`dptbd.model.segmentation.histogram_bins`), so two configurations with the same
    E but another shift s or bin count 2**b keep other candidates and must not share a
    detector (whose candidates would be selected with the first one's s). The other rules
    never look at the histogram.
    """
    key = f.behaviour_key()
    if tie_rule == "gateware-bins":
        key += (("bins", f.cfg.bin_shift, f.cfg.n_bins),)
    return key


def make_plan(spec: CompareSpec) -> Plan:
    """Group the configurations into detectors and precompute the target's truth."""
    floats: list[DPConfig] = []
    float_keys: list[tuple] = []
    fixed: list[DPConfig] = []
    behaviour_keys: list[tuple] = []
    fixed_float: list[int] = []
    fixed_adc: list[int] = []
    adcs: list[tuple[int, float, float]] = []
    config_detector: list[int] = []
    for f in spec.configs:
        fk = f.float_key()
        if fk not in float_keys:
            float_keys.append(fk)
            floats.append(f.cfg.replace(input_bits=16, energy_bits=32))
    for f in spec.configs:
        key = detector_key(f, spec.tie_rule)
        if key not in behaviour_keys:
            behaviour_keys.append(key)
            fixed.append(f.cfg)
            fixed_float.append(float_keys.index(f.float_key()))
            adc = (f.cfg.input_bits, f.adc_gain, f.adc_offset)
            if adc not in adcs:
                adcs.append(adc)
            fixed_adc.append(adcs.index(adc))
        config_detector.append(len(floats) + behaviour_keys.index(key))

    base = spec.base_cfg
    scene = scenes.table1_scenario(1.0, spec.velocity, frames=spec.frames, size=spec.size,
                                   mu=spec.mu, sigma=spec.sigma, noise=False)
    truth = scene.truth[0]
    target_t = np.flatnonzero(truth.visible)
    target_px = truth.pixel[target_t]
    ends = np.arange(base.n_segments(spec.frames)) * base.segment_stride + base.segment_frames - 1
    near = np.zeros((len(ends), spec.size, spec.size), dtype=bool)
    visible = truth.visible[ends].copy()
    for s, t in enumerate(ends):
        if visible[s]:
            near[s] = near_mask((spec.size, spec.size), truth.pixel[t][None], 1)
    k = base.segment_frames
    z = np.asarray(spec.thresholds)
    tau = k * spec.mu + z * math.sqrt(k) * spec.sigma  # float-model units
    levels = [tau for _ in floats]
    for b in range(len(fixed)):
        _, gain, offset = adcs[fixed_adc[b]]
        levels.append(gain * tau + k * offset)
    return Plan(spec=spec, floats=tuple(floats), fixed=tuple(fixed), fixed_float=tuple(fixed_float),
                fixed_adc=tuple(fixed_adc), adcs=tuple(adcs), config_detector=tuple(config_detector),
                amplitudes=tuple(scenes.amplitude_from_snr(s, spec.sigma) for s in spec.snr),
                target_t=target_t, target_px=target_px, ends=ends, near=near,
                near_flat=near.reshape(len(ends), -1).copy(), visible=visible,
                levels=np.array(levels),
                noise_keep=int(max(spec.pfa) * spec.trials * len(ends) * spec.size ** 2) + 1)
