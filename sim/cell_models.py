"""Verilog simulation models of the vendor cells that the family builds instantiate, for
4-state simulators (Icarus here; a user's bench may use the vendor's own).

The ECP5 builds (:meth:`dptbd.hw.flow.family.Family.options_for`) instantiate Lattice
``DP16KD`` block RAMs (:mod:`dptbd.hw.dp16kd`), which the Yosys ECP5 cell library has as a
blackbox only. ``dp16kd.v`` beside this module models the subset :mod:`dptbd.hw.dp16kd` uses
and refuses every other parameter value; it is strict about X: every array word is X until
written, every output latch and register X until first loaded, a read of the word written
at the same edge X (its header comment: the semantics, the Lattice document they follow,
the subset). :func:`model_sources` gives the
models a generated Verilog text needs; :mod:`dptbd.sim.reset_x` and the cocotb store benches
add them to the ``iverilog`` sources.
"""

from __future__ import annotations

import pathlib
import re
from importlib import resources

__all__ = ["CELL_MODELS", "model_path", "model_sources", "cell_instances"]

#: Cell (Verilog module) name -> its model's file name in this package.
CELL_MODELS = {"DP16KD": "dp16kd.v"}


def model_path(cell: str) -> pathlib.Path:
    """The model file of ``cell`` (a key of :data:`CELL_MODELS`)."""
    if cell not in CELL_MODELS:
        raise ValueError(f"cell must be one of {tuple(CELL_MODELS)}, got {cell!r}")
    return pathlib.Path(str(resources.files("dptbd.sim") / CELL_MODELS[cell]))


def model_sources(verilog: str) -> list[pathlib.Path]:
    """The model files of the cells that ``verilog`` (a generated text) instantiates: a cell
    named at the start of a line, before its parameters or its instance name."""
    return [model_path(cell) for cell in CELL_MODELS if cell_instances(verilog, cell)]


def cell_instances(verilog: str, cell: str) -> dict[str, int]:
    """How many ``cell`` instances each module of ``verilog`` (a generated text) holds,
    by module name (modules without one left out)."""
    counts: dict[str, int] = {}
    module = None
    for line in verilog.splitlines():
        found = re.match(r"\s*module\s+([^\s(]+)", line)
        if found:
            module = found.group(1).lstrip("\\")
        elif re.match(rf"\s*{cell}\s*(#|\\?[A-Za-z_])", line):
            counts[module] = counts.get(module, 0) + 1
    return counts
