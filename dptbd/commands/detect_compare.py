"""``dptbd detectors``: papers 000/001/004's detectors and CA-CFAR on the same scenes, Pd vs SNR.

Every detector's threshold is set on the same noise-only scenes for the same false-alarm
probability per decision; then Pd (detections within one cell of the truth / scored
frames) is measured on the same seeded target scenes at each SNR. Prints a Markdown table
(Pd with 95 % Wilson intervals), optionally writes it and a Pd-vs-SNR figure.
``docs/detectors.md`` §3 defines every choice.
"""

from __future__ import annotations

import argparse
import pathlib
import time

from dptbd.model.detectors.compare import SCENES, CompareResult, SceneSpec, run_comparison
from dptbd.model.detectors.interface import DETECTORS, DEFAULT_DETECTORS, parse_detectors
from dptbd.model.stats import wilson_interval

HELP = "compare papers 000/001/004's detectors and CA-CFAR at equal false-alarm rate (Pd vs SNR)"


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
                        help="SNRs in dB (default rd: 0,3,6,9,12,15; image: 0,2,4,6,8)")
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
    parser.add_argument("--seed", type=int, default=6, help="base seed (default 6)")
    parser.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    parser.add_argument("--markdown", type=pathlib.Path, help="also write the table to this Markdown file")
    parser.add_argument("--figure", type=pathlib.Path, help="write the Pd-vs-SNR figure (PNG) here")
    parser.add_argument("--force", action="store_true", help="overwrite --markdown/--figure if they exist")


def format_table(res: CompareResult) -> str:
    """Pd [95 % CI] per detector (rows) and SNR (columns), plus threshold and measured Pfa."""
    head = ["detector"] + [f"{s:g} dB" for s in res.snrs_db] + ["threshold", "noise false alarms"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for name in res.detectors:
        cells = [f"`{name}`"]
        for s in res.snrs_db:
            c = res.detections[(name, s)]
            lo, hi = wilson_interval(c.hits, c.total)
            cells.append(f"{c.rate:.2f} [{lo:.2f}, {hi:.2f}]")
        thr = res.thresholds[name]
        cells.append("per SNR" if isinstance(thr, dict) else f"{thr:.4g}")
        fa = res.false_alarms[name]
        cells.append(f"{fa.hits}/{fa.total} = {fa.rate:.4f}")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def plot(res: CompareResult, path: pathlib.Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=100)
    for name in res.detectors:
        pd = [res.detections[(name, s)].rate for s in res.snrs_db]
        ci = [wilson_interval(res.detections[(name, s)].hits, res.detections[(name, s)].total)
              for s in res.snrs_db]
        lo = [p - c[0] for p, c in zip(pd, ci)]
        hi = [c[1] - p for p, c in zip(pd, ci)]
        ax.errorbar(res.snrs_db, pd, yerr=[lo, hi], marker="o", ms=3, capsize=2, label=name)
    p = res.params
    ax.set_xlabel("SNR (dB)")
    ax.set_ylabel("Pd (per scored frame)")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(alpha=0.3)
    ax.set_title(f"{p['scene']} scenes, {p['frames']} frames, Pfa {p['false_alarm_rate']:g} per decision",
                 fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def main(args: argparse.Namespace) -> int:
    for path in (args.markdown, args.figure):
        if path is not None and path.exists() and not args.force:
            raise FileExistsError(f"{path} exists; pass --force to overwrite it")
    names = parse_detectors(args.detectors)
    snrs = args.snr if args.snr is not None else (
        [0.0, 3.0, 6.0, 9.0, 12.0, 15.0] if args.scene == "rd" else [0.0, 2.0, 4.0, 6.0, 8.0])
    spec = SceneSpec(kind=args.scene, frames=args.frames, preset_snr_db=args.preset_snr_db)
    start = time.perf_counter()
    res = run_comparison(names, snrs_db=snrs, spec=spec, trials=args.trials,
                         noise_trials=args.noise_trials, false_alarm_rate=args.pfa,
                         matched=args.matched, seed=args.seed, jobs=args.jobs, progress=True)
    table = format_table(res)
    p = res.params
    note = (f"{p['scene']} scenes, {p['frames']} frames, frames {p['first_frame']}..{p['frames'] - 1} scored, "
            f"{p['trials']} target scenes per SNR, {p['noise_trials']} noise-only scenes, "
            f"Pfa {p['false_alarm_rate']:g} per decision, preset SNR channel "
            f"{'matched' if p['matched'] else str(p['preset_snr_db']) + ' dB'}, gate {p['gate']} cell, "
            f"seed {p['seed']}, {time.perf_counter() - start:.0f} s")
    print(table)
    print(note)
    if args.markdown is not None:
        args.markdown.write_text(table + "\n\n" + note + "\n")
    if args.figure is not None:
        plot(res, args.figure)
    return 0
