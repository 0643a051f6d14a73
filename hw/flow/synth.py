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

The steps live beside this module: :mod:`~dptbd.hw.flow.tools` (running the tools and
their errors), :mod:`~dptbd.hw.flow.yosys` (synthesis and cell counts) and
:mod:`~dptbd.hw.flow.nextpnr` (place and route); their public names are re-exported here.

Tools (Debian packages): ``yosys`` (tested with 0.23) and ``nextpnr-ice40`` (0.4; the
chip database comes with ``fpga-icestorm-chipdb``). ``seeds=()`` runs Yosys only.
``docs/synthesis.md`` lists measured figures; ``benchmarks/bench_synth.py``
produces them.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import pathlib
import statistics
import tempfile
import time
from typing import Callable, Mapping, Sequence

from dptbd.config import DPConfig
from dptbd.hw.flow.nextpnr import (
    ICE40_DEVICES, PnrReport, PnrRun, parse_nextpnr_log, parse_nextpnr_report, pick_clock,
    run_nextpnr,
)
from dptbd.hw.flow.tools import (
    DEBIAN_PACKAGES, SynthToolError, ToolNotFoundError, ToolTimeoutError, require_tool,
    tool_version,
)
from dptbd.hw.flow.yosys import (
    NETLIST_NAME, CellCounts, parse_yosys_stat_json, parse_yosys_stat_text, run_yosys,
)

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

VERILOG_NAME = "dptbd_dp.v"


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
        raise ValueError(f"jobs must be an integer in [1, inf), got {jobs}")
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
