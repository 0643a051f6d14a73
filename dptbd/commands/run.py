"""``dptbd run``: the main job — FPGA stage, DSP stage, table and figures in an output folder.

With no arguments it runs the built-in scenario, paper 001's second experiment (001 §4:
128 x 128, 100 frames, SNR 2.0, two targets starting at (30, 100) with V = (0.8, -0.4) and
at (54, 40) with V = (0.4, 0.6), 0.2 % false-alarm threshold):

1. **FPGA stage** — the bit-accurate golden model of the direction-weighted DP (eqs (8)–(11),
   K = 6, segments back to back as the gateware runs them, a 12-bit ADC at 16 LSB per grey
   level as in ``dptbd.evaluation.table1.experiment``) and the constant-false-alarm-count
   histogram threshold (33 candidate points per accumulated frame). ``--rtl`` also runs the
   generated Verilog of the whole FPGA stage (``dptbd_seg``: DP pipeline + segmenter) on every
   frame (``--rtl-frames N``: the first N only) and stops unless every output word is bit for
   bit identical to the model. The simulator is Verilator by default
   (:mod:`dptbd.sim.verilator`, a cached compiled build: a few seconds for the built-in scene
   once built); ``--rtl-simulator icarus`` keeps the cocotb + Icarus bench (about 12 min for
   it). The printed summary and ``summary.json`` (``rtl``) say which simulator, which frames,
   the words compared, the cycles and the simulator's speed. A frame whose state does not fit
   in the block RAM of the largest device the flow builds for (640 x 512, 4096 x 256) runs
   through ``dptbd_axi --state-store axi`` (``dptbd_dp`` with ``--lists ideal``), its state
   in the Verilator harness's AXI4 memory model, and the summary adds the cycles per pixel
   (``--rtl-state-store``: ``auto``, the default, ``chip`` or ``axi``;
   :mod:`dptbd.evaluation.run.rtl`).
2. **DSP stage** — the fixed-capacity track association of 001 §3
   (:mod:`dptbd.dsp.association`), candidates' paths recovered by backtracking the
   direction maps (:mod:`dptbd.dsp.backtrack`); ``--dsp c`` runs it on the C firmware
   (:mod:`dptbd.dsp.c_tracker`), same tracks bit for bit.

It writes, into a new output folder (default ``dptbd-run``): ``table.md``/``table.csv``
(001's Table 1 form), ``tracks.csv`` (a position per frame of every confirmed track),
``candidates.csv``, ``summary.json`` (everything, machine-readable, including the bits per
segment the FPGA hands the DSP against the whole image, also printed;
``docs/arithmetic.md`` §6.6), ``scenario.toml``
(the effective scenario: rerun with ``--scenario``) and three figures: ``raw_frame.png``,
``accumulated.png``, ``tracks.png``. Everything is written into a hidden temporary folder
beside the output folder and renamed at the end, so an error leaves nothing behind.

Recorded data (``--input`` or ``[input]`` in a scenario file: ``.npy``, ``.npz``, or a
folder of 8/16-bit PNG/TIFF frames) has no ground truth: the table lists the tracks. The run
is named after the input file or folder unless the scenario file names it.
"""

from __future__ import annotations

import argparse
import functools
import pathlib
import sys
import time

from dptbd.commands.options import add_simulator_arguments
from dptbd.dsp.c_tracker import DSP_IMPLEMENTATIONS, FirmwareError
from dptbd.dsp.firmware import FirmwareBuildError, find_compiler
from dptbd.evaluation.run.job import effective_scenario, run_job
from dptbd.evaluation.run.report import RUN_FILES, TOOL, write_run_folder
from dptbd.evaluation.run.rtl import STATE_STORES, RtlCheck, RtlError, rtl_tools_missing
from dptbd.output_folder import check_output_folder


def add_arguments(parser: argparse.ArgumentParser) -> None:
    src = parser.add_argument_group("what to run")
    src.add_argument("--scenario", type=pathlib.Path, metavar="FILE.toml",
                     help="scenario file (TOML; see dptbd/evaluation/run/scenario.py); default: "
                          "paper 001's second experiment")
    src.add_argument("--input", type=pathlib.Path, metavar="PATH",
                     help="recorded data instead of a simulated scene: .npy or .npz (T, H, W) "
                          "integers, or a folder of 8/16-bit PNG or TIFF frames")
    src.add_argument("--npz-key", metavar="KEY", help="the array to use in an .npz input")
    src.add_argument("--seed", type=int, default=None, help="scene seed (default 0)")
    src.add_argument("--snr", type=float, default=None,
                     help="SNR of every target as paper 001 defines it (default 2.0)")
    src.add_argument("--target", action="append", default=None, metavar="ROW,COL,VROW,VCOL[,SNR]",
                     help="a target (start row, col; velocity rows, cols per frame); repeat "
                          "for several; replaces the scenario's targets")
    dp = parser.add_argument_group("FPGA stage")
    dp.add_argument("--segment-frames", type=int, default=None, metavar="K",
                    help="frames per segment (default 6)")
    dp.add_argument("--segment-stride", type=int, default=None, metavar="S",
                    help="frames between segment starts (default K: what the gateware does)")
    dp.add_argument("--lists", choices=("gateware", "ideal"), default=None,
                    help="candidate lists handed to the DSP: gateware (default: what the "
                         "segmenter emits, threshold from the previous segment's histogram) or "
                         "ideal (each segment's own histogram, what a two-pass segmenter gives; "
                         "docs/arithmetic.md §6.1)")
    dp.add_argument("--rtl", action="store_true",
                    help="also simulate the generated Verilog on every frame (--rtl-frames) "
                         "and check it bit for bit against the model: the whole FPGA stage "
                         "(dptbd_seg: DP + segmenter, every candidate-list word) with gateware "
                         "lists, the DP pipeline (dptbd_dp, every (E, d) word) with --lists "
                         "ideal")
    add_simulator_arguments(dp, prefix="rtl-", of=" of --rtl")
    dp.add_argument("--rtl-frames", type=int, default=0, metavar="N",
                    help="frames to simulate with --rtl (default 0: all; N: the first N, the "
                         "rest come from the model only, as the summary says)")
    dp.add_argument("--rtl-state-store", choices=STATE_STORES, default="auto",
                    help="where the simulated design keeps its state with --rtl: chip "
                         "(dptbd_seg / dptbd_dp, block RAM), axi (dptbd_axi / dptbd_dp built "
                         "with --state-store axi, its state in the Verilator harness's AXI4 "
                         "memory; Verilator only) or auto (default: axi when the frame's state "
                         "exceeds the block RAM of the largest device the flow builds for, "
                         "e.g. 640 x 512; chip otherwise)")
    dsp = parser.add_argument_group("DSP stage")
    dsp.add_argument("--dsp", choices=DSP_IMPLEMENTATIONS, default="python",
                     help="the track association: python (default, the readable reference "
                          "model) or c (the portable C99 firmware, built with the system C "
                          "compiler on first use; same tracks bit for bit; "
                          "docs/dsp_firmware.md)")
    out = parser.add_argument_group("output")
    out.add_argument("--out", type=pathlib.Path, default=pathlib.Path("dptbd-run"), metavar="DIR",
                     help="output folder, must not exist (default dptbd-run)")
    out.add_argument("--force", action="store_true",
                     help="replace an existing output folder of an earlier dptbd run")
    out.add_argument("--no-progress", action="store_true", help="no progress bars")


def build_scenario(args: argparse.Namespace):
    """The effective scenario: file (or built-in) plus command-line options, checked."""
    return effective_scenario(
        args.scenario, input_path=args.input, npz_key=args.npz_key, seed=args.seed,
        snr=args.snr, targets=args.target, segment_frames=args.segment_frames,
        segment_stride=args.segment_stride, lists=args.lists)


def _progress(disabled: bool):
    if disabled:
        return None
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover
        return None
    return functools.partial(tqdm, disable=None, unit="segment", file=sys.stderr)


def main(args: argparse.Namespace) -> int:
    """Run the job; an unreadable file or an unwritable folder is a clear error (exit 2).

    Every other refusal (bad scenario, data or option) raises an exception that the
    command line turns into ``dptbd run: error: …`` and exit status 2; in every case
    nothing is left in (or beside) the output folder
    (:func:`dptbd.output_folder.staged_folder`).
    """
    try:
        return _main(args)
    except (FileNotFoundError, FileExistsError):
        raise                                 # the command line reports these itself
    except OSError as exc:                    # permissions, disk full, …: no traceback
        what = f" {exc.filename}" if getattr(exc, "filename", None) else ""
        print(f"dptbd run: error: cannot read or write{what}: {exc.strerror or exc}",
              file=sys.stderr)
        return 2


def _main(args: argparse.Namespace) -> int:
    start = time.perf_counter()
    scenario = build_scenario(args)
    check_output_folder(args.out, args.force, marker="summary.json", tool=TOOL)  # before any work
    if args.rtl_frames is not None and args.rtl_frames < 0:
        raise ValueError(f"--rtl-frames must be an integer in [0, inf), got {args.rtl_frames}")
    rtl = None
    if args.rtl:                              # a missing simulator: refused before any work
        why = rtl_tools_missing(args.rtl_simulator)
        if why is not None:
            print(f"dptbd run: error: {why}", file=sys.stderr)
            return 2
        rtl = RtlCheck(args.rtl_simulator, args.rtl_frames, args.rtl_build_dir,
                       args.rtl_state_store)
    try:
        if args.dsp == "c":
            find_compiler()                   # a missing C compiler: refused before any work
        result = run_job(scenario, rtl=rtl, dsp=args.dsp, progress=_progress(args.no_progress),
                         log=functools.partial(print, flush=True))
    except (FirmwareBuildError, FirmwareError) as exc:
        print(f"dptbd run: error: --dsp c: {exc}", file=sys.stderr)
        return 2
    except RtlError as exc:
        print(f"dptbd run: error: {exc}", file=sys.stderr)
        return 1
    write_run_folder(result, args.out, args.force)
    print()
    print(result.table_text)
    print()
    print(f"wrote {args.out}/ ({', '.join(RUN_FILES)}) in {time.perf_counter() - start:.1f} s")
    return 0
