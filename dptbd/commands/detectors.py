"""``dptbd detectors``: papers 000/001/004's detectors and CA-CFAR on the same scenes, Pd vs SNR.

Every detector's threshold is set on the same noise-only scenes for the same false-alarm
probability per decision; then Pd (detections within one cell of the truth / scored
frames) is measured on the same seeded target scenes at each SNR. Prints a Markdown table
(Pd with 95 % Wilson intervals). ``--out DIR`` writes table (Markdown, CSV), result JSON
and figure together into a new folder; ``--markdown`` / ``--figure`` write single files.
Nothing that exists is overwritten without ``--force``, and every output path is checked
before the (long) run starts. ``docs/detectors.md`` §3 defines every choice.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import time

from dptbd.commands.options import add_execution_arguments
from dptbd.evaluation.detectors.pd_vs_snr import SCENES, SceneSpec, run_comparison
from dptbd.evaluation.detectors._checks import DetectorError
from dptbd.evaluation.detectors.adapters import (DETECTORS, DEFAULT_DETECTORS, detector_parameters,
                                                 parse_detectors)
from dptbd.evaluation.detectors.report import (DEFAULT_SNRS_DB, OUT_FILES, TOOL, describe_run,
                                               figure_pd_vs_snr, figure_roc, format_table,
                                               write_folder)

#: The ROC's further false-alarm rates per decision with ``--roc`` and no ``--roc-pfa``
DEFAULT_ROC_PFAS = (0.001, 0.003, 0.03, 0.1)
from dptbd.output_folder import (check_output_file, check_output_folder, check_still_new,
                                  write_new_text)

def _floats(text: str) -> list[float]:
    try:
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") from exc


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--detectors", default=",".join(DEFAULT_DETECTORS),
                        help=f"comma-separated, from: {', '.join(DETECTORS)} (default: all)")
    parser.add_argument("--scene", choices=SCENES, default="rd",
                        help="rd: paper 004 range-Doppler magnitudes (default); image: paper 000 64x64 images")
    parser.add_argument("--snr", type=_floats, default=None, metavar="DB,DB,...",
                        help="SNRs in dB (default rd: 0,3,6,9,12,15; image: 4,6,8,10,12,14)")
    parser.add_argument("--frames", type=int, default=20, help="frames per scene (default 20)")
    parser.add_argument("--trials", type=int, default=25, help="target scenes per SNR (default 25)")
    parser.add_argument("--noise-trials", type=int, default=80,
                        help="noise-only scenes that set the thresholds (default 80)")
    parser.add_argument("--pfa", type=float, default=0.01,
                        help="false-alarm probability per decision, all detectors (default 0.01)")
    parser.add_argument("--preset-snr-db", type=float, default=10.0,
                        help="SNR channel of the likelihood-based detectors (default 10 dB)")
    parser.add_argument("--matched", action="store_true",
                        help="set the SNR channel to each scene SNR and recalibrate per SNR")
    parser.add_argument("--set", action="append", default=[], metavar="DETECTOR.PARAM=VALUE",
                        help="a detector parameter, repeatable; VALUE is JSON (0.5, 8, true, "
                             "[[0,0.25,0],[0.25,0,0.25],[0,0.25,0]]), e.g. dp-penalty.alpha=0.85, "
                             "info.kernel=..., ca-cfar.n_ref=32 (docs/detectors.md §3.2)")
    parser.add_argument("--seed", type=int, default=6, help="base seed (default 6)")
    add_execution_arguments(parser, "--jobs", 2, "2")
    parser.add_argument("--out", type=pathlib.Path, metavar="DIR",
                        help="write table.md, table.csv, result.json and pd_vs_snr.png into this new "
                             "folder (must not exist unless --force)")
    parser.add_argument("--markdown", type=pathlib.Path, metavar="FILE.md",
                        help="also write the table to this Markdown file")
    parser.add_argument("--figure", type=pathlib.Path, metavar="FILE.png",
                        help="write the Pd-vs-SNR figure (PNG) here")
    parser.add_argument("--roc", type=pathlib.Path, metavar="FILE.png",
                        help="write the ROC (Pd against Pfa per decision, one panel per SNR) here; "
                             "its levels are --pfa and --roc-pfa")
    parser.add_argument("--roc-pfa", type=_floats, default=None, metavar="P,P,...",
                        help="further false-alarm rates per decision of the ROC, each calibrated on "
                             "the same noise-only scenes (default with --roc: 0.001,0.003,0.03,0.1)")
    parser.add_argument("--force", action="store_true",
                        help="overwrite --markdown/--figure files, and replace an --out folder written "
                             "by an earlier dptbd detectors run")


def parse_settings(items: list[str]) -> dict:
    """``["dp-penalty.alpha=0.85", ...]`` -> ``{"dp-penalty": {"alpha": 0.85}}``; values are JSON.

    Unknown detectors and parameters are refused here; values are checked by the detectors.
    """
    params: dict = {}
    for item in items:
        target, sep, raw = item.partition("=")
        name, dot, key = target.partition(".")
        if not sep or not dot or not name or not key:
            raise DetectorError(f"--set {item!r}: expected DETECTOR.PARAMETER=VALUE, e.g. dp-penalty.alpha=0.85")
        (name,) = parse_detectors([name])
        allowed = detector_parameters(name)
        if key not in allowed:
            raise DetectorError(f"--set {item!r}: detector {name!r} has no parameter {key!r}; "
                                f"it has: {', '.join(allowed)}")
        try:
            value = json.loads(raw)
        except ValueError:
            value = raw  # a plain string; the detector names it if it is wrong
        params.setdefault(name, {})[key] = value
    return params


def check_outputs(args: argparse.Namespace) -> None:
    """Refuse, before any work, every output that would overwrite something silently."""
    for path in (args.markdown, args.figure, args.roc):
        if args.out is not None and path is not None and args.out.resolve() in path.resolve().parents:
            raise ValueError(f"{path} is inside --out {args.out}, which is written as a whole")
    check_output_file(args.markdown, "--markdown", args.force, ".md")
    check_output_file(args.figure, "--figure", args.force, ".png")
    check_output_file(args.roc, "--roc", args.force, ".png")
    if args.out is not None:
        check_output_folder(args.out, args.force, marker="result.json", tool=TOOL)


def main(args: argparse.Namespace) -> int:
    check_outputs(args)
    names = parse_detectors(args.detectors)
    params = parse_settings(args.set)
    for name in params:
        if name not in names:
            raise DetectorError(f"--set names detector {name!r}, which is not in --detectors")
    snrs = args.snr if args.snr is not None else list(DEFAULT_SNRS_DB[args.scene])
    spec = SceneSpec(kind=args.scene, frames=args.frames, preset_snr_db=args.preset_snr_db)
    roc = args.roc_pfa if args.roc_pfa is not None else (list(DEFAULT_ROC_PFAS) if args.roc else [])
    roc = [p for p in roc if p != args.pfa]
    start = time.perf_counter()
    res = run_comparison(names, snrs_db=snrs, spec=spec, trials=args.trials,
                         noise_trials=args.noise_trials, false_alarm_rate=args.pfa,
                         matched=args.matched, seed=args.seed, jobs=args.jobs, params=params,
                         progress=True, scheduler=args.scheduler, dashboard=args.dashboard,
                         roc_pfas=roc)
    table = format_table(res)
    note = describe_run(res, time.perf_counter() - start, args.set)
    print(table)
    print(note)
    if args.out is not None:
        arguments = {k: (str(v) if isinstance(v, pathlib.Path) else v)   # where it ran is
                     for k, v in vars(args).items()                      # not a result
                     if not k.startswith("_") and k not in ("scheduler", "dashboard")}
        write_folder(res, args.out, table, note, arguments, args.force)
        print(f"wrote {args.out}/ ({', '.join(OUT_FILES)})")
    if args.markdown is not None:
        write_new_text(args.markdown, table + "\n\n" + note + "\n", args.force)
    if args.figure is not None:
        check_still_new(args.figure, "--figure", args.force)
        figure_pd_vs_snr(res, args.figure)
    if args.roc is not None:
        check_still_new(args.roc, "--roc", args.force)
        figure_roc(res, args.roc)
    return 0
