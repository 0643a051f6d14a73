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
import contextlib
import csv
import json
import os
import pathlib
import shutil
import tempfile
import time

from dptbd.evaluation.detectors.compare import SCENES, CompareResult, SceneSpec, run_comparison
from dptbd.evaluation.detectors._checks import DetectorError
from dptbd.evaluation.detectors.interface import (
    DETECTORS, DEFAULT_DETECTORS, detector_parameters, parse_detectors)
from dptbd.evaluation.stats import wilson_interval

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
    parser.add_argument("--jobs", type=int, default=2, help="worker processes (default 2); with "
                        "--scheduler: the workers the cluster must have")
    parser.add_argument("--scheduler", metavar="tcp://HOST:PORT", default=None,
                        help="run on this existing dask cluster (default: $DPTBD_SCHEDULER if "
                             "set, else local processes; docs/distributed.md)")
    parser.add_argument("--dashboard", action="store_true", help="print the dask dashboard's address")
    parser.add_argument("--out", type=pathlib.Path, metavar="DIR",
                        help="write table.md, table.csv, result.json and pd_vs_snr.png into this new "
                             "folder (must not exist unless --force)")
    parser.add_argument("--markdown", type=pathlib.Path, metavar="FILE.md",
                        help="also write the table to this Markdown file")
    parser.add_argument("--figure", type=pathlib.Path, metavar="FILE.png",
                        help="write the Pd-vs-SNR figure (PNG) here")
    parser.add_argument("--force", action="store_true",
                        help="overwrite --markdown/--figure files, and replace an --out folder written "
                             "by an earlier dptbd detectors run")


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
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


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


# ---- outputs ------------------------------------------------------------------------------

#: ``result.json``'s ``tool`` field: marks a folder that ``--force`` may replace
MARKER = "dptbd detectors"
OUT_FILES = ("table.md", "table.csv", "result.json", "pd_vs_snr.png")


def rows(res: CompareResult) -> list[dict]:
    """One record per (detector, SNR): counts, Pd, 95 % Wilson interval, threshold, noise false alarms."""
    out = []
    for name in res.detectors:
        fa = res.false_alarms[name]
        for s in res.snrs_db:
            c = res.detections[(name, s)]
            lo, hi = wilson_interval(c.hits, c.total)
            thr = res.thresholds[name]
            thr = thr[s] if isinstance(thr, dict) else thr
            out.append(dict(detector=name, snr_db=s, detections=c.hits, opportunities=c.total, pd=c.rate,
                            pd_lo=lo, pd_hi=hi, threshold=thr, noise_false_alarms=fa.hits,
                            noise_decisions=fa.total))
    return out


def _check_file(path: pathlib.Path | None, option: str, force: bool, suffix: str) -> None:
    if path is None:
        return
    if path.suffix.lower() != suffix:
        raise ValueError(f"{option} {path} must end in {suffix}")
    if path.is_dir():
        raise FileExistsError(f"{option} {path} is a folder")
    if not path.parent.resolve().is_dir():
        raise FileNotFoundError(f"{option} {path}: the folder {path.parent} does not exist")
    if (path.exists() or path.is_symlink()) and not force:
        raise FileExistsError(f"{option} {path} exists; pass --force to overwrite it")


def _is_out_folder(path: pathlib.Path) -> bool:
    try:
        return json.loads((path / "result.json").read_text()).get("tool") == MARKER
    except (OSError, ValueError, AttributeError):
        return False


def check_outputs(args: argparse.Namespace) -> None:
    """Refuse, before any work, every output that would overwrite something silently."""
    for path in (args.markdown, args.figure):
        if args.out is not None and path is not None and args.out.resolve() in path.resolve().parents:
            raise ValueError(f"{path} is inside --out {args.out}, which is written as a whole")
    _check_file(args.markdown, "--markdown", args.force, ".md")
    _check_file(args.figure, "--figure", args.force, ".png")
    out = args.out
    if out is None:
        return
    if not out.resolve().parent.is_dir():
        raise FileNotFoundError(f"--out {out}: the folder {out.parent} does not exist")
    if out.exists() or out.is_symlink():
        if not args.force:
            raise FileExistsError(f"--out {out} exists; pass --force to replace it, or choose another folder")
        if out.is_symlink() or not out.is_dir():
            raise FileExistsError(f"--out {out} exists and is not a folder; --force replaces only the "
                                  f"folder of an earlier dptbd detectors run")
        if any(out.iterdir()) and not _is_out_folder(out):
            raise FileExistsError(f"--out {out} is not the folder of an earlier dptbd detectors run "
                                  f"(no result.json from it); --force will not replace it")


@contextlib.contextmanager
def _staging(out: pathlib.Path):
    """A temporary folder beside ``out``, renamed to ``out`` only when everything is written."""
    tmp = pathlib.Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.resolve().parent))
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o777 & ~umask)  # mkdtemp makes it private (0700)
    try:
        yield tmp
        if out.exists():
            old = out.resolve().parent / f".{out.name}.old-{os.getpid()}"
            os.rename(out, old)
            os.rename(tmp, out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.rename(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def write_folder(res: CompareResult, out: pathlib.Path, table: str, note: str, arguments: dict) -> None:
    """``table.md``, ``table.csv``, ``result.json``, ``pd_vs_snr.png`` into ``out`` (atomically)."""
    records = rows(res)
    with _staging(out) as tmp:
        (tmp / "table.md").write_text(table + "\n\n" + note + "\n")
        with open(tmp / "table.csv", "w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(records[0]))
            writer.writeheader()
            writer.writerows(records)
        params = {k: (list(v) if isinstance(v, tuple) else v) for k, v in res.params.items()}
        (tmp / "result.json").write_text(json.dumps(
            dict(tool=MARKER, arguments=arguments, note=note, params=params, rows=records), indent=1,
            default=str) + "\n")
        plot(res, tmp / "pd_vs_snr.png")


def _write_text(path: pathlib.Path, text: str, force: bool) -> None:
    with open(path, "w" if force else "x") as fh:  # "x": never replace a file that appeared meanwhile
        fh.write(text)


def main(args: argparse.Namespace) -> int:
    check_outputs(args)
    names = parse_detectors(args.detectors)
    params = parse_settings(args.set)
    for name in params:
        if name not in names:
            raise DetectorError(f"--set names detector {name!r}, which is not in --detectors")
    snrs = args.snr if args.snr is not None else (
        [0.0, 3.0, 6.0, 9.0, 12.0, 15.0] if args.scene == "rd" else [4.0, 6.0, 8.0, 10.0, 12.0, 14.0])
    spec = SceneSpec(kind=args.scene, frames=args.frames, preset_snr_db=args.preset_snr_db)
    start = time.perf_counter()
    res = run_comparison(names, snrs_db=snrs, spec=spec, trials=args.trials,
                         noise_trials=args.noise_trials, false_alarm_rate=args.pfa,
                         matched=args.matched, seed=args.seed, jobs=args.jobs, params=params,
                         progress=True, scheduler=args.scheduler, dashboard=args.dashboard)
    table = format_table(res)
    p = res.params
    note = (f"{p['scene']} scenes, {p['frames']} frames, frames {p['first_frame']}..{p['frames'] - 1} scored, "
            f"{p['trials']} target scenes per SNR, {p['noise_trials']} noise-only scenes, "
            f"Pfa {p['false_alarm_rate']:g} per decision, preset SNR channel "
            f"{'matched' if p['matched'] else str(p['preset_snr_db']) + ' dB'}, gate {p['gate']} cell, "
            f"seed {p['seed']}, {time.perf_counter() - start:.0f} s"
            + (f"; --set {' '.join(args.set)}" if args.set else ""))
    print(table)
    print(note)
    if args.out is not None:
        arguments = {k: (str(v) if isinstance(v, pathlib.Path) else v)
                     for k, v in vars(args).items()
                     if not k.startswith("_") and k not in ("scheduler", "dashboard")}  # not results
        write_folder(res, args.out, table, note, arguments)
        print(f"wrote {args.out}/ ({', '.join(OUT_FILES)})")
    if args.markdown is not None:
        _write_text(args.markdown, table + "\n\n" + note + "\n", args.force)
    if args.figure is not None:
        if args.figure.exists() and not args.force:
            raise FileExistsError(f"--figure {args.figure} appeared during the run; not overwritten")
        plot(res, args.figure)
    return 0
