"""``dptbd compare``: fixed point against float — Monte Carlo Pd/Pfa, SNR loss, bit-width sweep.

Parses the arguments and calls the job :func:`dptbd.evaluation.compare.compare_job`: the
Monte Carlo on the built-in scene (or a TOML file's), optionally every configuration
synthesised for its iCE40 cost (``--synth``, cached), CSV, JSON and PNG figures written to
``--out``. ``docs/compare.md`` is the method, ``docs/compare_results.md`` has real results.
"""

from __future__ import annotations

import argparse
import pathlib
import sys

from dptbd.commands.options import add_execution_arguments

#: evaluation.compare.spec.TIE_RULES, written out for the same reason as the defaults below
#: (tests/commands/test_compare.py::test_cli_tie_rules_are_the_specs keeps them equal).
TIE_RULES = ("random", "gateware", "gateware-bins")

HELP = "fixed vs float detection: Monte Carlo Pd/Pfa, SNR loss, bit-width sweep with iCE40 cost"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--config", type=pathlib.Path, metavar="TOML",
                        help="run parameters, [[config]] list and [sweep] table (docs/compare.md); "
                             "default: the built-in comparison")
    # The defaults quoted here are evaluation.compare.DEFAULT_RUN's (written out rather than
    # imported, so that building the CLI does not import numba;
    # tests/commands/test_compare.py::test_cli_help_quotes_the_real_defaults keeps them equal).
    parser.add_argument("--trials", type=int, help="seeded scenes (default 240, or the file's)")
    parser.add_argument("--seed", type=int, help="base seed (default 2024, or the file's)")
    parser.add_argument("--snr", type=float, nargs="*", metavar="SNR",
                        help="paper 001 linear SNRs, strictly increasing "
                             "(default 1.5 1.7 1.9 2.1 2.3 2.5 2.7 2.9, or the file's)")
    parser.add_argument("--bootstrap", type=int, metavar="B",
                        help="bootstrap resamples for the SNR-loss intervals "
                             "(default 1000, or the file's)")
    parser.add_argument("--tie-rule", choices=TIE_RULES, default=None,
                        help="candidate rule: random = exactly n per image, ties broken by a "
                             "seeded priority; gateware = the segmenter's selection with the "
                             "image's own histogram, one bin per E (E > the (n+1)-th largest, "
                             "ties dropped whole); gateware-bins = the same on each "
                             "configuration's histogram bins E >> s (docs/compare.md; "
                             "default random, or the file's)")
    add_execution_arguments(parser)
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("compare-out"),
                        help="new output folder for CSV/JSON/PNG (default ./compare-out; must not "
                             "exist unless --force)")
    parser.add_argument("--force", action="store_true",
                        help="replace --out when it is the folder of an earlier dptbd compare run")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--rtl", action="store_true",
                        help="RTL in the loop: accumulate the fixed-point configurations' trials "
                             "on the compiled gateware (Verilator), every output word and "
                             "candidate list checked against the golden model "
                             "(docs/compare.md); the float model stays as it is")
    synth = parser.add_argument_group("hardware cost (slow: minutes per configuration, cached)")
    synth.add_argument("--synth", action="store_true",
                       help="synthesise every configuration (Yosys synth_ice40 + nextpnr-ice40); "
                            "off by default")
    synth.add_argument("--synth-variant", choices=("core", "top"), default="core",
                       help="core: DPCore, state store outside (default); top: DPPipeline with "
                            "the W*H store on chip")
    synth.add_argument("--synth-seeds", type=int, nargs="+", default=[1, 2, 3],
                       help="nextpnr placement seeds; Fmax is their median (default 1 2 3)")
    synth.add_argument("--device", default="hx8k", help="nextpnr-ice40 device (default hx8k)")
    synth.add_argument("--package", default="ct256", help="package (default ct256)")
    synth.add_argument("--freq", type=float, default=100.0, help="nextpnr target MHz (default 100)")
    synth.add_argument("--synth-size", type=int, default=128, metavar="N",
                       help="frame width = height the gateware is synthesised at (default 128, "
                            "the gateware's reference size; the Monte Carlo's scene size does "
                            "not change the widths, only the line buffers and counters)")
    synth.add_argument("--synth-cache", type=pathlib.Path, default=None,
                       help="cache folder (default ~/.cache/dptbd/synth)")


def main(args: argparse.Namespace) -> int:
    from dptbd.evaluation.compare import SynthOptions, compare_job
    from dptbd.hw.flow.synth import ToolNotFoundError
    from dptbd.sim.verilator import ToolMissingError

    synth = None if not args.synth else SynthOptions(
        variant=args.synth_variant, device=args.device, package=args.package,
        seeds=tuple(args.synth_seeds), target_mhz=args.freq, size=args.synth_size,
        cache_dir=args.synth_cache)
    try:
        outcome = compare_job(args.config, args.out, force=args.force, trials=args.trials,
                              seed=args.seed, snr=args.snr, bootstrap=args.bootstrap,
                              tie_rule=args.tie_rule,
                              workers=args.workers, progress=not args.no_progress,
                              rtl=args.rtl, synth=synth, scheduler=args.scheduler,
                              dashboard=args.dashboard)
    except (ToolNotFoundError, ToolMissingError) as exc:  # Yosys/nextpnr or Verilator missing
        print(f"dptbd compare: error: {exc}", file=sys.stderr)
        return 2
    print(outcome.text())
    return 0
