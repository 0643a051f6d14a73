"""Yosys ``synth_ice40`` / ``synth_ecp5`` on the generated Verilog, its cell counts, and the
per-block breakdown of a hierarchical synthesis."""

from __future__ import annotations

import dataclasses
import json
import pathlib
import re
from typing import Mapping, Sequence

from dptbd.hw.flow.family import ICE40, YOSYS, Family
from dptbd.hw.flow.tools import SynthToolError, _run, _tail, require_tool

__all__ = [
    "NETLIST_NAME", "YOSYS_LOG_NAME", "YOSYS_STAT_NAME", "YOSYS_HIER_STAT_NAME",
    "CellCounts", "parse_yosys_stat_json", "parse_yosys_stat_text", "block_breakdown",
    "yosys_script", "run_yosys",
]

NETLIST_NAME = "netlist.json"
YOSYS_LOG_NAME = "yosys.log"
YOSYS_STAT_NAME = "yosys-stat.json"
YOSYS_HIER_STAT_NAME = "yosys-stat-hier.json"

#: Cell types of each resource, both families (iCE40 ``SB_*``, ECP5 ``TRELLIS_*`` & co.).
_LUT_TYPES = ("SB_LUT4", "LUT4")
_FF_PREFIXES = ("SB_DFF", "TRELLIS_FF")
_CARRY_TYPES = ("SB_CARRY", "CCU2C")
_BRAM_TYPES = ("SB_RAM40_4K", "DP16KD", "PDPW16KD")
_DSP_TYPES = ("SB_MAC16", "MULT18X18D", "ALU54B")
_LUTRAM_TYPES = ("TRELLIS_DPR16X4",)
#: Bookkeeping of Yosys >= 0.36 (flattened hierarchy scopes; the text report's count of
#: submodule cells), not logic.
_IGNORED_TYPES = ("$scopeinfo", "submodules")


@dataclasses.dataclass(frozen=True)
class CellCounts:
    """Cells of the synthesised netlist, by type (``{"SB_LUT4": 3154, …}``)."""

    by_type: Mapping[str, int]

    def count(self, prefix: str) -> int:
        """Cells whose type starts with ``prefix``."""
        return sum(n for t, n in self.by_type.items() if t.startswith(prefix))

    def _sum(self, types) -> int:
        return sum(self.by_type.get(t, 0) for t in types)

    @property
    def lut4(self) -> int:
        """Four-input look-up tables (``SB_LUT4``, ``LUT4``)."""
        return self._sum(_LUT_TYPES)

    @property
    def dff(self) -> int:
        """Flip-flops: every ``SB_DFF*`` variant, ``TRELLIS_FF``."""
        return sum(self.count(p) for p in _FF_PREFIXES)

    @property
    def bram(self) -> int:
        """Block RAMs: ``SB_RAM40_4K`` (4 kbit), ``DP16KD`` / ``PDPW16KD`` (18 kbit)."""
        return self._sum(_BRAM_TYPES)

    @property
    def carry(self) -> int:
        """Carry cells: ``SB_CARRY`` (one bit), ``CCU2C`` (two bits)."""
        return self._sum(_CARRY_TYPES)

    @property
    def dsp(self) -> int:
        """Multiplier blocks: ``SB_MAC16``, ``MULT18X18D``, ``ALU54B``."""
        return self._sum(_DSP_TYPES)

    @property
    def lutram(self) -> int:
        """Distributed RAM: ``TRELLIS_DPR16X4`` (16 x 4 bits in a slice's LUTs)."""
        return self._sum(_LUTRAM_TYPES)

    def to_dict(self) -> dict:
        return {"lut4": self.lut4, "dff": self.dff, "bram": self.bram, "carry": self.carry,
                "dsp": self.dsp, "lutram": self.lutram,
                "by_type": dict(sorted(self.by_type.items()))}

    def __add__(self, other: "CellCounts") -> "CellCounts":
        merged = dict(self.by_type)
        for t, n in other.by_type.items():
            merged[t] = merged.get(t, 0) + n
        return CellCounts(merged)


def _counts(node: Mapping, modules: Mapping | None = None) -> CellCounts:
    """A ``stat -json`` node's cells, without bookkeeping cells and submodule instances."""
    return CellCounts({str(k): int(v) for k, v in node.get("num_cells_by_type", {}).items()
                       if k not in _IGNORED_TYPES
                       and not (modules and ("\\" + k in modules or k in modules))})


def parse_yosys_stat_json(text: str, top: str | None = None) -> CellCounts:
    """Cell counts from the output of Yosys ``stat -json``.

    Uses the whole-design totals (``"design"``) when present, else the module ``top``
    (Yosys escapes names with a backslash: ``\\dptbd_dp``; either spelling works), else the
    only module. Yosys' bookkeeping ``$scopeinfo`` cells and submodule instances are not
    counted.
    """
    data = json.loads(text)
    modules = data.get("modules", {})
    if "design" in data and "num_cells_by_type" in data["design"]:
        node = data["design"]
    elif top is not None and ("\\" + top) in modules:
        node = modules["\\" + top]
    elif top is not None and top in modules:
        node = modules[top]
    elif len(modules) == 1:
        node = next(iter(modules.values()))
    else:
        raise ValueError(f"stat -json output has no design totals and {len(modules)} "
                         f"modules; name the top module")
    return _counts(node, modules)


def parse_yosys_stat_text(text: str) -> CellCounts:
    """Cell counts from the last ``stat`` report in a Yosys log (the text fallback).

    Reads the ``Number of cells:`` line and the ``TYPE  COUNT`` lines indented under it
    (Yosys 0.23's layout, name then count), or the ``N cells`` line and ``COUNT  TYPE`` lines
    (Yosys 0.70's layout, with an optional area column).
    """
    blocks = list(re.finditer(r"^\s*(?:Number of cells:\s+\d+|\d+\s+(?:[\d.]+\s+)?cells)\s*$",
                              text, re.M))
    if not blocks:
        raise ValueError("no 'Number of cells:' line in the Yosys log")
    counts: dict[str, int] = {}
    for line in text[blocks[-1].end():].splitlines()[1:]:
        m = (re.match(r"^\s+(?P<t>\$?[A-Za-z_][\w$]*)\s+(?P<n>\d+)\s*$", line)
             or re.match(r"^\s+(?P<n>\d+)\s+(?:[\d.]+\s+)?(?P<t>\$?[A-Za-z_][\w$]*)\s*$", line))
        if not m:
            break
        if m.group("t") not in _IGNORED_TYPES:
            counts[m.group("t")] = int(m.group("n"))
    return CellCounts(counts)


def block_breakdown(text: str, top: str) -> dict[str, CellCounts]:
    """Cost of each block from ``stat -json`` of a hierarchical (not flattened) synthesis.

    Amaranth names a submodule's Verilog module after its path (``dptbd_dp.line_buffer``,
    ``dptbd_dp.dp.core.window`` …). Every module instantiated under ``top`` is a block,
    named by its path below ``top`` (``line_buffer``, ``dp.core.window``) and charged with
    its own cells only (times its instance count), not its submodules'; the entry ``top``
    holds the cells at the top level (glue: pipeline registers, stream handshakes). A block
    with submodules thus shows its glue, and each submodule has its own entry. Returns
    ``{block: CellCounts}`` depth first, in instance order. The sum is the hierarchical
    total, larger than the flattened netlist's (Yosys does not optimise across module
    boundaries here).
    """
    data = json.loads(text)
    modules = {k.lstrip("\\"): v for k, v in data.get("modules", {}).items()}
    if top not in modules:
        raise ValueError(f"stat -json output has no module {top!r}")
    out: dict[str, CellCounts] = {}

    def visit(name: str, times: int) -> None:
        node = modules[name]
        label = top if name == top else (
            name[len(top) + 1:] if name.startswith(top + ".") else name)
        local = _counts(node, modules)
        local = CellCounts({t: n * times for t, n in local.by_type.items()})
        out[label] = out[label] + local if label in out else local
        for t, n in node.get("num_cells_by_type", {}).items():
            child = t.lstrip("\\")
            if child in modules:
                visit(child, times * int(n))

    visit(top, 1)
    return out


def yosys_script(verilog_name: str, *, top: str, family: Family, breakdown: bool,
                 synth_args: Sequence[str] | None = None) -> str:
    """The Yosys script of :func:`run_yosys`.

    ``read_verilog F; SYNTH -top TOP ARGS -json netlist.json; tee -q -o yosys-stat.json stat
    -json``, ``ARGS`` being ``synth_args`` (default: the family's,
    :attr:`~dptbd.hw.flow.family.Family.synth_args`); with ``breakdown`` the read design is
    saved first, synthesised once without flattening (``SYNTH -top TOP ARGS -noflatten``,
    its ``stat -json`` to ``yosys-stat-hier.json``) and restored for the flat synthesis that
    nextpnr places.
    """
    args = tuple(family.synth_args if synth_args is None else synth_args)
    synth = " ".join((family.synth_command, "-top", top, *args))
    steps = [f"read_verilog {verilog_name}"]
    if breakdown:
        steps += ["design -save rtl", f"{synth} -noflatten",
                  f"tee -q -o {YOSYS_HIER_STAT_NAME} stat -json", "design -load rtl"]
    steps += [f"{synth} -json {NETLIST_NAME}", f"tee -q -o {YOSYS_STAT_NAME} stat -json"]
    return "; ".join(steps)


def run_yosys(verilog_path: pathlib.Path, *, top: str = "dptbd_dp", family: Family = ICE40,
              yosys: str = YOSYS, timeout: float = 1800,
              breakdown: bool = False, synth_args: Sequence[str] | None = None,
              ) -> tuple[CellCounts, float, dict[str, CellCounts]]:
    """Synthesise ``verilog_path`` for ``family``; writes ``netlist.json`` beside it.

    Returns the flat netlist's cell counts, the wall-clock seconds and, with ``breakdown``,
    :func:`block_breakdown` of a second, hierarchical synthesis (else ``{}``). The script is
    :func:`yosys_script` (with ``synth_args``, default the family's), the log ``yosys.log``;
    when the stat file is missing the counts come from the log's last ``stat`` report.
    """
    exe = require_tool(yosys)
    work = verilog_path.parent
    log = work / YOSYS_LOG_NAME
    stat = work / YOSYS_STAT_NAME
    hier = work / YOSYS_HIER_STAT_NAME
    for stale in (work / NETLIST_NAME, stat, hier):
        stale.unlink(missing_ok=True)
    script = yosys_script(verilog_path.name, top=top, family=family, breakdown=breakdown,
                          synth_args=synth_args)
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
    blocks = block_breakdown(hier.read_text(), top) if breakdown and hier.exists() else {}
    return cells, seconds, blocks
