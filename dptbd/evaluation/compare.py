"""Fixed point against float: Monte Carlo detection performance on the same seeded scenes.

``dptbd compare`` (``docs/compare.md``) asks what a fixed-point configuration (ADC width
B_in, accumulator B_E, weight fraction F, rounding, weight LUT) costs in detection, against
the float64 model with the same (real-valued) LUT. This module runs the Monte Carlo and
reduces it to statistics; :mod:`dptbd.evaluation.snr_loss` holds the loss arithmetic,
:mod:`dptbd.evaluation.sweep` the bit-width sweep and hardware cost, and
:mod:`dptbd.evaluation.compare_report` the tables and figures.

The scene (paper 001 §4, scaled down by default)
    Gaussian noise of mean ``mu`` and standard deviation ``sigma`` (001's Table 1: 30 and
    sqrt(3) grey levels) and one point target of amplitude ``SNR * sigma``
    (:func:`dptbd.scenes.synthetic.table1_scenario`, trajectory centred in the frame). Trial
    ``i``'s noise depends only on ``(seed, i)`` and is the same at every SNR (common
    random numbers: the Pd curves are smooth and the SNR points are paired), and the same
    noise without the target is trial ``i``'s noise-only scene.

What each model sees
    The **float model** (:func:`dptbd.model.fast_float.run_float_fast`, bit-identical to
    ``run_float``) sees the float sensor output. A **fixed configuration**
    (:func:`dptbd.model.fast.run_fixed_fast`, bit-identical to ``run_fixed``) sees the
    same frames through its ADC: ``code = clip(rint(gain * x + offset), 0, 2**B_in - 1)``
    (:func:`dptbd.scenes.synthetic.quantise`) with, unless the configuration sets
    ``adc_gain`` / ``adc_offset``, the mapping of :func:`adc_mapping`: a fixed analogue
    window ``[mu - 6 sigma, mu + 10 sigma]`` spread over the 2**B_in codes, so one sigma is
    ``2**B_in / 16`` LSB (0.5 LSB at 3 bits, 1 at 4, 4 at 6, 16 at 8). Each extra bit
    halves the LSB, as in a real ADC whose full scale is fixed by the sensor.

Measured per detector, on the same scenes
    * first-level Pd at each SNR at a constant false-alarm count: exactly n candidates per
      accumulated image (n = ``false_alarm_rate`` of the pixels,
      :func:`dptbd.model.segmentation.count_for_rate`), the n largest E with ties at the
      n-th largest broken by a pseudo-random priority per (seed, trial, segment, pixel),
      the same for every detector (:func:`candidate_indices`), so every detector — however
      coarse its E — runs at the same number of candidates;
      a candidate within one pixel of the target's true pixel in the segment's last frame
      is a detection (:mod:`dptbd.evaluation.metrics`), the others are false points;
    * the false-alarm probability per pixel against a threshold, on the noise-only scenes.
      Thresholds are in noise units of a K-frame path, ``z = (E - K mu) / (sqrt(K) sigma)``;
      a fixed configuration's E is mapped back through its ADC,
      ``E_float = (E_fixed - K offset) / gain``;
    * agreement with the float model (same LUT): per accumulated image, the number of
      identical candidate points (row, column and direction d) over the larger of the two
      candidate counts, and whether the two candidate lists are identical.

All counts are kept per trial, so that every interval can be clustered by trial
(:func:`dptbd.evaluation.snr_loss.clustered_wilson`) and the SNR loss bootstrapped over trials
(:func:`dptbd.evaluation.snr_loss.bootstrap_losses`). Trials run in chunks on worker processes;
a trial's numbers depend only on the seed and its index, never on the chunking or the
number of workers.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import multiprocessing
import os
import time
import warnings
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any, Mapping, Sequence

import numpy as np
from numba import njit

from dptbd.config import ConfigError, DPConfig, EnergyWidthWarning, move_offsets, paper_weights, plain_weights
from dptbd.scenes import synthetic as scenes
from dptbd.evaluation.metrics import near_mask
from dptbd.model.segmentation import count_for_rate

__all__ = [
    "LUTS", "cosine_weights", "lut_weights", "adc_mapping", "FixedSpec", "CompareSpec",
    "DEFAULT_RUN", "DEFAULT_CONFIGS", "DEFAULT_SWEEP", "build_spec", "Plan", "make_plan",
    "measure_frames", "CompareResult", "run_compare", "default_workers", "candidate_indices",
    "nth_largest", "image_keys", "check_rtl",
]

#: Built-in weight LUTs (a configuration may instead give ``weights`` as a table).
LUTS = ("paper", "plain", "cosine")

#: Run-level parameters (flat keys of the TOML file) and their defaults. The default run
#: takes about a minute on 2 cores (``docs/compare.md``).
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
}

#: The configurations compared by default besides the sweep: the gateware's defaults, and
#: B_E two bits below the worst case (where the default ADC's noise floor saturates it).
DEFAULT_CONFIGS: tuple[dict, ...] = (
    {"name": "gateware default 8/16/8", "input_bits": 8, "energy_bits": 16, "weight_frac_bits": 8,
     "rounding": "truncate", "lut": "paper"},
    {"name": "saturating 8/9/8", "input_bits": 8, "energy_bits": 9, "weight_frac_bits": 8,
     "rounding": "truncate", "lut": "paper"},
)

#: The default bit-width sweep: every combination of these axes (``docs/compare.md``).
DEFAULT_SWEEP: dict[str, Any] = {
    "input_bits": [3, 4, 5, 6, 7, 8, 10, 12],
    "energy_headroom": [0, -1],
    "weight_frac_bits": [0],
    "rounding": ["truncate"],
    "lut": ["paper"],
}

_CONFIG_KEYS = ("name", "lut", "adc_gain", "adc_offset", "input_bits", "energy_bits",
                "weight_frac_bits", "rounding", "weights")
_RUN_LEVEL_DP_KEYS = ("width", "height", "segment_frames", "segment_stride", "radius")
_SWEEP_KEYS = ("input_bits", "energy_bits", "energy_headroom", "weight_frac_bits", "rounding", "lut")


# ==== weight LUTs and the ADC ===========================================================

def cosine_weights(radius: int = 1) -> np.ndarray:
    """A soft direction LUT: ``w = (1 + cos theta) / 2`` for the turning angle theta.

    1 straight on, 0.854 at 45 deg, 0.5 at 90 deg, 0.146 at 135 deg, 0 for a reversal; a
    zero move and a ``START`` predecessor get 1 (as in the paper's LUT, ``paper_weights``).
    Not exact for any F, so it exercises the weight quantisation and the rounding mode,
    which the paper's 0/1 LUT (exact for every F >= 0) cannot.
    """
    moves = move_offsets(radius).astype(np.float64)
    n_moves = len(moves)
    norms = np.linalg.norm(moves, axis=1)
    lut = np.ones((n_moves + 1, n_moves))
    for p in range(n_moves):
        for m in range(n_moves):
            if norms[p] > 0 and norms[m] > 0:
                cos = moves[p] @ moves[m] / (norms[p] * norms[m])
                lut[p, m] = min(1.0, max(0.0, (1.0 + cos) / 2.0))
    return lut


def lut_weights(name: str, radius: int) -> np.ndarray:
    """The built-in LUT ``name`` (:data:`LUTS`) for ``radius``."""
    if name == "paper":
        return paper_weights(radius)
    if name == "plain":
        return plain_weights(radius)
    if name == "cosine":
        return cosine_weights(radius)
    raise ConfigError(f"lut must be one of {LUTS} (or give 'weights' as a table), got {name!r}")


def adc_mapping(input_bits: int, mu: float, sigma: float, *, low_sigma: float = 6.0,
                span_sigma: float = 16.0) -> tuple[float, float]:
    """``(gain, offset)`` of the default ADC for B_in bits.

    The analogue window ``[mu - low_sigma * sigma, mu - low_sigma * sigma + span_sigma * sigma]``
    (default ``[mu - 6 sigma, mu + 10 sigma]``) is spread over the ``2**B_in`` codes:
    ``gain = 2**B_in / (span_sigma * sigma)`` codes per grey level, ``offset`` such that the
    window's bottom is code 0. One sigma is ``2**B_in / span_sigma`` LSB. Noise below the
    window (6 sigma: 1e-9 of the pixels) clips at 0; the window's top leaves 10 sigma for
    noise plus target (SNR up to ~6).
    """
    gain = float(1 << input_bits) / (span_sigma * sigma)
    offset = -gain * (mu - low_sigma * sigma)
    return gain, offset


# ==== the specification of a run ========================================================

@dataclasses.dataclass(frozen=True)
class FixedSpec:
    """One fixed-point configuration: the DP parameters, its LUT's name and its ADC."""

    name: str
    cfg: DPConfig
    lut: str
    adc_gain: float
    adc_offset: float
    in_sweep: bool = False
    explicit: bool = True
    saturates: bool = False  # B_E below the worst-case width (EnergyWidthWarning)

    @property
    def widths(self) -> str:
        """``"B_in/B_E/F"``."""
        c = self.cfg
        return f"{c.input_bits}/{c.energy_bits}/{c.weight_frac_bits}"

    def behaviour_key(self) -> tuple:
        """Two configurations with the same key produce the same bits on every scene.

        The ADC; the LUT's codes, and F and the rounding unless every code is 0 or 2**F
        (then a weighted candidate is exactly E or 0 in either mode, ``dptbd.model.fast``);
        B_E, or "no saturation" when K full-scale pixels fit (E then never reaches E_max).
        """
        c = self.cfg
        codes = c.weight_codes
        binary = bool(np.all((codes == 0) | (codes == 1 << c.weight_frac_bits)))
        weights = (("binary", (codes != 0).tobytes()) if binary
                   else ("codes", codes.tobytes(), c.weight_frac_bits, c.rounding))
        energy = "no-saturation" if c.energy_bits >= c.energy_bits_needed else c.energy_bits
        return (c.input_bits, self.adc_gain, self.adc_offset, energy, weights)

    def float_key(self) -> tuple:
        """The float model this configuration is compared with: same real-valued LUT."""
        return tuple(self.cfg.weights)

    def to_dict(self) -> dict:
        c = self.cfg
        return {"name": self.name, "input_bits": c.input_bits, "energy_bits": c.energy_bits,
                "weight_frac_bits": c.weight_frac_bits, "rounding": c.rounding, "lut": self.lut,
                "adc_gain": self.adc_gain, "adc_offset": self.adc_offset,
                "energy_bits_needed": c.energy_bits_needed, "saturates": self.saturates,
                "weights_exact": c.weights_exact, "in_sweep": self.in_sweep,
                "explicit": self.explicit}


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
    configs: tuple[FixedSpec, ...]

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
        """The run-level parameters as plain values (for JSON)."""
        out = {}
        for f in dataclasses.fields(self):
            if f.name == "configs":
                continue
            v = getattr(self, f.name)
            out[f.name] = list(v) if isinstance(v, tuple) else v
        return out


def _fail(msg: str) -> None:
    raise ConfigError(msg)


def _as_int(name: str, v: Any, lo: int, hi: int | None = None) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
        _fail(f"{name} must be an integer, got {v!r}")
    if v < lo or (hi is not None and v > hi):
        _fail(f"{name} must be in [{lo}, {'inf' if hi is None else hi}], got {v}")
    return int(v)


def _as_float(name: str, v: Any, *, positive: bool = False, lo: float | None = None,
              hi: float | None = None, open_lo: bool = False, open_hi: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        _fail(f"{name} must be a number, got {v!r}")
    x = float(v)
    if not math.isfinite(x):
        _fail(f"{name} must be finite, got {v!r}")
    if positive and x <= 0:
        _fail(f"{name} must be > 0, got {v!r}")
    if lo is not None and (x < lo or (open_lo and x == lo)):
        _fail(f"{name} must be {'>' if open_lo else '>='} {lo}, got {v!r}")
    if hi is not None and (x > hi or (open_hi and x == hi)):
        _fail(f"{name} must be {'<' if open_hi else '<='} {hi}, got {v!r}")
    return x


def _as_list(name: str, v: Any) -> list:
    if isinstance(v, (str, bytes)) or not hasattr(v, "__iter__"):
        _fail(f"{name} must be a list, got {v!r}")
    return list(v)


def _increasing(name: str, v: Any, *, min_len: int = 1, positive: bool = False) -> tuple:
    vals = _as_list(name, v)
    if len(vals) < min_len:
        _fail(f"{name} must hold at least {min_len} value(s), got {vals!r}"
              + (" (an empty list)" if not vals else ""))
    out = tuple(_as_float(f"{name}[{i}]", x, positive=positive) for i, x in enumerate(vals))
    bad = [i for i in range(1, len(out)) if out[i] <= out[i - 1]]
    if bad:
        i = bad[0]
        _fail(f"{name} must be strictly increasing, but {name}[{i}] = {out[i]:g} <= "
              f"{name}[{i - 1}] = {out[i - 1]:g}")
    return out


def _make_fixed(entry: Mapping[str, Any], run: dict, where: str, *, in_sweep: bool,
                explicit: bool) -> FixedSpec:
    """A :class:`FixedSpec` from a ``[[config]]`` table (or a sweep point)."""
    if not isinstance(entry, Mapping):
        _fail(f"{where} must be a table of parameters, got {entry!r}")
    entry = dict(entry)
    misplaced = sorted(set(entry) & set(_RUN_LEVEL_DP_KEYS))
    if misplaced:
        _fail(f"{where}: {misplaced} are run-level parameters (every configuration runs on the "
              f"same scenes); set them at the top level of the file")
    unknown = sorted(set(entry) - set(_CONFIG_KEYS))
    if unknown:
        _fail(f"{where}: unknown configuration key(s) {unknown}; allowed: {sorted(_CONFIG_KEYS)}")
    radius = run["radius"]
    if "weights" in entry and "lut" in entry:
        _fail(f"{where}: give either 'lut' (one of {LUTS}) or 'weights' (a table), not both")
    lut = entry.pop("lut", "paper")
    if "weights" in entry:
        lut = "custom"
    else:
        if not isinstance(lut, str):
            _fail(f"{where}: lut must be one of {LUTS}, got {lut!r}")
        entry["weights"] = lut_weights(lut, radius)
    name = entry.pop("name", None)
    gain = entry.pop("adc_gain", None)
    offset = entry.pop("adc_offset", None)
    bits = entry.get("input_bits", 8)
    energy = entry.pop("energy_bits", "needed")
    params = dict(entry, width=run["size"], height=run["size"], segment_frames=run["segment_frames"],
                  segment_stride=run["segment_stride"], radius=radius)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", EnergyWidthWarning)
            probe = DPConfig.from_mapping(params)  # validates input_bits etc.
            if energy == "needed":
                energy = probe.energy_bits_needed
            elif isinstance(energy, str):
                _fail(f"energy_bits must be an integer or \"needed\", got {energy!r}")
            cfg = DPConfig.from_mapping(dict(params, energy_bits=energy))
    except ConfigError as exc:
        raise ConfigError(f"{where}: {exc}") from None
    bits = cfg.input_bits
    d_gain, d_offset = adc_mapping(bits, run["mu"], run["sigma"], low_sigma=run["adc_low_sigma"],
                                   span_sigma=run["adc_span_sigma"])
    gain = d_gain if gain is None else _as_float(f"{where}: adc_gain", gain, positive=True)
    offset = d_offset if offset is None else _as_float(f"{where}: adc_offset", offset)
    if name is None:
        name = f"{bits}/{cfg.energy_bits}/{cfg.weight_frac_bits} {cfg.rounding} {lut}"
    elif not isinstance(name, str) or not name.strip():
        _fail(f"{where}: name must be a non-empty string, got {name!r}")
    return FixedSpec(name=name, cfg=cfg, lut=lut, adc_gain=gain, adc_offset=offset,
                     in_sweep=in_sweep, explicit=explicit,
                     saturates=cfg.energy_bits < cfg.energy_bits_needed)


def _sweep_entries(sweep: Mapping[str, Any], run: dict) -> list[dict]:
    """The grid of a ``[sweep]`` table as ``[[config]]``-like entries."""
    if not isinstance(sweep, Mapping):
        _fail(f"sweep must be a table (or a list of tables), got {sweep!r}")
    if not sweep:
        return []
    unknown = sorted(set(sweep) - set(_SWEEP_KEYS))
    if unknown:
        _fail(f"sweep: unknown key(s) {unknown}; allowed: {sorted(_SWEEP_KEYS)}")
    if "energy_bits" in sweep and "energy_headroom" in sweep:
        _fail("sweep: give either energy_bits (absolute widths) or energy_headroom "
              "(B_E minus the worst-case width), not both")
    axes = {}
    for key in _SWEEP_KEYS:
        if key in sweep:
            vals = _as_list(f"sweep.{key}", sweep[key])
            if not vals:
                _fail(f"sweep.{key} must not be empty")
            axes[key] = vals
    axes.setdefault("input_bits", [8])
    if "energy_bits" not in axes:
        axes.setdefault("energy_headroom", [0])
    entries = []
    names = list(axes)
    for combo in itertools.product(*(axes[k] for k in names)):
        point = dict(zip(names, combo))
        head = point.pop("energy_headroom", None)
        if head is not None:
            head = _as_int("sweep.energy_headroom", head, -32, 32)
            bits = _as_int("sweep.input_bits", point["input_bits"], 1, 16)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", EnergyWidthWarning)
                needed = DPConfig(width=run["size"], height=run["size"], input_bits=bits,
                                  energy_bits=32, segment_frames=run["segment_frames"],
                                  segment_stride=run["segment_stride"],
                                  radius=run["radius"]).energy_bits_needed
            point["energy_bits"] = needed + head
        entries.append(point)
    return entries


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
    dptbd.config.ConfigError
        Unknown keys (by name), impossible widths, an empty or non-increasing SNR list,
        ``trials`` < 1, …
    """
    mapping = dict(mapping or {})
    configs = mapping.pop("config", list(DEFAULT_CONFIGS))
    sweep = mapping.pop("sweep", DEFAULT_SWEEP)
    unknown = sorted(set(mapping) - set(DEFAULT_RUN))
    if unknown:
        _fail(f"unknown parameter(s) {unknown}; allowed: {sorted(DEFAULT_RUN) + ['config', 'sweep']}")
    bad_over = sorted(set(overrides) - set(DEFAULT_RUN))
    if bad_over:
        _fail(f"unknown parameter(s) {bad_over}")
    run = dict(DEFAULT_RUN)
    run.update(mapping)
    run.update({k: v for k, v in overrides.items() if v is not None})

    run["trials"] = _as_int("trials", run["trials"], 1)
    run["seed"] = _as_int("seed", run["seed"], 0)
    run["snr"] = _increasing("snr", run["snr"], min_len=2, positive=True)
    run["size"] = _as_int("size", run["size"], 3, 4096)
    run["frames"] = _as_int("frames", run["frames"], 1, 100000)
    vel = _as_list("velocity", run["velocity"])
    if len(vel) != 2:
        _fail(f"velocity must be a (row, col) pair, got {run['velocity']!r}")
    run["velocity"] = tuple(_as_float(f"velocity[{i}]", v) for i, v in enumerate(vel))
    run["mu"] = _as_float("mu", run["mu"])
    run["sigma"] = _as_float("sigma", run["sigma"], positive=True)
    run["segment_frames"] = _as_int("segment_frames", run["segment_frames"], 1, 65535)
    if run["segment_stride"] is not None:
        run["segment_stride"] = _as_int("segment_stride", run["segment_stride"], 1,
                                        run["segment_frames"])
    else:
        run["segment_stride"] = run["segment_frames"]
    run["radius"] = _as_int("radius", run["radius"], 1, 2)
    if run["frames"] < run["segment_frames"]:
        _fail(f"frames={run['frames']} is shorter than one segment "
              f"(segment_frames={run['segment_frames']})")
    run["false_alarm_rate"] = _as_float("false_alarm_rate", run["false_alarm_rate"], lo=0.0,
                                        hi=1.0, open_lo=True, open_hi=True)
    if count_for_rate(run["false_alarm_rate"], run["size"] ** 2) < 1:
        _fail(f"false_alarm_rate={run['false_alarm_rate']} keeps no candidate in a "
              f"{run['size']}x{run['size']} image")
    run["thresholds"] = _increasing("thresholds", run["thresholds"])
    levels = _as_list("pd_levels", run["pd_levels"])
    if not levels:
        _fail("pd_levels must not be empty")
    run["pd_levels"] = tuple(_as_float(f"pd_levels[{i}]", v, lo=0.0, hi=1.0, open_lo=True,
                                       open_hi=True) for i, v in enumerate(levels))
    run["tolerance_db"] = _as_float("tolerance_db", run["tolerance_db"], lo=0.0)
    run["bootstrap"] = _as_int("bootstrap", run["bootstrap"], 0, 10**6)
    run["chunk"] = _as_int("chunk", run["chunk"], 1)
    run["adc_low_sigma"] = _as_float("adc_low_sigma", run["adc_low_sigma"])
    run["adc_span_sigma"] = _as_float("adc_span_sigma", run["adc_span_sigma"], positive=True)
    try:
        DPConfig(width=run["size"], height=run["size"], segment_frames=run["segment_frames"],
                 segment_stride=run["segment_stride"], radius=run["radius"])
    except ConfigError as exc:
        raise ConfigError(f"run parameters: {exc}") from None

    fixed: list[FixedSpec] = []
    for i, entry in enumerate(_as_list("config", configs)):
        fixed.append(_make_fixed(entry, run, f"config[{i}]", in_sweep=False, explicit=True))
    sweeps = sweep if isinstance(sweep, (list, tuple)) else [sweep]
    for entry in (e for sw in sweeps for e in _sweep_entries(sw, run)):
        where = "sweep point " + ", ".join(f"{k}={v}" for k, v in entry.items())
        spec = _make_fixed(entry, run, where, in_sweep=True, explicit=False)
        same = [j for j, f in enumerate(fixed) if f.cfg == spec.cfg and f.adc_gain == spec.adc_gain
                and f.adc_offset == spec.adc_offset]
        if same:
            fixed[same[0]] = dataclasses.replace(fixed[same[0]], in_sweep=True)
        else:
            fixed.append(spec)
    if not fixed:
        _fail("nothing to compare: no [[config]] and an empty sweep")
    names = [f.name for f in fixed]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        _fail(f"configuration names must be unique, repeated: {dup}")
    return CompareSpec(configs=tuple(fixed), **run)


# ==== the plan a worker runs ============================================================

@dataclasses.dataclass(frozen=True)
class Plan:
    """What a worker needs: the detectors, the ADCs, the target's truth. Picklable.

    Detectors ``0 .. len(floats) - 1`` are the float models (one per distinct LUT),
    then the fixed behaviours (configurations that compute identical bits share one).
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
    rtl: tuple = ()                   # RTL in the loop: dptbd.sim.rtl_trials.RTLBuilds per
    #                                   fixed behaviour (empty: the golden model)

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
        key = f.behaviour_key()
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
                levels=np.array(levels))


# ==== one chunk of trials ===============================================================

# ---- the candidate rule: exactly n per image, ties at the n-th largest broken at random --
#
# Every pixel with E above the image's n-th largest value is a candidate; the pixels AT that
# value fill the list up to n in the order of a pseudo-random priority per pixel,
# splitmix64 of (seed, trial, segment, pixel). The priority depends on the scene, never on
# the detector, so every detector breaks its ties with the same priorities on the same scene
# (paired), and it is uniform over the frame, so a tied target is kept with the same chance
# wherever it is (a raster-order tie-break keeps tied pixels near the top of the frame:
# docs/compare.md measures the bias). Reproducible: no generator state, only the indices.

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)


@njit(cache=True)
def _mix(z):
    """splitmix64's finaliser (uint64 -> uint64, a bijection)."""
    z = (z ^ (z >> np.uint64(30))) * _M1
    z = (z ^ (z >> np.uint64(27))) * _M2
    return z ^ (z >> np.uint64(31))


def _mix_np(z):
    """:func:`_mix` in numpy (uint64 scalars or arrays; wraps like the kernel)."""
    z = np.asarray(z, dtype=np.uint64)
    with np.errstate(over="ignore"):
        z = (z ^ (z >> np.uint64(30))) * _M1
        z = (z ^ (z >> np.uint64(27))) * _M2
        return z ^ (z >> np.uint64(31))


def image_keys(seed: int, first_trial: int, n_trials: int, n_seg: int) -> np.ndarray:
    """``(n_trials * n_seg,)`` uint64 tie-break keys of the images of trials
    ``first_trial ..`` (image ``i``: trial ``first_trial + i // n_seg``, segment
    ``i % n_seg``), the same for every detector and every SNR of a trial."""
    trial = np.repeat(np.arange(first_trial, first_trial + n_trials, dtype=np.uint64), n_seg)
    seg = np.tile(np.arange(n_seg, dtype=np.uint64), n_trials)
    with np.errstate(over="ignore"):
        base = _mix_np(np.uint64(seed) + _GOLDEN)
        return _mix_np(_mix_np(base ^ _mix_np(trial + _GOLDEN)) ^ seg)


@njit(cache=True)
def _select(energy, level, keys, near, n_seg, count, idx, n_cand, hit, near_count):
    """Exactly ``min(count, H*W)`` candidates of each image (raster order) and how many lie
    in the detection gate.

    ``energy``: ``(images, H*W)``; image ``i`` is segment ``i % n_seg``; ``level[i]`` its
    ``count``-th largest value (``-inf`` when ``count >= H*W``); ``keys[i]`` its tie-break
    key (:func:`image_keys`). Every pixel with E > level is a candidate; of the pixels with
    E == level, the ``count - #(E > level)`` with the smallest priority
    ``_mix(keys[i] ^ (p * golden))`` (then the lowest index) are too
    (:func:`candidate_indices` is the same rule in numpy).
    """
    n_pix = energy.shape[1]
    prio = np.empty(n_pix, np.uint64)
    for i in range(energy.shape[0]):
        s = i % n_seg
        lv = level[i]
        above = 0
        tied = 0
        for p in range(n_pix):
            e = energy[i, p]
            if e > lv:
                above += 1
            elif e == lv:
                prio[tied] = _mix(keys[i] ^ (np.uint64(p) * _GOLDEN))
                tied += 1
        slots = count - above  # tied pixels to take
        if slots > tied:
            slots = tied
        cut = np.uint64(0)
        if 0 < slots < tied:
            cut = np.sort(prio[:tied])[slots - 1]  # the slots-th smallest priority
        k = 0
        inside = 0
        j = 0  # tied pixels seen: prio[j] is this one's priority (same order as above)
        for p in range(n_pix):
            e = energy[i, p]
            take = e > lv
            if not take and e == lv and slots > 0:
                if slots == tied - j:
                    take = True
                else:
                    take = prio[j] <= cut
                if take:
                    slots -= 1
                j += 1
            if take:
                idx[i, k] = p
                k += 1
                if near[s, p]:
                    inside += 1
        n_cand[i] = k
        near_count[i] = inside
        hit[i] = inside > 0


def nth_largest(flat: np.ndarray, count: int) -> np.ndarray:
    """The ``count``-th largest value of each row of ``flat`` ``(images, pixels)``, with
    multiplicity, as float64 (``-inf`` when ``count >= pixels``, ``+inf`` when 0)."""
    n_pix = flat.shape[-1]
    if count >= n_pix:
        return np.full(flat.shape[:-1], -np.inf)
    if count <= 0:
        return np.full(flat.shape[:-1], np.inf)
    kth = n_pix - count  # ascending position of the count-th largest
    return np.partition(flat, kth, axis=-1)[..., kth].astype(np.float64)


def candidate_indices(image: np.ndarray, count: int, key: int) -> np.ndarray:
    """The compare rule, written plainly: the raster indices (ascending) of exactly
    ``min(count, H*W)`` candidates of ONE image — the first ``count`` pixels sorted by
    descending E, then ascending tie-break priority ``_mix(key ^ (p * golden))``, then
    index. ``key``: the image's entry of :func:`image_keys`. The reference of the numba
    kernel :func:`_select` (``docs/compare.md``)."""
    flat = np.asarray(image).reshape(-1)
    pix = np.arange(flat.size, dtype=np.uint64)
    with np.errstate(over="ignore"):
        prio = _mix_np(np.uint64(key) ^ (pix * _GOLDEN))
    order = np.lexsort((np.arange(flat.size), prio, -flat.astype(np.float64)))
    return np.sort(order[:max(0, min(count, flat.size))])


@njit(cache=True)
def _same_points(idx_a, n_a, dir_a, idx_b, n_b, dir_b, out):
    """Per image: candidates at the same pixel with the same direction in both lists."""
    for i in range(idx_a.shape[0]):
        ja = 0
        jb = 0
        same = 0
        while ja < n_a[i] and jb < n_b[i]:
            pa = idx_a[i, ja]
            pb = idx_b[i, jb]
            if pa == pb:
                if dir_a[i, pa] == dir_b[i, pb]:
                    same += 1
                ja += 1
                jb += 1
            elif pa < pb:
                ja += 1
            else:
                jb += 1
        out[i] = same


@dataclasses.dataclass
class _Candidates:
    """The candidate lists of one detector on one batch, flattened to (images, …)."""

    idx: np.ndarray        # (images, count) raster index, first n_cand valid
    n_cand: np.ndarray     # (images,)
    hit: np.ndarray        # (images,) a candidate in the gate
    near_count: np.ndarray  # (images,) candidates in the gate
    direction: np.ndarray  # (images, H*W)


def _candidates(energy: np.ndarray, direction: np.ndarray, plan: "Plan",
                keys: np.ndarray) -> _Candidates:
    """Exactly n candidates per image (:func:`_select`); ``keys``: :func:`image_keys`."""
    count = plan.spec.candidate_count
    n_seg = len(plan.ends)
    flat = energy.reshape(-1, energy.shape[-1] * energy.shape[-2])
    level = nth_largest(flat, count)
    images = flat.shape[0]
    idx = np.zeros((images, max(count, 1)), np.int64)
    n_cand = np.zeros(images, np.int64)
    hit = np.zeros(images, np.bool_)
    near_count = np.zeros(images, np.int64)
    _select(flat, level, keys, plan.near_flat, n_seg, count, idx, n_cand, hit,
            near_count)
    return _Candidates(idx, n_cand, hit, near_count, direction.reshape(images, -1))


def _exceedances(energy: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """Per trial: pixels (over all segments) with E strictly above each level."""
    flat = np.sort(energy.reshape(energy.shape[0], -1), axis=1)
    n = flat.shape[1]
    return np.stack([n - np.searchsorted(row, levels, side="right") for row in flat])


def _evaluate(plan: Plan, float_frames: np.ndarray, codes: Sequence[np.ndarray],
              with_target: bool, out: dict, kind: int, first: int) -> None:
    """Run every detector on one batch (one SNR, or noise only) of trials ``first ..`` and
    store per-trial counts."""
    from dptbd.model.fast import run_fixed_fast
    from dptbd.model.fast_float import run_float_fast

    n_trials = float_frames.shape[0]
    n_seg = len(plan.ends)
    keys = image_keys(plan.spec.seed, first, n_trials, n_seg)
    refs = []
    for i, cfg in enumerate(plan.floats):
        res = run_float_fast(float_frames, cfg)
        cand = _candidates(res.energy, res.direction, plan, keys)
        refs.append(cand)
        _store(out, kind, i, cand, None, with_target, n_trials, n_seg)
        if not with_target:
            out["exceed"][:, i] = _exceedances(res.energy, plan.levels[i])
    for b, cfg in enumerate(plan.fixed):
        d = len(plan.floats) + b
        if plan.rtl:  # the gateware accumulates, every word checked (docs/compare.md)
            from dptbd.sim.rtl_trials import accumulate_trials
            scene = (f"SNR {plan.spec.snr[kind]:g}" if with_target else "noise only")
            res = accumulate_trials(
                plan.rtl[b], codes[plan.fixed_adc[b]], first_trial=first,
                label=f"configuration {plan.detector_names()[d]!r}, scene {scene}: ")
            out["rtl"] = out["rtl"] + res.tally
        else:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", EnergyWidthWarning)
                res = run_fixed_fast(codes[plan.fixed_adc[b]], cfg, threads=1)
        cand = _candidates(res.energy, res.direction, plan, keys)
        _store(out, kind, d, cand, refs[plan.fixed_float[b]], with_target, n_trials, n_seg)
        if not with_target:
            out["exceed"][:, d] = _exceedances(res.energy, plan.levels[d])


def _store(out, kind, d, cand: _Candidates, ref: _Candidates | None, with_target, n_trials, n_seg):
    per = (n_trials, n_seg)
    n_cand = cand.n_cand.reshape(per)
    out["candidates"][:, d, kind] = n_cand.sum(axis=1)
    if with_target:
        out["detections"][:, d, kind] = cand.hit.reshape(per).sum(axis=1)
        out["false_points"][:, d, kind] = (cand.n_cand - cand.near_count).reshape(per).sum(axis=1)
    else:
        out["false_points"][:, d, kind] = n_cand.sum(axis=1)
    if ref is None:  # a float model against itself
        out["agree_frac"][:, d, kind] = n_seg
        out["agree_same"][:, d, kind] = n_seg
        return
    same = np.zeros(len(cand.n_cand), np.int64)
    _same_points(cand.idx, cand.n_cand, cand.direction, ref.idx, ref.n_cand, ref.direction, same)
    larger = np.maximum(cand.n_cand, ref.n_cand)
    frac = np.where(larger == 0, 1.0, same / np.maximum(larger, 1))
    identical = (same == cand.n_cand) & (cand.n_cand == ref.n_cand)
    out["agree_frac"][:, d, kind] = frac.reshape(per).sum(axis=1)
    out["agree_same"][:, d, kind] = identical.reshape(per).sum(axis=1)


def _empty_out(plan: Plan, n: int) -> dict:
    d, s = plan.n_detectors, len(plan.spec.snr)
    out = {
        "detections": np.zeros((n, d, s), np.int64),
        "false_points": np.zeros((n, d, s + 1), np.int64),
        "candidates": np.zeros((n, d, s + 1), np.int64),
        "agree_frac": np.zeros((n, d, s + 1), np.float64),
        "agree_same": np.zeros((n, d, s + 1), np.int64),
        "exceed": np.zeros((n, d, len(plan.spec.thresholds)), np.int64),
    }
    if plan.rtl:  # not per trial: summed over chunks by run_compare, not concatenated
        from dptbd.sim.rtl_trials import RTLTally
        out["rtl"] = RTLTally()
    return out


def _chunk(plan: Plan, first: int, stop: int) -> dict:
    """Trials ``first .. stop - 1``: every SNR and the noise-only scene, every detector.

    The noise is drawn once and the target added per SNR; the ADC codes of the noise are
    computed once per ADC and only the target's pixels re-quantised per SNR. This gives the
    same frames as ``table1_scenario(...).frames`` and ``quantise`` of them
    (``tests/evaluation/test_compare.py`` checks it against :func:`measure_frames`).
    """
    spec = plan.spec
    n = stop - first
    noise = scenes.make_noise((spec.size, spec.size), spec.frames, mu=spec.mu, sigma=spec.sigma,
                              seed=spec.seed, trials=n, first_trial=first, dtype=np.float32)
    out = _empty_out(plan, n)
    t, rows, cols = plan.target_t, plan.target_px[:, 0], plan.target_px[:, 1]
    codes = [scenes.quantise(noise, bits, gain=g, offset=o) for bits, g, o in plan.adcs]
    background = noise[:, t, rows, cols].copy()
    background_codes = [c[:, t, rows, cols].copy() for c in codes]
    for kind, amp in enumerate(plan.amplitudes):
        lit = background + np.float32(amp)  # as make_scene draws a target (float32)
        noise[:, t, rows, cols] = lit
        for (bits, g, o), c in zip(plan.adcs, codes):
            c[:, t, rows, cols] = scenes.quantise(lit, bits, gain=g, offset=o)
        _evaluate(plan, noise, codes, True, out, kind, first)
    noise[:, t, rows, cols] = background
    for c, bc in zip(codes, background_codes):
        c[:, t, rows, cols] = bc
    _evaluate(plan, noise, codes, False, out, len(plan.amplitudes), first)
    return out


def measure_frames(plan: Plan, frames_by_snr: Sequence[np.ndarray], noise_only: np.ndarray,
                   first_trial: int = 0) -> dict:
    """Per-trial counts for given float frames (one batch per SNR, plus the noise-only batch)
    of trials ``first_trial ..`` (the index sets the candidates' tie-break keys).

    The straightforward path (each batch quantised whole): for tests and for scenes that
    are not the built-in one. Same output layout as a chunk of :func:`run_compare`.
    """
    n = noise_only.shape[0]
    out = _empty_out(plan, n)
    for kind, frames in enumerate(list(frames_by_snr) + [noise_only]):
        codes = [scenes.quantise(frames, bits, gain=g, offset=o) for bits, g, o in plan.adcs]
        _evaluate(plan, frames, codes, kind < len(frames_by_snr), out, kind, first_trial)
    return out


# ==== the whole run =====================================================================

@dataclasses.dataclass
class CompareResult:
    """Per-trial counts of every detector (see :func:`_empty_out` for the arrays).

    ``counts[name]`` has the trial axis first, trials in index order. ``rtl``: with
    ``run_compare(..., rtl=True)``, what went through the gateware and was checked
    (:func:`dptbd.sim.rtl_trials.summary`), else None.
    """

    plan: Plan
    counts: dict
    seconds: float
    workers: int
    rtl: dict | None = None

    @property
    def spec(self) -> CompareSpec:
        return self.plan.spec

    @property
    def segments(self) -> int:
        return len(self.plan.ends)

    @property
    def opportunities(self) -> np.ndarray:
        """``(n_snr, trials)``: (segment, target) pairs per trial at each SNR."""
        n = self.spec.trials
        return np.full((len(self.spec.snr), n), int(self.plan.visible.sum()), dtype=np.int64)

    @property
    def trials_per_second(self) -> float:
        return self.spec.trials / self.seconds if self.seconds > 0 else math.nan


def default_workers() -> int:
    """The machine's cores available to this process."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def _warm(plan: Plan) -> None:
    """Compile (or load from numba's cache) every kernel on a tiny batch."""
    spec = plan.spec
    frames = np.full((1, spec.frames, spec.size, spec.size), spec.mu, dtype=np.float32)
    _evaluate(plan, frames, [scenes.quantise(frames, b, gain=g, offset=o) for b, g, o in plan.adcs],
              False, _empty_out(plan, 1), len(spec.snr), 0)


def _worker_init() -> None:
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
        os.environ.setdefault(var, "1")


def check_rtl(spec: CompareSpec) -> None:
    """Refuse (``ConfigError`` naming it) a configuration the gateware cannot run."""
    from dptbd.sim.rtl_trials import check_configs

    check_configs((f.name, f.cfg) for f in spec.configs)


def run_compare(spec: CompareSpec, *, workers: int | None = None, progress: bool = False,
                rtl: bool = False) -> CompareResult:
    """Run the Monte Carlo: ``spec.trials`` trials in chunks of ``spec.chunk``.

    ``workers``: processes (default: :func:`default_workers`); 1 runs in this process.
    The counts do not depend on ``workers``. ``progress``: a tqdm bar on stderr.
    ``rtl``: the fixed-point configurations' trials are accumulated by the compiled
    gateware (:func:`dptbd.sim.rtl_trials.accumulate_trials`, every output word checked
    against the golden model) instead of :func:`dptbd.model.fast.run_fixed_fast`; the
    float models stay as they are. The counts are the same (``docs/compare.md``, "RTL in
    the loop"). Configurations the gateware does not implement are refused first.
    """
    workers = default_workers() if workers is None else _as_int("workers", workers, 1, 1024)
    if rtl:
        check_rtl(spec)
    plan = make_plan(spec)
    if rtl:  # build (or find in the cache) every executable here, before the fork
        from dptbd.sim.rtl_trials import prepare_builds
        plan = dataclasses.replace(plan, rtl=tuple(prepare_builds(cfg) for cfg in plan.fixed))
    _warm(plan)  # compile (or load) the kernels here, once, before the clock and the fork
    bounds = [(a, min(a + spec.chunk, spec.trials)) for a in range(0, spec.trials, spec.chunk)]
    parts: list[dict | None] = [None] * len(bounds)
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=spec.trials, unit="trial", desc="compare", smoothing=0.1)
    start = time.perf_counter()
    try:
        if workers == 1:
            for i, (a, b) in enumerate(bounds):
                parts[i] = _chunk(plan, a, b)
                if bar is not None:
                    bar.update(b - a)
        else:
            # fork (Linux): workers inherit the imported modules and compiled kernels, so
            # they start in milliseconds; nothing here runs threads that a fork could break
            # (the kernels run with threads=1). Elsewhere: spawn.
            method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
            ctx = multiprocessing.get_context(method)
            with ProcessPoolExecutor(max_workers=min(workers, len(bounds)), mp_context=ctx,
                                     initializer=_worker_init) as pool:
                jobs = {pool.submit(_chunk, plan, a, b): i for i, (a, b) in enumerate(bounds)}
                for job in as_completed(jobs):
                    i = jobs[job]
                    parts[i] = job.result()
                    if bar is not None:
                        bar.update(bounds[i][1] - bounds[i][0])
    finally:
        if bar is not None:
            bar.close()
    seconds = time.perf_counter() - start
    counts = {k: np.concatenate([p[k] for p in parts], axis=0) for k in parts[0] if k != "rtl"}
    rtl_info = None
    if plan.rtl:
        from dptbd.sim.rtl_trials import summary
        tally = parts[0]["rtl"]
        for p in parts[1:]:
            tally = tally + p["rtl"]
        names = plan.detector_names()[len(plan.floats):]
        rtl_info = summary(tally, [(n, b.segmenter_missing) for n, b in zip(names, plan.rtl)])
    return CompareResult(plan=plan, counts=counts, seconds=seconds, workers=workers,
                         rtl=rtl_info)
