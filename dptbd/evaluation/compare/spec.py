"""The specification of a comparison: the run and the fixed configurations it compares,
validated from a TOML file (:func:`build_spec`) before any work. This module holds the
run-level parameters (:data:`DEFAULT_RUN`, :class:`CompareSpec`); the configurations
(:class:`FixedSpec`, the defaults, the ``[[config]]`` and ``[sweep]`` tables) are in
:mod:`dptbd.evaluation.compare.configs`, the checks of the TOML values in
:mod:`dptbd.evaluation.compare.checks`, the weight LUTs and the default ADC mapping in
:mod:`dptbd.evaluation.compare.luts` (the names of both re-exported here).

The package docstring (:mod:`dptbd.evaluation.compare`) describes the scene and what is
measured; ``docs/compare.md`` the TOML file.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Mapping

import numpy as np

from dptbd.config import DPConfig
from dptbd.errors import ConfigError, check_prob, check_real
from dptbd.evaluation.compare.checks import as_list, checked_int, checked_real, increasing_reals
from dptbd.evaluation.compare.configs import (DEFAULT_CONFIGS, DEFAULT_SWEEP, FixedSpec,
                                              make_fixed, sweep_entries)
from dptbd.evaluation.compare.luts import LUTS, adc_mapping, cosine_weights, lut_weights
from dptbd.scenes import synthetic as scenes
from dptbd.model.segmentation import count_for_rate

__all__ = [
    "LUTS", "cosine_weights", "lut_weights", "adc_mapping", "FixedSpec", "CompareSpec",
    "DEFAULT_RUN", "DEFAULT_CONFIGS", "DEFAULT_SWEEP", "TIE_RULES", "build_spec",
]

#: The candidate rules (run-level key ``tie_rule``, ``--tie-rule``;
#: :mod:`dptbd.evaluation.compare.selection`): ``random``, exactly n candidates per image with
#: the ties at the n-th largest E broken by a seeded priority (the default); ``gateware``,
#: the gateware segmenter's selection with the image's own histogram and one bin per E value
#: (``E > v_(n+1)``, a tie at the boundary dropped whole); ``gateware-bins``, the same on
#: the histogram bins of each configuration's ``DPConfig`` (``E >> s``, clamped).
TIE_RULES = ("random", "gateware", "gateware-bins")

#: Run-level parameters (flat keys of the TOML file) and their defaults (``docs/compare.md``;
#: the default run's time: ``docs/compare_results.md``).
DEFAULT_RUN: dict[str, Any] = {
    "trials": 240,
    "seed": 2024,
    "snr": (1.5, 1.7, 1.9, 2.1, 2.3, 2.5, 2.7, 2.9),  # 001's linear SNR
    "size": 64,
    "frames": 48,
    "velocity": (1.0, 1.0),
    "mu": scenes.TABLE1_MU,
    "sigma": scenes.TABLE1_SIGMA,
    "segment_frames": 6,
    "segment_stride": None,
    "radius": 1,
    "false_alarm_rate": 0.002,
    "thresholds": tuple(round(2.0 + 0.1 * i, 10) for i in range(46)),  # z = 2.0 … 6.5
    "pd_levels": (0.5, 0.8),
    "tolerance_db": 0.1,
    "bootstrap": 1000,
    "chunk": 8,
    "adc_low_sigma": 6.0,
    "adc_span_sigma": 16.0,
    "tie_rule": "random",
    # the second operating point: false-alarm probabilities per pixel, each a threshold
    # calibrated on the noise-only scenes; None: false_alarm_rate's (the list's own rate)
    "pfa": None,
}


# ==== the specification of a run ========================================================

@dataclasses.dataclass(frozen=True)
class CompareSpec:
    """Everything that determines a comparison's numbers (see :data:`DEFAULT_RUN`)."""

    trials: int
    seed: int
    snr: tuple[float, ...]
    size: int
    frames: int
    velocity: tuple[float, float]
    mu: float
    sigma: float
    segment_frames: int
    segment_stride: int
    radius: int
    false_alarm_rate: float
    thresholds: tuple[float, ...]
    pd_levels: tuple[float, ...]
    tolerance_db: float
    bootstrap: int
    chunk: int
    adc_low_sigma: float
    adc_span_sigma: float
    tie_rule: str
    configs: tuple[FixedSpec, ...]
    pfa: tuple[float, ...] = (0.002,)

    @property
    def base_cfg(self) -> DPConfig:
        return DPConfig(width=self.size, height=self.size, segment_frames=self.segment_frames,
                        segment_stride=self.segment_stride, radius=self.radius)

    @property
    def snr_db(self) -> np.ndarray:
        return 20.0 * np.log10(np.asarray(self.snr))

    @property
    def candidate_count(self) -> int:
        return count_for_rate(self.false_alarm_rate, self.size * self.size)

    def run_params(self) -> dict:
        """The run-level parameters as plain values (for JSON).

        ``tie_rule`` only when it is not the default ``"random"``: a summary without it is a
        ``random`` run, as every run before the option existed was (and the default run's
        files stay what they were).
        """
        out = {}
        for f in dataclasses.fields(self):
            if f.name == "configs" or (f.name == "tie_rule" and self.tie_rule == "random"):
                continue
            v = getattr(self, f.name)
            out[f.name] = list(v) if isinstance(v, tuple) else v
        return out


def build_spec(mapping: Mapping[str, Any] | None = None, **overrides: Any) -> CompareSpec:
    """Validate a comparison's parameters; every error is raised here, before any work.

    Parameters
    ----------
    mapping : mapping, optional
        A parsed TOML file: run-level keys (:data:`DEFAULT_RUN`), ``config`` (a list of
        tables, replacing :data:`DEFAULT_CONFIGS`) and ``sweep`` (a table — or a list of
        tables, each its own grid — replacing :data:`DEFAULT_SWEEP`; an empty table means
        no sweep).
    **overrides
        Run-level keys given on the command line (``trials``, ``seed``, ``snr``, …);
        ``None`` values are ignored.

    Raises
    ------
    dptbd.errors.ConfigError
        Unknown keys (by name), impossible widths, an empty or non-increasing SNR list,
        ``trials`` < 1, …
    """
    mapping = dict(mapping or {})
    configs = mapping.pop("config", list(DEFAULT_CONFIGS))
    sweep = mapping.pop("sweep", DEFAULT_SWEEP)
    unknown = sorted(set(mapping) - set(DEFAULT_RUN))
    if unknown:
        raise ConfigError(f"unknown parameter(s) {unknown}; "
                          f"allowed: {sorted(DEFAULT_RUN) + ['config', 'sweep']}")
    bad_over = sorted(set(overrides) - set(DEFAULT_RUN))
    if bad_over:
        raise ConfigError(f"unknown parameter(s) {bad_over}")
    run = dict(DEFAULT_RUN)
    run.update(mapping)
    run.update({k: v for k, v in overrides.items() if v is not None})

    run["trials"] = checked_int("trials", run["trials"], 1)
    run["seed"] = checked_int("seed", run["seed"], 0)
    run["snr"] = increasing_reals("snr", run["snr"], min_len=2, positive=True)
    run["size"] = checked_int("size", run["size"], 3, 4096)
    run["frames"] = checked_int("frames", run["frames"], 1, 100000)
    vel = as_list("velocity", run["velocity"])
    if len(vel) != 2:
        raise ConfigError(f"velocity must be a (row, col) pair, got {run['velocity']!r}")
    run["velocity"] = tuple(checked_real(f"velocity[{i}]", v) for i, v in enumerate(vel))
    run["mu"] = checked_real("mu", run["mu"])
    run["sigma"] = checked_real("sigma", run["sigma"], positive=True)
    run["segment_frames"] = checked_int("segment_frames", run["segment_frames"], 1, 65535)
    if run["segment_stride"] is not None:
        run["segment_stride"] = checked_int("segment_stride", run["segment_stride"], 1,
                                        run["segment_frames"])
    else:
        run["segment_stride"] = run["segment_frames"]
    run["radius"] = checked_int("radius", run["radius"], 1, 2)
    if run["frames"] < run["segment_frames"]:
        raise ConfigError(f"frames={run['frames']} is shorter than one segment "
                          f"(segment_frames={run['segment_frames']})")
    run["false_alarm_rate"] = check_prob("false_alarm_rate", run["false_alarm_rate"],
                                         error=ConfigError)
    if count_for_rate(run["false_alarm_rate"], run["size"] ** 2) < 1:
        raise ConfigError(f"false_alarm_rate={run['false_alarm_rate']} keeps no candidate in a "
                          f"{run['size']}x{run['size']} image")
    run["thresholds"] = increasing_reals("thresholds", run["thresholds"])
    levels = as_list("pd_levels", run["pd_levels"])
    if not levels:
        raise ConfigError("pd_levels must not be empty")
    run["pd_levels"] = tuple(check_prob(f"pd_levels[{i}]", v, error=ConfigError)
                             for i, v in enumerate(levels))
    run["tolerance_db"] = check_real("tolerance_db", run["tolerance_db"], 0.0, error=ConfigError)
    run["bootstrap"] = checked_int("bootstrap", run["bootstrap"], 0, 10**6)
    run["chunk"] = checked_int("chunk", run["chunk"], 1)
    run["adc_low_sigma"] = checked_real("adc_low_sigma", run["adc_low_sigma"])
    run["adc_span_sigma"] = checked_real("adc_span_sigma", run["adc_span_sigma"], positive=True)
    pfas = [run["false_alarm_rate"]] if run["pfa"] is None else as_list("pfa", run["pfa"])
    if not pfas:
        raise ConfigError("pfa must hold at least one false-alarm probability per pixel in (0, 1)")
    run["pfa"] = tuple(check_prob(f"pfa[{i}] (false-alarm probability per pixel)", v, error=ConfigError)
                       for i, v in enumerate(pfas))
    noise_pixels = (run["trials"] * run["size"] ** 2
                    * ((run["frames"] - run["segment_frames"]) // run["segment_stride"] + 1))
    for i, v in enumerate(run["pfa"]):
        if int(v * noise_pixels) < 1:
            raise ConfigError(f"pfa[{i}]={v:g} needs at least {math.ceil(1 / v - 1e-9)} noise-only "
                              f"pixels, {run['trials']} trials give {noise_pixels}; raise trials or pfa")
    if not isinstance(run["tie_rule"], str) or run["tie_rule"] not in TIE_RULES:
        raise ConfigError(f"tie_rule must be one of {TIE_RULES}, got {run['tie_rule']!r}")
    try:
        DPConfig(width=run["size"], height=run["size"], segment_frames=run["segment_frames"],
                 segment_stride=run["segment_stride"], radius=run["radius"])
    except ConfigError as exc:
        raise ConfigError(f"run parameters: {exc}") from None

    fixed: list[FixedSpec] = []
    for i, entry in enumerate(as_list("config", configs)):
        fixed.append(make_fixed(entry, run, f"config[{i}]", in_sweep=False, explicit=True))
    sweeps = sweep if isinstance(sweep, (list, tuple)) else [sweep]
    for entry in (e for sw in sweeps for e in sweep_entries(sw, run)):
        where = "sweep point " + ", ".join(f"{k}={v}" for k, v in entry.items())
        spec = make_fixed(entry, run, where, in_sweep=True, explicit=False)
        same = [j for j, f in enumerate(fixed) if f.cfg == spec.cfg and f.adc_gain == spec.adc_gain
                and f.adc_offset == spec.adc_offset]
        if same:
            fixed[same[0]] = dataclasses.replace(fixed[same[0]], in_sweep=True)
        else:
            fixed.append(spec)
    if not fixed:
        raise ConfigError("nothing to compare: no [[config]] and an empty sweep")
    names = [f.name for f in fixed]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ConfigError(f"configuration names must be unique, repeated: {dup}")
    return CompareSpec(configs=tuple(fixed), **run)
