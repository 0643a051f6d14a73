"""The fixed-point configurations a comparison compares: one configuration
(:class:`FixedSpec`), the defaults (:data:`DEFAULT_CONFIGS`, :data:`DEFAULT_SWEEP`) and the
validation of a ``[[config]]`` table or a ``[sweep]`` grid (``docs/compare.md``) against the
run-level parameters (:func:`dptbd.evaluation.compare.spec.build_spec`).
"""

from __future__ import annotations

import dataclasses
import itertools
import warnings
from typing import Any, Mapping

import numpy as np

from dptbd.config import DPConfig, EnergyWidthWarning, non_saturating_energy_bits
from dptbd.errors import ConfigError
from dptbd.evaluation.compare.checks import as_list, checked_int, checked_real
from dptbd.evaluation.compare.luts import LUTS, adc_mapping, lut_weights

__all__ = ["FixedSpec", "DEFAULT_CONFIGS", "DEFAULT_SWEEP", "make_fixed", "sweep_entries"]

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


def make_fixed(entry: Mapping[str, Any], run: dict, where: str, *, in_sweep: bool,
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
    gain = d_gain if gain is None else checked_real(f"{where}: adc_gain", gain, positive=True)
    offset = d_offset if offset is None else checked_real(f"{where}: adc_offset", offset)
    if name is None:
        name = f"{bits}/{cfg.energy_bits}/{cfg.weight_frac_bits} {cfg.rounding} {lut}"
    elif not isinstance(name, str) or not name.strip():
        raise ConfigError(f"{where}: name must be a non-empty string, got {name!r}")
    return FixedSpec(name=name, cfg=cfg, lut=lut, adc_gain=gain, adc_offset=offset,
                     in_sweep=in_sweep, explicit=explicit,
                     saturates=cfg.energy_bits < cfg.energy_bits_needed)


def sweep_entries(sweep: Mapping[str, Any], run: dict) -> list[dict]:
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
            vals = as_list(f"sweep.{key}", sweep[key])
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
            head = checked_int("sweep.energy_headroom", head, -32, 32)
            bits = checked_int("sweep.input_bits", point["input_bits"], 1, 16)
            point["energy_bits"] = non_saturating_energy_bits(bits, run["segment_frames"]) + head
        entries.append(point)
    return entries
