"""The ``dptbd`` command line: one sub-command per job a user comes for.

Each sub-command lives in ``dptbd.commands.<name>`` and provides ``add_arguments(parser)``
and ``main(args) -> int``.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from dptbd.errors import ConfigError

#: sub-command name -> (module, one-line help)
COMMANDS = {
    "run": ("dptbd.commands.run", "run the main job on the built-in scenario (or a scenario file)"),
    "table1": ("dptbd.commands.table1", "reproduce paper 001's Table 1 (Monte Carlo, first-level Pd)"),
    "sim": ("dptbd.commands.sim",
            "simulate the generated Verilog on a scene (Verilator, or cocotb + Icarus): bit-exact "
            "check and cycle count"),
    "verilog": ("dptbd.commands.verilog", "write the pipeline's Verilog and manifest JSON"),
    "verify": ("dptbd.commands.verify",
               "verification campaign: >= 10^8 RTL words on Verilator against the golden model"),
    "compare": ("dptbd.commands.compare",
                "fixed vs float detection: Monte Carlo Pd/Pfa, SNR loss, bit-width sweep with iCE40 cost"),
    "detectors": ("dptbd.commands.detectors",
                  "papers 000/001/004's detectors and CA-CFAR on the same scenes at equal Pfa (Pd vs SNR)"),
    "paper000": ("dptbd.commands.paper000",
                 "paper 000's scenes and SNR-gain curve through its DP variants in fixed point (--rtl: "
                 "on the gateware, bit-exact checked) against float, paired intervals"),
}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="dptbd",
        description="Fixed-point DP track-before-detect: golden model, gateware, verification.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, (module, help_text) in COMMANDS.items():
        cmd = sub.add_parser(name, help=help_text, description=help_text)
        importlib.import_module(module).add_arguments(cmd)
        cmd.set_defaults(_module=module)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(importlib.import_module(args._module).main(args) or 0)
    except (ConfigError, ValueError, TypeError, FileNotFoundError, FileExistsError) as exc:
        print(f"dptbd {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
