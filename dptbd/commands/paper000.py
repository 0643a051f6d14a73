"""``dptbd paper000``: paper 000's §5.1 / §5.2 scenes and SNR-gain curve through its DP
variants in fixed point — on the gateware (``--rtl``, Verilator, every state checked bit for
bit against the golden model) or on the golden model — against the float variants, on the
same scenes with paired intervals (``docs/detectors.md`` §1.6).

Prints the tables; ``--json FILE`` writes the summary (strict JSON: a value without a finite
number, such as the interval of one scene or an SNR not reached in the grid, is ``null``),
``--markdown FILE`` the tables (neither overwritten without ``--force``, both checked before
the run).
"""

from __future__ import annotations

import argparse
import pathlib

from dptbd.commands.options import add_execution_arguments
from dptbd.evaluation.detectors.paper000 import CASES
from dptbd.evaluation.paper000.experiment import GAIN_DPS, Paper000Spec, run_paper000
from dptbd.evaluation.paper000.report import markdown, summarise
from dptbd.output_folder import check_output_file, json_text, write_new_text


def _names(text: str) -> tuple[str, ...]:
    return tuple(v.strip() for v in text.split(";") if v.strip())


def _floats(text: str) -> tuple[float, ...]:
    try:
        return tuple(float(v) for v in text.split(",") if v.strip())
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") from exc


def add_arguments(parser: argparse.ArgumentParser) -> None:
    spec = Paper000Spec()
    parser.add_argument("--rtl", action="store_true",
                        help="fixed point on the compiled gateware (Verilator), every state "
                             "word checked against the golden model (default: golden model)")
    parser.add_argument("--cases", type=_names, default=spec.cases, metavar="LABEL;LABEL",
                        help=f"§5.1/§5.2 cases, ';'-separated (default: all: "
                             f"{'; '.join(c.label for c in CASES)}; '' for none)")
    parser.add_argument("--seeds", type=int, default=spec.seeds,
                        help=f"scenes per case, seeds 0 … N-1 (default {spec.seeds})")
    parser.add_argument("--gain", type=_names, default=spec.gain, metavar="DP;DP",
                        help=f"DPs of the SNR-gain curve (default: all: {'; '.join(GAIN_DPS)}; "
                             f"'' for none)")
    parser.add_argument("--snr", type=_floats, default=spec.gain_snrs_db, metavar="DB,DB,...",
                        help="SNRs of the gain curve in dB (default 0,1,...,15)")
    parser.add_argument("--trials", type=int, default=spec.gain_trials,
                        help=f"target scenes per SNR (default {spec.gain_trials})")
    parser.add_argument("--noise-trials", type=int, default=spec.noise_trials,
                        help=f"noise-only scenes that set each threshold (default {spec.noise_trials})")
    parser.add_argument("--pfa", type=float, default=spec.pfa,
                        help=f"per-cell false-alarm probability (default {spec.pfa:g})")
    parser.add_argument("--frames", type=int, default=spec.frames,
                        help=f"frames per scene (default {spec.frames})")
    parser.add_argument("--chunk", type=int, default=spec.chunk,
                        help=f"scenes per task (default {spec.chunk})")
    add_execution_arguments(parser)
    parser.add_argument("--json", type=pathlib.Path, metavar="FILE.json",
                        help="write the summary (every figure of the tables) here")
    parser.add_argument("--markdown", type=pathlib.Path, metavar="FILE.md",
                        help="write the tables here")
    parser.add_argument("--force", action="store_true", help="overwrite --json / --markdown")


def main(args: argparse.Namespace) -> int:
    check_output_file(args.json, "--json", args.force, ".json")
    check_output_file(args.markdown, "--markdown", args.force, ".md")
    spec = Paper000Spec(engine="rtl" if args.rtl else "model", cases=args.cases, seeds=args.seeds,
                        gain=args.gain, gain_snrs_db=args.snr, gain_trials=args.trials,
                        noise_trials=args.noise_trials, pfa=args.pfa, frames=args.frames,
                        chunk=args.chunk)
    result = run_paper000(spec, workers=args.workers, scheduler=args.scheduler,
                          dashboard=args.dashboard, progress=True)
    summary = summarise(result)
    text = markdown(summary)
    print(text)
    print(f"\n{spec.engine} engine, {result.workers} worker(s), {result.seconds:.1f} s")
    if args.json is not None:
        write_new_text(args.json, json_text(summary, indent=1, default=str) + "\n", args.force)
    if args.markdown is not None:
        write_new_text(args.markdown, text + "\n", args.force)
    return 0
