"""Argument groups that several commands share: the DPConfig parameters (``dptbd verilog``,
``dptbd sim``), the simulator options (``dptbd sim``, ``dptbd run --rtl``) and where the
Monte Carlo runs (``dptbd compare``, ``dptbd table1``, ``dptbd detectors``)."""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
import tomllib
import warnings

import numpy as np

from dptbd.config import ROUNDING_MODES, DPConfig, EnergyWidthWarning
from dptbd.errors import ConfigError

__all__ = ["add_config_arguments", "config_from_args", "load_weights",
           "add_simulator_arguments", "add_execution_arguments"]

_INT_FIELDS = ("width", "height", "segment_frames", "max_segment_frames", "segment_stride",
               "input_bits", "energy_bits", "weight_frac_bits", "radius")
_HELP = {
    "width": "frame width W",
    "height": "frame height H",
    "segment_frames": "K, frames per segment (the gateware's reset value of its run-time K)",
    "max_segment_frames": "K_max, the largest run-time K the gateware accepts (the range of "
                          "the SEGMENT_FRAMES register; sizes its frame counters and B_E), "
                          "in [K, 65535]",
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
        default = "K" if name in ("segment_stride", "max_segment_frames") else \
            getattr(defaults, name)
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
    shape) raise :class:`~dptbd.errors.ConfigError` with DPConfig's message.
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


def add_simulator_arguments(group, prefix: str = "", of: str = "") -> None:
    """``--{prefix}simulator`` (verilator or icarus) and ``--{prefix}build-dir``; ``of``
    starts their help (e.g. ``"of --rtl: "``)."""
    group.add_argument(f"--{prefix}simulator", choices=("verilator", "icarus"),
                       default="verilator",
                       help=f"simulator{of}: verilator (default: compiled and cached builds, "
                            f"100 frames of 128 x 128 in seconds once built) or icarus (cocotb + "
                            f"Icarus, 4-state, minutes for the same)")
    group.add_argument(f"--{prefix}build-dir", type=pathlib.Path, default=None, metavar="DIR",
                       help=f"build root{of}, one directory per parameter set (default: "
                            f"Verilator's shared cache, $DPTBD_BUILD_DIR/verilator or "
                            f"~/.cache/dptbd/verilator; Icarus build/sim)")


def add_execution_arguments(parser, flag: str = "--workers", default: int | None = None,
                            default_text: str = "all cores") -> None:
    """Where a Monte Carlo job's tasks run (``dptbd.evaluation.execution``, ``docs/
    distributed.md``): ``flag`` (the worker count, ``--workers`` or ``--jobs``; ``default``
    described as ``default_text``), ``--scheduler`` and ``--dashboard``."""
    parser.add_argument(flag, type=int, default=default,
                        help=f"worker processes (default: {default_text}; 1 = in this process); "
                             f"with --scheduler: the workers the cluster must have")
    parser.add_argument("--scheduler", metavar="tcp://HOST:PORT", default=None,
                        help="run the trials on this existing dask cluster (default: "
                             "$DPTBD_SCHEDULER if set, else local processes; "
                             "docs/distributed.md)")
    parser.add_argument("--dashboard", action="store_true",
                        help="print the dask dashboard's address")
