"""iCE40-HX8K resources and post-route Fmax of the DP pipeline (Yosys + nextpnr).

Cases (each: Verilog generation, Yosys ``synth_ice40``, nextpnr-ice40 once per seed; the
weight LUT storage is the gateware's ``lut_style`` keyword, default ``"auto"`` = logic for
r = 1, block RAM for r = 2):

* ``core128`` — ``DPCore`` (state store external), W = H = 128, B_in = 8, B_E = 16, F = 8,
  r = 1, default LUT storage (logic): LUT / FF / BRAM and the median post-route Fmax of the
  seeds (target >= 100 MHz). This is also the README's resource figure of the 128 x 128
  configuration (the state store, 16384 x 20 bits, is an external SRAM).
* ``top64`` — ``DPPipeline`` (on-chip state store, 4096 words of (E, d)) at 64 x 64, same
  widths, default LUT storage (logic): does it fit an HX8K (utilisation, Fmax)?
* ``top128`` — ``DPPipeline`` at 128 x 128 (16384-word store): what the on-chip store
  would need.
* ``core128-lutbram``, ``top64-lutbram`` — as ``core128`` / ``top64`` with
  ``lut_style="bram"`` (one block RAM per LUT column).
* ``top64-e12`` — as ``top64-lutbram`` with B_E = 12 (16-bit state words; 12 bits never
  saturate for K <= 16 frames of 8-bit pixels).
* ``core128-r2`` — as ``core128`` with r = 2 (25 moves; the default LUT storage is then
  block RAM).

    python benchmarks/bench_synth.py                          # core128 top64 top128
    python benchmarks/bench_synth.py --cases top64-lutbram top64-e12 core128-r2
    python benchmarks/bench_synth.py --cases core128 --seeds 1 2 3 4 5 --jobs 2
    python benchmarks/bench_synth.py --json build/synth.json [--force]

Needs Debian's ``yosys`` and ``nextpnr-ice40``. The work folders (Verilog, netlist, logs)
go to ``--workdir``/<case> (default ``build/synth``). Prints a Markdown table.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
import time

from dptbd.config import DPConfig
from dptbd.hw.flow.synth import SynthResult, synthesize


#: name -> (description, DPConfig, variant, lut_style)
CASES = {
    "core128": ("DPCore 128x128 (external store)", DPConfig(width=128, height=128), "core",
                "auto"),
    "top64": ("DPPipeline 64x64 (on-chip store)", DPConfig(width=64, height=64), "top",
              "auto"),
    "top128": ("DPPipeline 128x128 (on-chip store)", DPConfig(width=128, height=128), "top",
               "auto"),
    "core128-lutbram": ("DPCore 128x128, LUT in BRAM (external store)",
                        DPConfig(width=128, height=128), "core", "bram"),
    "top64-lutbram": ("DPPipeline 64x64, LUT in BRAM (on-chip store)",
                      DPConfig(width=64, height=64), "top", "bram"),
    "top64-e12": ("DPPipeline 64x64, B_E=12, LUT in BRAM (on-chip store)",
                  DPConfig(width=64, height=64, energy_bits=12), "top", "bram"),
    "core128-r2": ("DPCore 128x128, r=2 (external store)",
                   DPConfig(width=128, height=128, radius=2), "core", "auto"),
}
DEFAULT_CASES = ("core128", "top64", "top128")


def _fmt_mhz(x: float | None) -> str:
    return "—" if x is None else f"{x:.1f}"


def _used(res: SynthResult, bel: str) -> str:
    u = res.utilisation.get(bel)
    return "—" if u is None else f"{u[0]}/{u[1]} ({100 * u[0] / u[1]:.0f} %)"


def markdown_table(rows: list[tuple[str, str, SynthResult]]) -> str:
    """One line per case: Yosys cells, nextpnr utilisation, Fmax per seed and median."""
    head = ("| case | design | B_E | LUT storage | SB_LUT4 | FFs | SB_CARRY | SB_RAM40_4K | "
            "ICESTORM_LC | ICESTORM_RAM | fits | Fmax per seed (MHz) | Fmax median (MHz) |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for name, desc, res in rows:
        c = res.cells
        seeds = ", ".join(f"{r.seed}: {_fmt_mhz(r.fmax_mhz)}" for r in res.runs) or "—"
        fits = {None: "not run", True: "yes", False: "**no**"}[res.fits]
        style = res.params.get("lut_style", "—")
        lines.append(
            f"| {name} | {desc} | {res.params['energy_bits']} | {style} | {c.lut4} | {c.dff} "
            f"| {c.carry} | {c.bram} | {_used(res, 'ICESTORM_LC')} | {_used(res, 'ICESTORM_RAM')} | {fits} "
            f"| {seeds} | {_fmt_mhz(res.fmax_median_mhz)} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", choices=sorted(CASES), default=list(DEFAULT_CASES))
    parser.add_argument("--seeds", nargs="*", type=int, default=[1, 2, 3],
                        help="nextpnr placement seeds (none: Yosys only)")
    parser.add_argument("--jobs", type=int, default=1, help="nextpnr runs in parallel")
    parser.add_argument("--freq", type=float, default=100.0, help="target MHz (--freq)")
    parser.add_argument("--device", default="hx8k")
    parser.add_argument("--package", default="ct256")
    parser.add_argument("--workdir", type=pathlib.Path, default=pathlib.Path("build/synth"))
    parser.add_argument("--timeout", type=float, default=1800, help="seconds per tool call")
    parser.add_argument("--json", type=pathlib.Path, help="also write the figures here")
    parser.add_argument("--force", action="store_true", help="overwrite --json")
    args = parser.parse_args(argv)
    if args.json is not None and args.json.exists() and not args.force:
        parser.error(f"{args.json} exists; pass --force to overwrite it")

    rows, figures = [], {}
    for name in args.cases:
        desc, cfg, variant, lut_style = CASES[name]
        start = time.monotonic()
        print(f"[{name}] {desc}: synthesising …", file=sys.stderr, flush=True)
        res = synthesize(cfg, variant=variant, seeds=args.seeds, workdir=args.workdir / name,
                         device=args.device, package=args.package, target_mhz=args.freq,
                         jobs=args.jobs, yosys_timeout=args.timeout,
                         nextpnr_timeout=args.timeout, lut_style=lut_style)
        wall = time.monotonic() - start
        print(f"[{name}] done in {wall:.0f} s (yosys {res.yosys_seconds:.0f} s, nextpnr "
              f"{', '.join(f'{r.seconds:.0f}' for r in res.runs) or '—'} s); fits: {res.fits}"
              + ("" if res.fits is not False else f" ({res.runs[0].error})"),
              file=sys.stderr, flush=True)
        rows.append((name, desc, res))
        figures[name] = {"description": desc, "wall_seconds": round(wall, 1), **res.to_dict()}

    print(f"\niCE40-{args.device.upper()} ({args.package}), target {args.freq:g} MHz, "
          f"seeds {args.seeds}\n")
    print(markdown_table(rows))
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"command": " ".join(sys.argv), "cases": figures},
                                        indent=2) + "\n")
        print(f"\nwrote {args.json}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
