"""The specification of a comparison: the fixed configurations and the run, validated from a
TOML file (:func:`build_spec`) before any work. The weight LUTs and the default ADC mapping
it uses are in :mod:`dptbd.evaluation.compare.luts` (re-exported here).

The package docstring (:mod:`dptbd.evaluation.compare`) describes the scene and what is
measured; ``docs/compare.md`` the TOML file.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import warnings
from typing import Any, Mapping

import numpy as np

from dptbd.config import DPConfig, EnergyWidthWarning, non_saturating_energy_bits
from dptbd.errors import ConfigError, check_int, check_prob, check_real, shown
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
                "weight_frac_bits", "rounding", "weights", "histogram_bits", "histogram_shift")
_RUN_LEVEL_DP_KEYS = ("width", "height", "segment_frames", "segment_stride", "radius")
_SWEEP_KEYS = ("input_bits", "energy_bits", "energy_headroom", "weight_frac_bits", "rounding", "lut")


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


# ---- checks of the TOML values: ranges by the one family of :mod:`dptbd.errors` (raising
# ConfigError, "NAME must be an integer in [lo, hi], got VALUE"); lists checked here.

def _checked_int(name: str, v: Any, lo: int, hi: int | None = None) -> int:
    """``v`` as an int in ``[lo, hi]``: :func:`dptbd.errors.check_int` raising
    :class:`~dptbd.errors.ConfigError` (:mod:`~dptbd.evaluation.compare.runner` uses it too)."""
    return check_int(name, v, lo, hi, error=ConfigError)


def _real(name: str, v: Any, *, positive: bool = False) -> float:
    """``v`` as a finite float (``> 0`` if ``positive``): :func:`dptbd.errors.check_real`."""
    if positive:
        return check_real(name, v, 0.0, lo_open=True, error=ConfigError)
    return check_real(name, v, error=ConfigError)


def _as_list(name: str, v: Any) -> list:
    """``v`` as a list (any iterable but a string)."""
    if isinstance(v, (str, bytes)) or not hasattr(v, "__iter__"):
        raise ConfigError(f"{name} must be a list, got {shown(v)}")
    return list(v)


def _increasing_reals(name: str, v: Any, *, min_len: int = 1, positive: bool = False) -> tuple:
    """``v`` as a strictly increasing tuple of at least ``min_len`` finite floats."""
    vals = _as_list(name, v)
    if len(vals) < min_len:
        raise ConfigError(f"{name} must hold at least {min_len} value(s), got {vals!r}"
                          + (" (an empty list)" if not vals else ""))
    out = tuple(_real(f"{name}[{i}]", x, positive=positive) for i, x in enumerate(vals))
    bad = [i for i in range(1, len(out)) if out[i] <= out[i - 1]]
    if bad:
        i = bad[0]
        raise ConfigError(f"{name} must be strictly increasing, but {name}[{i}] = {out[i]:g} <= "
                          f"{name}[{i - 1}] = {out[i - 1]:g}")
    return out


def _make_fixed(entry: Mapping[str, Any], run: dict, where: str, *, in_sweep: bool,
                explicit: bool) -> FixedSpec:
    """A :class:`FixedSpec` from a ``[[config]]`` table (or a sweep point)."""
    if not isinstance(entry, Mapping):
        raise ConfigError(f"{where} must be a table of parameters, got {entry!r}")
    entry = dict(entry)
    misplaced = sorted(set(entry) & set(_RUN_LEVEL_DP_KEYS))
    if misplaced:
        raise ConfigError(f"{where}: {misplaced} are run-level parameters (every configuration "
                          f"runs on the same scenes); set them at the top level of the file")
    unknown = sorted(set(entry) - set(_CONFIG_KEYS))
    if unknown:
        raise ConfigError(f"{where}: unknown configuration key(s) {unknown}; "
                          f"allowed: {sorted(_CONFIG_KEYS)}")
    radius = run["radius"]
    if "weights" in entry and "lut" in entry:
        raise ConfigError(f"{where}: give either 'lut' (one of {LUTS}) or 'weights' (a table), "
                          f"not both")
    lut = entry.pop("lut", "paper")
    if "weights" in entry:
        lut = "custom"
    else:
        if not isinstance(lut, str):
            raise ConfigError(f"{where}: lut must be one of {LUTS}, got {lut!r}")
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
                raise ConfigError(f"energy_bits must be an integer or \"needed\", got {energy!r}")
            cfg = DPConfig.from_mapping(dict(params, energy_bits=energy))
    except ConfigError as exc:
        raise ConfigError(f"{where}: {exc}") from None
    bits = cfg.input_bits
    d_gain, d_offset = adc_mapping(bits, run["mu"], run["sigma"], low_sigma=run["adc_low_sigma"],
                                   span_sigma=run["adc_span_sigma"])
    gain = d_gain if gain is None else _real(f"{where}: adc_gain", gain, positive=True)
    offset = d_offset if offset is None else _real(f"{where}: adc_offset", offset)
    if name is None:
        name = f"{bits}/{cfg.energy_bits}/{cfg.weight_frac_bits} {cfg.rounding} {lut}"
    elif not isinstance(name, str) or not name.strip():
        raise ConfigError(f"{where}: name must be a non-empty string, got {name!r}")
    return FixedSpec(name=name, cfg=cfg, lut=lut, adc_gain=gain, adc_offset=offset,
                     in_sweep=in_sweep, explicit=explicit,
                     saturates=cfg.energy_bits < cfg.energy_bits_needed)


def _sweep_entries(sweep: Mapping[str, Any], run: dict) -> list[dict]:
    """The grid of a ``[sweep]`` table as ``[[config]]``-like entries."""
    if not isinstance(sweep, Mapping):
        raise ConfigError(f"sweep must be a table (or a list of tables), got {sweep!r}")
    if not sweep:
        return []
    unknown = sorted(set(sweep) - set(_SWEEP_KEYS))
    if unknown:
        raise ConfigError(f"sweep: unknown key(s) {unknown}; allowed: {sorted(_SWEEP_KEYS)}")
    if "energy_bits" in sweep and "energy_headroom" in sweep:
        raise ConfigError("sweep: give either energy_bits (absolute widths) or energy_headroom "
                          "(B_E minus the worst-case width), not both")
    axes = {}
    for key in _SWEEP_KEYS:
        if key in sweep:
            vals = _as_list(f"sweep.{key}", sweep[key])
            if not vals:
                raise ConfigError(f"sweep.{key} must not be empty")
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
            head = _checked_int("sweep.energy_headroom", head, -32, 32)
            bits = _checked_int("sweep.input_bits", point["input_bits"], 1, 16)
            point["energy_bits"] = non_saturating_energy_bits(bits, run["segment_frames"]) + head
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

    run["trials"] = _checked_int("trials", run["trials"], 1)
    run["seed"] = _checked_int("seed", run["seed"], 0)
    run["snr"] = _increasing_reals("snr", run["snr"], min_len=2, positive=True)
    run["size"] = _checked_int("size", run["size"], 3, 4096)
    run["frames"] = _checked_int("frames", run["frames"], 1, 100000)
    vel = _as_list("velocity", run["velocity"])
    if len(vel) != 2:
        raise ConfigError(f"velocity must be a (row, col) pair, got {run['velocity']!r}")
    run["velocity"] = tuple(_real(f"velocity[{i}]", v) for i, v in enumerate(vel))
    run["mu"] = _real("mu", run["mu"])
    run["sigma"] = _real("sigma", run["sigma"], positive=True)
    run["segment_frames"] = _checked_int("segment_frames", run["segment_frames"], 1, 65535)
    if run["segment_stride"] is not None:
        run["segment_stride"] = _checked_int("segment_stride", run["segment_stride"], 1,
                                        run["segment_frames"])
    else:
        run["segment_stride"] = run["segment_frames"]
    run["radius"] = _checked_int("radius", run["radius"], 1, 2)
    if run["frames"] < run["segment_frames"]:
        raise ConfigError(f"frames={run['frames']} is shorter than one segment "
                          f"(segment_frames={run['segment_frames']})")
    run["false_alarm_rate"] = check_prob("false_alarm_rate", run["false_alarm_rate"],
                                         error=ConfigError)
    if count_for_rate(run["false_alarm_rate"], run["size"] ** 2) < 1:
        raise ConfigError(f"false_alarm_rate={run['false_alarm_rate']} keeps no candidate in a "
                          f"{run['size']}x{run['size']} image")
    run["thresholds"] = _increasing_reals("thresholds", run["thresholds"])
    levels = _as_list("pd_levels", run["pd_levels"])
    if not levels:
        raise ConfigError("pd_levels must not be empty")
    run["pd_levels"] = tuple(check_prob(f"pd_levels[{i}]", v, error=ConfigError)
                             for i, v in enumerate(levels))
    run["tolerance_db"] = check_real("tolerance_db", run["tolerance_db"], 0.0, error=ConfigError)
    run["bootstrap"] = _checked_int("bootstrap", run["bootstrap"], 0, 10**6)
    run["chunk"] = _checked_int("chunk", run["chunk"], 1)
    run["adc_low_sigma"] = _real("adc_low_sigma", run["adc_low_sigma"])
    run["adc_span_sigma"] = _real("adc_span_sigma", run["adc_span_sigma"], positive=True)
    pfas = [run["false_alarm_rate"]] if run["pfa"] is None else _as_list("pfa", run["pfa"])
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
        raise ConfigError("nothing to compare: no [[config]] and an empty sweep")
    names = [f.name for f in fixed]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ConfigError(f"configuration names must be unique, repeated: {dup}")
    return CompareSpec(configs=tuple(fixed), **run)
