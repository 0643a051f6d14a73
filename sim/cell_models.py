"""Verilog simulation models of the vendor cells that the family builds instantiate, for
4-state simulators (Icarus here; a user's bench may use the vendor's own).

The ECP5 builds (:meth:`dptbd.hw.flow.family.Family.options_for`) instantiate Lattice
``DP16KD`` block RAMs (:mod:`dptbd.hw.dp16kd`), which the Yosys ECP5 cell library has as a
blackbox only. ``dp16kd.v`` beside this module models the subset :mod:`dptbd.hw.dp16kd` uses
and refuses every other parameter value; it is strict about X: every array word is X until
written and every output latch and register X until first loaded (its header comment: the
semantics, the Lattice document they follow, the subset). :func:`model_sources` gives the
models a generated Verilog text needs; :mod:`dptbd.sim.reset_x` and the cocotb store benches
add them to the ``iverilog`` sources.
"""

from __future__ import annotations

import pathlib
import re
from importlib import resources

__all__ = ["CELL_MODELS", "model_path", "model_sources"]

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
    return [model_path(cell) for cell in CELL_MODELS
            if re.search(rf"^\s*{cell}\s*(#|\\?[A-Za-z_])", verilog, flags=re.M)]
