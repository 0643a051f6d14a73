"""iCE40 synthesis and place-and-route of the DP pipeline: resources and Fmax.

``synthesize(cfg)`` generates the Verilog of :class:`~dptbd.hw.dp_core.DPCore`
(``variant="core"``, state store outside) or :class:`~dptbd.hw.dp_pipeline.DPPipeline`
(``variant="top"``, on-chip state store), synthesises it with Yosys ``synth_ice40``,
places and routes it with ``nextpnr-ice40`` once per placement seed, and returns a
:class:`SynthResult`: Yosys cell counts (SB_LUT4, SB_DFF*, SB_RAM40_4K, SB_CARRY), and per
seed the post-route Fmax, the device utilisation and whether the design fits. The weight
LUT's storage is the gateware's ``lut_style`` (``"auto"``: logic for r = 1, block RAM for
r = 2; ``"bram"``; ``"logic"``), recorded in ``SynthResult.params["lut_style"]``. ::

    from dptbd.config import DPConfig
    from dptbd.hw.flow.synth import synthesize
    res = synthesize(DPConfig(), variant="core", seeds=(1, 2, 3))
    res_bram = synthesize(DPConfig(), variant="core", lut_style="bram")
    print(res.cells.lut4, res.cells.bram, res.fmax_median_mhz, res.fits)

A design that does not fit the device is a result (``fits`` False, utilisation above 100 %,
the nextpnr error in ``PnrRun.error``), not an exception; a missing tool, a tool timeout and
any other tool failure raise :class:`SynthToolError` (or a subclass) with the log's tail.

Tools (Debian packages): ``yosys`` (tested with 0.23) and ``nextpnr-ice40`` (0.4; the
chip database comes with ``fpga-icestorm-chipdb``). ``seeds=()`` runs Yosys only.
``docs/synthesis.md`` lists measured figures; ``benchmarks/bench_synth.py``
produces them.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import json
import pathlib
import re
import shutil
import statistics
import subprocess
import tempfile
import time
from typing import Callable, Mapping, Sequence

from dptbd.config import DPConfig

__all__ = [
    "VARIANTS", "ICE40_DEVICES", "DEBIAN_PACKAGES",
    "SynthToolError", "ToolNotFoundError", "ToolTimeoutError",
    "CellCounts", "PnrReport", "PnrRun", "SynthResult",
    "parse_yosys_stat_json", "parse_yosys_stat_text", "parse_nextpnr_log",
    "parse_nextpnr_report", "pick_clock", "require_tool", "tool_version",
    "run_yosys", "run_nextpnr", "synthesize",
]

#: ``"core"``: DPCore, state store outside (port ``state_store__*``); ``"top"``: DPPipeline.
VARIANTS = ("core", "top")

#: Devices ``nextpnr-ice40`` knows (``--hx8k`` …).
ICE40_DEVICES = ("lp384", "lp1k", "lp4k", "lp8k", "hx1k", "hx4k", "hx8k",
                 "up3k", "up5k", "u1k", "u2k", "u4k")

#: Debian package that provides each tool (named in :class:`ToolNotFoundError`).
DEBIAN_PACKAGES = {"yosys": "yosys", "nextpnr-ice40": "nextpnr-ice40"}

VERILOG_NAME = "dptbd_dp.v"
NETLIST_NAME = "netlist.json"
YOSYS_LOG_NAME = "yosys.log"
YOSYS_STAT_NAME = "yosys-stat.json"

#: Causes of a nextpnr failure that mean "the design does not fit this device".
_NO_FIT_PATTERNS = (
    re.compile(r"no BELs remaining", re.I),
    re.compile(r"Unable to place cell", re.I),
    re.compile(r"Unable to find legal placement", re.I),
    re.compile(r"failed to place", re.I),
    re.compile(r"Failed to route", re.I),
    re.compile(r"Failed to expand region", re.I),
)

_FMAX_RE = re.compile(
    r"Max frequency for clock\s+'(?P<clock>[^']+)':\s+(?P<fmax>[0-9.]+)\s+MHz"
    r"(?:\s+\((?P<verdict>PASS|FAIL)\s+at\s+(?P<target>[0-9.]+)\s+MHz\))?")
_UTIL_RE = re.compile(r"^Info:\s+(?P<bel>[A-Za-z0-9_]+):\s+(?P<used>\d+)/\s*(?P<avail>\d+)\s+\d+%",
                      re.M)
_ERROR_RE = re.compile(r"^ERROR:\s*(?P<msg>.*)$", re.M)


# --------------------------------------------------------------------------------------
# Errors


class SynthToolError(RuntimeError):
    """A synthesis tool failed; ``tool``, ``returncode`` and the log tail in the message."""

    def __init__(self, message: str, *, tool: str = "", returncode: int | None = None,
                 log_tail: str = ""):
        super().__init__(message + (f"\n--- last lines of the {tool} log ---\n{log_tail}"
                                    if log_tail else ""))
        self.tool = tool
        self.returncode = returncode
        self.log_tail = log_tail


class ToolNotFoundError(SynthToolError):
    """The tool is not on ``PATH``; the message names the Debian package to install."""


class ToolTimeoutError(SynthToolError):
    """The tool ran longer than its timeout and was killed."""


def require_tool(name: str) -> str:
    """Absolute path of the executable ``name`` (a name on ``PATH`` or a path).

    Raises
    ------
    ToolNotFoundError
        Naming the Debian package that provides it (``apt-get install …``).
    """
    path = shutil.which(name)
    if path is None:
        base = pathlib.Path(name).name
        package = DEBIAN_PACKAGES.get(base, base)
        raise ToolNotFoundError(
            f"{name!r} not found on PATH: it is needed for iCE40 synthesis; install the "
            f"Debian package {package!r} (apt-get install {package})", tool=base)
    return path


def tool_version(executable: str, timeout: float = 30) -> str:
    """First non-empty line of ``executable -V`` / ``--version`` output ("" if neither works)."""
    for flag in ("-V", "--version"):
        try:
            proc = subprocess.run([executable, flag], capture_output=True, text=True,
                                  timeout=timeout)
        except (OSError, subprocess.TimeoutExpired):
            continue
        lines = [ln.strip() for ln in (proc.stdout + proc.stderr).splitlines() if ln.strip()]
        if proc.returncode == 0 and lines:
            return lines[0]
    return ""


def _tail(text: str, lines: int = 25) -> str:
    return "\n".join(text.splitlines()[-lines:])


def _run(cmd: Sequence[str], *, cwd: pathlib.Path, timeout: float, tool: str,
         log_path: pathlib.Path | None) -> tuple[subprocess.CompletedProcess, float]:
    """Run ``cmd``; a timeout raises :class:`ToolTimeoutError` (the child is killed)."""
    start = time.monotonic()
    try:
        proc = subprocess.run(list(cmd), cwd=cwd, capture_output=True, text=True,
                              timeout=timeout)
    except subprocess.TimeoutExpired as exc:
        log = log_path.read_text(errors="replace") if log_path and log_path.exists() else ""
        raise ToolTimeoutError(f"{tool} timed out after {timeout:g} s: {' '.join(cmd)}",
                               tool=tool, log_tail=_tail(log)) from exc
    return proc, time.monotonic() - start


# --------------------------------------------------------------------------------------
# Yosys


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


# --------------------------------------------------------------------------------------
# nextpnr


@dataclasses.dataclass(frozen=True)
class PnrReport:
    """What a nextpnr log (or ``--report`` JSON) says.

    ``fmax`` maps each clock to its **final** (post-route) Fmax in MHz; ``utilisation`` each
    BEL type to ``(used, available)``; ``errors`` lists the ``ERROR:`` messages.
    """

    fmax: Mapping[str, float]
    utilisation: Mapping[str, tuple[int, int]]
    errors: tuple[str, ...] = ()

    @property
    def over_capacity(self) -> tuple[str, ...]:
        """BEL types used beyond what the device has."""
        return tuple(b for b, (used, avail) in self.utilisation.items() if used > avail)

    @property
    def no_fit_error(self) -> str | None:
        """The first error that means the design does not fit (placement / routing), if any."""
        for err in self.errors:
            if any(p.search(err) for p in _NO_FIT_PATTERNS):
                return err
        return None


def parse_nextpnr_log(text: str) -> PnrReport:
    """Parse a ``nextpnr-ice40`` log.

    The log prints ``Max frequency for clock 'X': F MHz (PASS|FAIL at T MHz)`` after
    placement and again after routing; the last line per clock (post-route) wins. The
    ``Device utilisation:`` block gives ``BEL: used/ available``.
    """
    fmax: dict[str, float] = {}
    for m in _FMAX_RE.finditer(text):
        fmax[m.group("clock")] = float(m.group("fmax"))
    util: dict[str, tuple[int, int]] = {}
    start = text.rfind("Device utilisation:")
    if start >= 0:
        for line in text[start:].splitlines()[1:]:
            m = _UTIL_RE.match(line)
            if not m:
                break
            util[m.group("bel")] = (int(m.group("used")), int(m.group("avail")))
    errors = tuple(m.group("msg").strip() for m in _ERROR_RE.finditer(text))
    return PnrReport(fmax=fmax, utilisation=util, errors=errors)


def parse_nextpnr_report(text: str) -> PnrReport:
    """Parse the JSON written by ``nextpnr --report`` (keys ``fmax`` and ``utilization``)."""
    data = json.loads(text)
    fmax = {str(c): float(v["achieved"]) for c, v in data.get("fmax", {}).items()}
    util = {str(b): (int(v["used"]), int(v["available"]))
            for b, v in data.get("utilization", {}).items()}
    return PnrReport(fmax=fmax, utilisation=util)


def pick_clock(fmax: Mapping[str, float], clock: str = "clk") -> str | None:
    """The clock of interest among nextpnr's names (``clk$SB_IO_IN_$glb_clk`` for ``clk``).

    The only clock if there is one; else the one named ``clock`` or ``clock$…``.
    """
    if len(fmax) == 1:
        return next(iter(fmax))
    matches = [c for c in fmax if c == clock or c.startswith(clock + "$")]
    return matches[0] if len(matches) == 1 else None


@dataclasses.dataclass(frozen=True)
class PnrRun:
    """One nextpnr run (one placement seed).

    ``fits``: placed and routed. ``fmax_mhz``: post-route Fmax of the clock (``None`` when it
    did not fit). ``utilisation``: ``{BEL type: (used, available)}``, also when it did not
    fit (then some type is above 100 %). ``error``: nextpnr's reason when it did not fit.
    """

    seed: int
    fits: bool
    fmax_mhz: float | None
    target_mhz: float
    utilisation: Mapping[str, tuple[int, int]]
    seconds: float
    error: str | None = None
    clock: str | None = None
    log_path: str | None = None

    @property
    def meets_target(self) -> bool:
        return self.fmax_mhz is not None and self.fmax_mhz >= self.target_mhz

    def used(self, bel: str) -> int | None:
        """Used count of BEL type ``bel`` (``ICESTORM_LC``, ``ICESTORM_RAM``, …)."""
        return self.utilisation[bel][0] if bel in self.utilisation else None

    def to_dict(self) -> dict:
        return {"seed": self.seed, "fits": self.fits, "fmax_mhz": self.fmax_mhz,
                "target_mhz": self.target_mhz, "meets_target": self.meets_target,
                "clock": self.clock, "error": self.error, "seconds": round(self.seconds, 1),
                "utilisation": {b: {"used": u, "available": a}
                                for b, (u, a) in self.utilisation.items()},
                "log": self.log_path}


def run_nextpnr(netlist: pathlib.Path, *, seed: int, device: str = "hx8k",
                package: str = "ct256", target_mhz: float = 100.0, clock: str = "clk",
                nextpnr: str = "nextpnr-ice40", timeout: float = 1800,
                extra_args: Sequence[str] = ()) -> PnrRun:
    """Place and route ``netlist`` once (``--seed seed``); log ``nextpnr-seed<N>.log``.

    Runs with ``--pcf-allow-unconstrained`` (pins placed automatically) and
    ``--timing-allow-fail`` (a missed target is reported in ``fmax_mhz``, not an error).
    A design that does not fit returns ``fits=False``; other failures raise
    :class:`SynthToolError`.
    """
    if device not in ICE40_DEVICES:
        raise ValueError(f"device must be one of {ICE40_DEVICES}, got {device!r}")
    exe = require_tool(nextpnr)
    work = netlist.parent
    log = work / f"nextpnr-seed{seed}.log"
    report = work / f"nextpnr-seed{seed}.report.json"
    for stale in (log, report):
        stale.unlink(missing_ok=True)
    cmd = [exe, f"--{device}", "--package", package, "--json", netlist.name,
           "--freq", f"{target_mhz:g}", "--pcf-allow-unconstrained", "--timing-allow-fail",
           "--seed", str(seed), "--report", report.name, "-l", log.name, "-q", *extra_args]
    proc, seconds = _run(cmd, cwd=work, timeout=timeout, tool="nextpnr", log_path=log)
    log_text = log.read_text(errors="replace") if log.exists() else ""
    parsed = parse_nextpnr_log(log_text + "\n" + proc.stderr)
    if proc.returncode == 0 and report.exists():
        from_json = parse_nextpnr_report(report.read_text())
        parsed = PnrReport(fmax=from_json.fmax or parsed.fmax,
                           utilisation=from_json.utilisation or parsed.utilisation,
                           errors=parsed.errors)
    if proc.returncode == 0:
        name = pick_clock(parsed.fmax, clock)
        if name is None:
            raise SynthToolError(f"nextpnr finished but reported no Fmax for clock {clock!r} "
                                 f"(clocks: {sorted(parsed.fmax)})", tool="nextpnr",
                                 returncode=0, log_tail=_tail(log_text))
        return PnrRun(seed=seed, fits=True, fmax_mhz=parsed.fmax[name], target_mhz=target_mhz,
                      utilisation=parsed.utilisation, seconds=seconds, clock=name,
                      log_path=str(log))
    over = parsed.over_capacity
    reason = parsed.no_fit_error
    if over or reason:
        parts = []
        if over:
            parts.append("over capacity: " + ", ".join(
                f"{b} {parsed.utilisation[b][0]}/{parsed.utilisation[b][1]}" for b in over))
        if reason:
            parts.append("nextpnr: " + reason)
        reason = "; ".join(parts)
        return PnrRun(seed=seed, fits=False, fmax_mhz=None, target_mhz=target_mhz,
                      utilisation=parsed.utilisation, seconds=seconds, error=reason,
                      log_path=str(log))
    raise SynthToolError(f"nextpnr failed (exit {proc.returncode}): {' '.join(cmd)}",
                         tool="nextpnr", returncode=proc.returncode,
                         log_tail=_tail(log_text or proc.stderr))


# --------------------------------------------------------------------------------------
# The flow


@dataclasses.dataclass(frozen=True)
class SynthResult:
    """Yosys cell counts and the nextpnr runs of one configuration and variant."""

    variant: str
    device: str
    package: str
    target_mhz: float
    params: Mapping[str, object]
    cells: CellCounts
    runs: tuple[PnrRun, ...]
    yosys_seconds: float
    verilog_seconds: float
    tools: Mapping[str, str] = dataclasses.field(default_factory=dict)
    workdir: str | None = None

    @property
    def fits(self) -> bool | None:
        """Every run placed and routed (``None`` if nextpnr was not run)."""
        return all(r.fits for r in self.runs) if self.runs else None

    @property
    def fmaxes_mhz(self) -> tuple[float, ...]:
        """Post-route Fmax of each fitting run, in seed order."""
        return tuple(r.fmax_mhz for r in self.runs if r.fmax_mhz is not None)

    @property
    def fmax_median_mhz(self) -> float | None:
        f = self.fmaxes_mhz
        return statistics.median(f) if f else None

    @property
    def fmax_min_mhz(self) -> float | None:
        return min(self.fmaxes_mhz, default=None)

    @property
    def fmax_max_mhz(self) -> float | None:
        return max(self.fmaxes_mhz, default=None)

    @property
    def meets_target(self) -> bool | None:
        """Median Fmax at least the target (``None`` if nextpnr was not run or nothing fit)."""
        med = self.fmax_median_mhz
        return None if med is None else med >= self.target_mhz

    @property
    def utilisation(self) -> Mapping[str, tuple[int, int]]:
        """Device utilisation of the first run (packing, hence the counts, is seed-independent)."""
        return self.runs[0].utilisation if self.runs else {}

    def used(self, bel: str) -> int | None:
        u = self.utilisation.get(bel)
        return None if u is None else u[0]

    def available(self, bel: str) -> int | None:
        u = self.utilisation.get(bel)
        return None if u is None else u[1]

    def to_dict(self) -> dict:
        return {
            "variant": self.variant, "device": self.device, "package": self.package,
            "target_mhz": self.target_mhz, "params": dict(self.params),
            "cells": self.cells.to_dict(),
            "fits": self.fits, "fmax_median_mhz": self.fmax_median_mhz,
            "fmax_min_mhz": self.fmax_min_mhz, "fmax_max_mhz": self.fmax_max_mhz,
            "meets_target": self.meets_target,
            "utilisation": {b: {"used": u, "available": a}
                            for b, (u, a) in self.utilisation.items()},
            "runs": [r.to_dict() for r in self.runs],
            "seconds": {"verilog": round(self.verilog_seconds, 1),
                        "yosys": round(self.yosys_seconds, 1),
                        "nextpnr": [round(r.seconds, 1) for r in self.runs]},
            "tools": dict(self.tools), "workdir": self.workdir,
        }


def _config_params(cfg: DPConfig) -> dict:
    return {f.name: getattr(cfg, f.name) for f in dataclasses.fields(cfg) if f.name != "weights"}


def synthesize(cfg: DPConfig, *, variant: str = "core", seeds: Sequence[int] = (1, 2, 3),
               workdir: str | pathlib.Path | None = None, device: str = "hx8k",
               package: str = "ct256", target_mhz: float = 100.0, jobs: int = 1,
               yosys: str = "yosys", nextpnr: str = "nextpnr-ice40",
               yosys_timeout: float = 1800, nextpnr_timeout: float = 1800,
               lut_style: str = "auto",
               verilog_filter: Callable[[str], str] | None = None) -> SynthResult:
    """Generate, synthesise and place-and-route the pipeline for ``cfg``.

    Parameters
    ----------
    cfg : DPConfig
        The configuration.
    variant : {"core", "top"}
        ``"core"``: :class:`DPCore` (state store outside, on the module's ports);
        ``"top"``: :class:`DPPipeline` (W*H-word on-chip state store).
    seeds : sequence of int
        One nextpnr run per placement seed; ``()`` runs Yosys only.
    workdir : path-like, optional
        Where ``dptbd_dp.v``, its manifest ``dptbd_dp.json``, ``netlist.json`` and the logs
        go (created; files of a previous run are overwritten). Default: a temporary folder,
        deleted afterwards (``SynthResult.workdir`` and the logs' paths are then ``None``).
    device, package : str
        nextpnr-ice40 device (``hx8k``, ``up5k``, … :data:`ICE40_DEVICES`) and package.
    target_mhz : float
        ``--freq`` (the timing-driven placer's target; also the ``meets_target`` threshold).
    jobs : int
        nextpnr runs in parallel (each uses one core).
    yosys, nextpnr : str
        Executables (names on ``PATH`` or paths).
    yosys_timeout, nextpnr_timeout : float
        Seconds per tool call before it is killed (:class:`ToolTimeoutError`).
    lut_style : {"auto", "bram", "logic"}
        Weight LUT storage, passed to the gateware
        (:class:`~dptbd.hw.weight_lut.WeightLUT`); the resolved style is
        ``SynthResult.params["lut_style"]``. ``ValueError`` for anything else.
    verilog_filter : callable, optional
        Applied to the generated Verilog text before synthesis, e.g. to try a synthesis
        attribute the gateware has no option for. The file written is the filtered text.

    Raises
    ------
    ToolNotFoundError
        Yosys or nextpnr is missing (checked before anything runs).
    SynthToolError
        A tool failed for a reason other than the design not fitting.
    dptbd.config.ConfigError
        The gateware does not support ``cfg``.
    """
    from dptbd.hw.flow.verilog import MODULE_NAME, generate_verilog  # Amaranth import on demand
    from dptbd.hw.weight_lut import resolve_lut_style

    style = resolve_lut_style(cfg, lut_style)   # ValueError before any tool runs
    if variant not in VARIANTS:
        raise ValueError(f"variant must be one of {VARIANTS}, got {variant!r}")
    if device not in ICE40_DEVICES:
        raise ValueError(f"device must be one of {ICE40_DEVICES}, got {device!r}")
    seeds = tuple(int(s) for s in seeds)
    if len(set(seeds)) != len(seeds):
        raise ValueError(f"seeds must be distinct, got {seeds}")
    if jobs < 1:
        raise ValueError(f"jobs must be >= 1, got {jobs}")
    yosys_exe = require_tool(yosys)
    nextpnr_exe = require_tool(nextpnr) if seeds else None
    tools = {"yosys": tool_version(yosys_exe)}
    if nextpnr_exe:
        tools["nextpnr"] = tool_version(nextpnr_exe)

    tmp = None
    if workdir is None:
        tmp = tempfile.TemporaryDirectory(prefix="dptbd-synth-")
        work = pathlib.Path(tmp.name)
    else:
        work = pathlib.Path(workdir)
        work.mkdir(parents=True, exist_ok=True)
    try:
        start = time.monotonic()
        text, _ = generate_verilog(cfg, external_state_store=(variant == "core"),
                                   lut_style=lut_style, manifest_path=work / "dptbd_dp.json")
        if verilog_filter is not None:
            text = verilog_filter(text)
        verilog_path = work / VERILOG_NAME
        verilog_path.write_text(text)
        verilog_seconds = time.monotonic() - start

        cells, yosys_seconds = run_yosys(verilog_path, top=MODULE_NAME, yosys=yosys_exe,
                                         timeout=yosys_timeout)

        def one(seed: int) -> PnrRun:
            return run_nextpnr(work / NETLIST_NAME, seed=seed, device=device, package=package,
                               target_mhz=target_mhz, nextpnr=nextpnr_exe,
                               timeout=nextpnr_timeout)

        if jobs == 1 or len(seeds) <= 1:
            runs = tuple(one(s) for s in seeds)
        else:
            with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
                runs = tuple(pool.map(one, seeds))
        if tmp is not None:
            runs = tuple(dataclasses.replace(r, log_path=None) for r in runs)
        return SynthResult(variant=variant, device=device, package=package,
                           target_mhz=float(target_mhz),
                           params={**_config_params(cfg), "lut_style": style},
                           cells=cells, runs=runs, yosys_seconds=yosys_seconds,
                           verilog_seconds=verilog_seconds, tools=tools,
                           workdir=None if tmp is not None else str(work))
    finally:
        if tmp is not None:
            tmp.cleanup()

