"""``dptbd verilog``: write the DP pipeline's top-level Verilog and its manifest.

Parameters come from options named after the :class:`~dptbd.config.DPConfig` fields, from a
TOML file of those fields (``--config``; unknown keys are refused), or both (options win).
The manifest JSON beside the Verilog lists the parameters, the weight LUT storage
(``lut_style``), derived widths, weight codes, every port with direction and width, the
latency and the payload bit fields (:func:`dptbd.hw.flow.verilog.manifest`). ``--lut-style``
chooses the weight LUT's storage (``auto``, the default: logic for r = 1, block RAM for
r = 2; ``bram``; ``logic``), a synthesis choice that does not change behaviour.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
import tomllib
import warnings

import numpy as np

from dptbd.config import ROUNDING_MODES, ConfigError, DPConfig, EnergyWidthWarning

__all__ = ["add_config_arguments", "config_from_args", "load_weights", "add_arguments", "main"]

_INT_FIELDS = ("width", "height", "segment_frames", "segment_stride", "input_bits",
               "energy_bits", "weight_frac_bits", "radius")
_HELP = {
    "width": "frame width W",
    "height": "frame height H",
    "segment_frames": "K, frames per segment",
    "segment_stride": "frames between segment starts (the gateware needs = K)",
    "input_bits": "B_in, pixel width",
    "energy_bits": "B_E, energy width",
    "weight_frac_bits": "F, fractional bits of a weight code",
    "radius": "search radius r (1: 3x3, 2: 5x5)",
}


def add_config_arguments(parser: argparse.ArgumentParser) -> None:
    """Options for every DPConfig field, ``--config FILE.toml`` and ``--weights FILE``."""
    defaults = DPConfig()
    group = parser.add_argument_group("parameters (docs/arithmetic.md)")
    group.add_argument("--config", type=pathlib.Path, metavar="TOML",
                       help="TOML file of DPConfig fields (width = 128, rounding = \"half_up\", "
                            "weights = [[…], …], …); options given here override it")
    for name in _INT_FIELDS:
        default = "K" if name == "segment_stride" else getattr(defaults, name)
        group.add_argument("--" + name.replace("_", "-"), type=int, default=None,
                           help=f"{_HELP[name]} (default {default})")
    group.add_argument("--rounding", choices=ROUNDING_MODES, default=None,
                       help=f"weight multiplier rounding (default {defaults.rounding})")
    group.add_argument("--weights", type=pathlib.Path, metavar="FILE",
                       help="weight LUT, (M+1) x M reals in [0, 1] as .npy or .json "
                            "(default: paper 001 eq (11))")


def load_weights(path: pathlib.Path) -> list:
    """A weight table from ``.npy`` or ``.json`` (nested lists)."""
    path = pathlib.Path(path)
    if not path.exists():
        raise FileNotFoundError(f"weights file {path} does not exist")
    if path.suffix == ".npy":
        return np.load(path, allow_pickle=False).tolist()
    if path.suffix == ".json":
        return json.loads(path.read_text())
    raise ValueError(f"weights file must be .npy or .json, got {path.name}")


def config_from_args(args: argparse.Namespace) -> DPConfig:
    """The validated DPConfig: DPConfig's defaults, then the TOML file, then explicit options.

    A narrow ``energy_bits`` is allowed; its :class:`~dptbd.config.EnergyWidthWarning` is
    printed to stderr. Errors (unknown TOML keys, out-of-range values, a LUT of the wrong
    shape) raise :class:`~dptbd.config.ConfigError` with DPConfig's message.
    """
    values: dict = {}
    if args.config is not None:
        if not args.config.exists():
            raise FileNotFoundError(f"config file {args.config} does not exist")
        with open(args.config, "rb") as fh:
            try:
                values = tomllib.load(fh)
            except tomllib.TOMLDecodeError as exc:
                raise ConfigError(f"{args.config} is not valid TOML: {exc}") from exc
    for name in (*_INT_FIELDS, "rounding"):
        value = getattr(args, name, None)
        if value is not None:
            values[name] = value
    if getattr(args, "weights", None) is not None:
        values["weights"] = load_weights(args.weights)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", EnergyWidthWarning)
        try:
            cfg = DPConfig.from_mapping(values)
        except ConfigError as exc:
            where = f" (from {args.config})" if args.config is not None else ""
            raise ConfigError(f"{exc}{where}") from exc
    for w in caught:
        print(f"warning: {w.message}", file=sys.stderr)
    return cfg


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-o", "--output", type=pathlib.Path, required=True, metavar="FILE.v",
                        help="Verilog file to write; the manifest goes to FILE.json beside it")
    parser.add_argument("--force", action="store_true", help="overwrite existing files")
    parser.add_argument("--external-state-store", action="store_true",
                        help="convert DPCore: the W*H-word state store outside the module")
    parser.add_argument("--lut-style", choices=("auto", "bram", "logic"), default="auto",
                        help="weight LUT storage: auto (default; logic for r = 1, block RAM "
                             "for r = 2), bram (one block RAM per move), logic (flip-flops and "
                             "multiplexers, no block RAM; lets the 64x64 top level fit an "
                             "iCE40-HX8K)")
    add_config_arguments(parser)


def main(args: argparse.Namespace) -> int:
    from dptbd.hw.flow.verilog import generate_verilog

    out = args.output
    if out.suffix == ".json":
        raise ValueError(f"output {out} would collide with its manifest; use a .v name")
    manifest = out.with_suffix(".json")
    cfg = config_from_args(args)
    existing = [p for p in (out, manifest) if p.exists()]
    if existing and not args.force:
        raise FileExistsError(f"{', '.join(map(str, existing))} exist(s); pass --force to "
                              f"overwrite")
    text, info = generate_verilog(cfg, external_state_store=args.external_state_store,
                                  lut_style=args.lut_style)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    manifest.write_text(json.dumps(info, indent=2) + "\n")
    ports = ", ".join(f"{p['name']}[{p['width']}]" for p in info["ports"])
    print(f"wrote {out} (module {info['module']}, {info['top']}, {text.count(chr(10))} lines) "
          f"and {manifest}")
    print(f"  {cfg.width}x{cfg.height}, K={cfg.segment_frames}, B_in={cfg.input_bits}, "
          f"B_E={cfg.energy_bits}, F={cfg.weight_frac_bits}, r={cfg.radius}, {cfg.rounding}; "
          f"weight LUT in {info['lut_style']}; latency {info['latency']} cycles")
    print(f"  ports: {ports}")
    return 0
