"""Yosys ``synth_ice40`` on the generated Verilog, and its cell counts."""

from __future__ import annotations

import dataclasses
import json
import pathlib
import re
from typing import Mapping

from dptbd.hw.flow.tools import SynthToolError, _run, _tail, require_tool

__all__ = [
    "NETLIST_NAME", "YOSYS_LOG_NAME", "YOSYS_STAT_NAME",
    "CellCounts", "parse_yosys_stat_json", "parse_yosys_stat_text", "run_yosys",
]

NETLIST_NAME = "netlist.json"
YOSYS_LOG_NAME = "yosys.log"
YOSYS_STAT_NAME = "yosys-stat.json"


@dataclasses.dataclass(frozen=True)
class CellCounts:
    """Cells of the synthesised netlist, by type (``{"SB_LUT4": 3154, …}``)."""

    by_type: Mapping[str, int]

    def count(self, prefix: str) -> int:
        """Cells whose type starts with ``prefix``."""
        return sum(n for t, n in self.by_type.items() if t.startswith(prefix))

    @property
    def lut4(self) -> int:
        """SB_LUT4: logic cells' look-up tables."""
        return self.by_type.get("SB_LUT4", 0)

    @property
    def dff(self) -> int:
        """Flip-flops: every SB_DFF* variant."""
        return self.count("SB_DFF")

    @property
    def bram(self) -> int:
        """SB_RAM40_4K: 4 kbit block RAMs."""
        return self.by_type.get("SB_RAM40_4K", 0)

    @property
    def carry(self) -> int:
        """SB_CARRY: carry-chain cells."""
        return self.by_type.get("SB_CARRY", 0)

    def to_dict(self) -> dict:
        return {"lut4": self.lut4, "dff": self.dff, "bram": self.bram, "carry": self.carry,
                "by_type": dict(sorted(self.by_type.items()))}


def parse_yosys_stat_json(text: str, top: str | None = None) -> CellCounts:
    """Cell counts from the output of Yosys ``stat -json``.

    Uses the whole-design totals (``"design"``) when present, else the module ``top``
    (Yosys escapes names with a backslash: ``\\dptbd_dp``; either spelling works), else the
    only module.
    """
    data = json.loads(text)
    if "design" in data and "num_cells_by_type" in data["design"]:
        node = data["design"]
    else:
        modules = data.get("modules", {})
        if top is not None and ("\\" + top) in modules:
            node = modules["\\" + top]
        elif top is not None and top in modules:
            node = modules[top]
        elif len(modules) == 1:
            node = next(iter(modules.values()))
        else:
            raise ValueError(f"stat -json output has no design totals and {len(modules)} "
                             f"modules; name the top module")
    return CellCounts({str(k): int(v) for k, v in node.get("num_cells_by_type", {}).items()})


def parse_yosys_stat_text(text: str) -> CellCounts:
    """Cell counts from the last ``stat`` report in a Yosys log (the text fallback).

    Reads the ``Number of cells:`` line and the ``TYPE  COUNT`` lines indented under it.
    """
    blocks = list(re.finditer(r"^\s*Number of cells:\s+\d+\s*$", text, re.M))
    if not blocks:
        raise ValueError("no 'Number of cells:' line in the Yosys log")
    counts: dict[str, int] = {}
    for line in text[blocks[-1].end():].splitlines()[1:]:
        m = re.match(r"^\s+(\$?[A-Za-z_][\w$]*)\s+(\d+)\s*$", line)
        if not m:
            break
        counts[m.group(1)] = int(m.group(2))
    return CellCounts(counts)


def run_yosys(verilog_path: pathlib.Path, *, top: str = "dptbd_dp",
              yosys: str = "yosys", timeout: float = 1800) -> tuple[CellCounts, float]:
    """``synth_ice40`` on ``verilog_path``; writes ``netlist.json`` beside it.

    Returns the cell counts and the wall-clock seconds. The script is
    ``read_verilog F; synth_ice40 -top TOP -json netlist.json; tee -q -o yosys-stat.json
    stat -json``, the log ``yosys.log``; when the stat file is missing the counts come from
    the log's last ``stat`` report.
    """
    exe = require_tool(yosys)
    work = verilog_path.parent
    log = work / YOSYS_LOG_NAME
    stat = work / YOSYS_STAT_NAME
    for stale in (work / NETLIST_NAME, stat):
        stale.unlink(missing_ok=True)
    script = (f"read_verilog {verilog_path.name}; synth_ice40 -top {top} -json {NETLIST_NAME}; "
              f"tee -q -o {YOSYS_STAT_NAME} stat -json")
    proc, seconds = _run([exe, "-q", "-l", log.name, "-p", script], cwd=work,
                         timeout=timeout, tool="yosys", log_path=log)
    log_text = log.read_text(errors="replace") if log.exists() else ""
    if proc.returncode != 0 or not (work / NETLIST_NAME).exists():
        raise SynthToolError(f"yosys failed (exit {proc.returncode}) in {work}",
                             tool="yosys", returncode=proc.returncode,
                             log_tail=_tail(proc.stderr or log_text))
    if stat.exists():
        cells = parse_yosys_stat_json(stat.read_text(), top=top)
    else:
        cells = parse_yosys_stat_text(log_text)
    return cells, seconds
