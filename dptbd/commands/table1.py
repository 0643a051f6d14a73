"""``dptbd table1``: reproduce paper 001's Table 1 by Monte Carlo and print it; the trials run
on every core, or a dask cluster (``--workers``, ``--scheduler``, ``docs/distributed.md``)."""

from __future__ import annotations

import argparse
import pathlib
import time

from dptbd.commands.options import add_execution_arguments
from dptbd.errors import ConfigError
from dptbd.evaluation.table1.experiment import run_table1
from dptbd.evaluation.table1.report import format_table
from dptbd.output_folder import check_output_file, write_new_text


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--trials", type=int, default=50, help="seeded scenes per setting (default 50)")
    parser.add_argument("--segment-frames", type=int, default=6, metavar="K",
                        help="frames per segment (default 6, see docs/table1.md)")
    parser.add_argument("--segment-stride", type=int, default=None, metavar="S",
                        help="frames between segment starts (default 4: 24 outputs from 100 "
                             "frames; with --rtl the default is K, the only stride the gateware "
                             "implements)")
    parser.add_argument("--seed", type=int, default=2003, help="base seed (default 2003)")
    parser.add_argument("--markdown", type=pathlib.Path, help="also write the table to this Markdown file")
    parser.add_argument("--force", action="store_true", help="overwrite --markdown if it exists")
    parser.add_argument("--rtl", action="store_true",
                        help="RTL in the loop: the two DP detectors accumulated on the compiled "
                             "gateware (Verilator), every output word and candidate list checked "
                             "against the golden model; needs stride = K (docs/table1.md)")
    add_execution_arguments(parser)


def main(args: argparse.Namespace) -> int:
    check_output_file(args.markdown, "--markdown", args.force, ".md")
    rtl = getattr(args, "rtl", False)
    stride = args.segment_stride
    chosen = ""
    if stride is None:
        stride = args.segment_frames if rtl else 4
        if rtl:
            chosen = (f" (--rtl: stride = K = {stride}, the gateware has one state store and "
                      f"implements non-overlapping segments only)")
    if rtl:
        from dptbd.sim.verilator import check_tools
        if stride != args.segment_frames:
            raise ConfigError(
                f"--rtl needs --segment-stride equal to --segment-frames "
                f"({args.segment_frames}): the gateware implements non-overlapping segments "
                f"only, got --segment-stride {stride}")
        check_tools()
    start = time.perf_counter()
    run = run_table1(args.trials, segment_frames=args.segment_frames, segment_stride=stride,
                     seed=args.seed, progress=True, rtl=rtl, workers=args.workers,
                     scheduler=args.scheduler, dashboard=args.dashboard)
    rows = run.rows
    table = format_table(rows)
    frames = rows[0].counts.frames // args.trials
    note = (f"{args.trials} trials per setting, K = {args.segment_frames}, stride "
            f"{stride}{chosen} ({frames} accumulated frames per trial), seed {args.seed}, "
            f"{time.perf_counter() - start:.0f} s"
            + (", DP detectors on the RTL" if rtl else ""))
    if run.rtl is not None:
        from dptbd.sim.rtl.trials import summary_line
        note += "\n" + summary_line(run.rtl)
    print(table)
    print(note)
    if args.markdown is not None:
        write_new_text(args.markdown, table + "\n\n" + note + "\n", args.force)
    return 0
