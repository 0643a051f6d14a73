"""The tables, files and figure of ``dptbd detectors``: a :func:`.compare.run_comparison`
result as a Markdown table, CSV records, ``result.json`` and the Pd-vs-SNR figure.
"""

from __future__ import annotations

import csv
import math
import pathlib

import numpy as np

from dptbd.evaluation.detectors.pd_vs_snr import CompareResult
from dptbd.evaluation.stats import wilson_interval
from dptbd.figures import new_figure, save_figure
from dptbd.output_folder import json_text, staged_folder

__all__ = ["DEFAULT_SNRS_DB", "TOOL", "OUT_FILES", "pd_interval", "format_table", "error_bars",
           "figure_pd_vs_snr", "describe_run", "rows", "roc_rows", "figure_roc", "write_folder"]

#: SNRs (dB) of each scene kind when none are given
DEFAULT_SNRS_DB = {"rd": (0.0, 3.0, 6.0, 9.0, 12.0, 15.0), "image": (4.0, 6.0, 8.0, 10.0, 12.0, 14.0)}


def pd_interval(res: CompareResult, name: str, snr: float) -> tuple[float, float, float]:
    """``(Pd, lo, hi)`` of one detector at one SNR, its 95 % Wilson interval: the one the
    table prints, the records hold and the figure draws. ``lo <= Pd <= hi``; all three NaN
    when the detector had no scored frame at that SNR (no estimate, no interval)."""
    c = res.detections[(name, snr)]
    lo, hi = wilson_interval(c.hits, c.total)
    return c.rate, lo, hi


def format_table(res: CompareResult) -> str:
    """Pd [95 % CI] per detector (rows) and SNR (columns), plus threshold and measured Pfa;
    "no scored frame" where a detector had none at that SNR."""
    head = ["detector"] + [f"{s:g} dB" for s in res.snrs_db] + ["threshold", "noise false alarms"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for name in res.detectors:
        cells = [f"`{name}`"]
        for s in res.snrs_db:
            pd, lo, hi = pd_interval(res, name, s)
            cells.append("no scored frame" if math.isnan(pd) else f"{pd:.2f} [{lo:.2f}, {hi:.2f}]")
        thr = res.thresholds[name]
        cells.append("per SNR" if isinstance(thr, dict) else f"{thr:.4g}")
        fa = res.false_alarms[name]
        cells.append(f"{fa.hits}/{fa.total} = {fa.rate:.4f}")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def error_bars(res: CompareResult, name: str) -> tuple[list[float], list[float], list[float]]:
    """One detector's points and bars of the figure: Pd per SNR and the distances below and
    above it to the bounds of :func:`pd_interval`. Where Pd is undefined (no scored frame)
    the point is NaN (not drawn) and both distances are 0 (no bar)."""
    pd, below, above = [], [], []
    for s in res.snrs_db:
        p, lo, hi = pd_interval(res, name, s)
        pd.append(p)
        below.append(0.0 if math.isnan(p) else p - lo)
        above.append(0.0 if math.isnan(p) else hi - p)
    return pd, below, above


def figure_pd_vs_snr(res: CompareResult, path: pathlib.Path) -> None:
    """Pd (95 % Wilson interval bars, :func:`error_bars`) against SNR, one line per detector,
    as PNG."""
    fig, ax = new_figure(6.4, 4.2, dpi=100)
    for name in res.detectors:
        pd, below, above = error_bars(res, name)
        ax.errorbar(res.snrs_db, pd, yerr=[below, above], marker="o", ms=3, capsize=2, label=name)
    p = res.params
    ax.set_xlabel("SNR (dB)")
    ax.set_ylabel("Pd (per scored frame)")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(alpha=0.3)
    ax.set_title(f"{p['scene']} scenes, {p['frames']} frames, Pfa {p['false_alarm_rate']:g} per decision",
                 fontsize=10)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    save_figure(fig, path)


def describe_run(res: CompareResult, seconds: float, settings: list[str] = ()) -> str:
    """The line under the table: scenes, scoring, calibration, preset channel, seed, time and
    the ``--set`` parameters."""
    p = res.params
    return (f"{p['scene']} scenes, {p['frames']} frames, frames {p['first_frame']}..{p['frames'] - 1} scored, "
            f"{p['trials']} target scenes per SNR, {p['noise_trials']} noise-only scenes, "
            f"Pfa {p['false_alarm_rate']:g} per decision, preset SNR channel "
            f"{'matched' if p['matched'] else str(p['preset_snr_db']) + ' dB'}, gate {p['gate']} cell, "
            f"seed {p['seed']}, {seconds:.0f} s"
            + (f"; --set {' '.join(settings)}" if settings else ""))


#: ``result.json``'s ``tool`` field: marks a folder that ``--force`` may replace
TOOL = "dptbd detectors"
#: The files of the ``--out`` folder
OUT_FILES = ("table.md", "table.csv", "result.json", "pd_vs_snr.png")


def rows(res: CompareResult) -> list[dict]:
    """One record per (detector, SNR): counts, Pd, 95 % Wilson interval (:func:`pd_interval`;
    NaN when no frame was scored), threshold, noise false alarms."""
    out = []
    for name in res.detectors:
        fa = res.false_alarms[name]
        for s in res.snrs_db:
            c = res.detections[(name, s)]
            pd, lo, hi = pd_interval(res, name, s)
            thr = res.thresholds[name]
            thr = thr[s] if isinstance(thr, dict) else thr
            out.append(dict(detector=name, snr_db=s, detections=c.hits, opportunities=c.total, pd=pd,
                            pd_lo=lo, pd_hi=hi, threshold=thr, noise_false_alarms=fa.hits,
                            noise_decisions=fa.total))
    return out


def roc_rows(res: CompareResult) -> list[dict]:
    """One record per (detector, SNR, false-alarm rate per decision): the operating point
    and every ROC level (:func:`.pd_vs_snr.run_comparison`'s ``roc_pfas``), in rate order;
    Pd with its 95 % Wilson interval (NaN without a scored frame)."""
    out = []
    for name in res.detectors:
        for s in res.snrs_db:
            levels = [(res.params["false_alarm_rate"], res.thresholds[name], res.false_alarms[name],
                       res.detections[(name, s)])]
            levels += list(zip(res.roc_pfas, res.roc_thresholds.get(name, ()),
                               res.roc_false_alarms.get(name, ()), res.roc_detections.get((name, s), ())))
            for pfa, thr, fa, c in sorted(levels, key=lambda x: x[0]):
                lo, hi = wilson_interval(c.hits, c.total)
                out.append(dict(detector=name, snr_db=s, false_alarm_rate=pfa,
                                threshold=thr[s] if isinstance(thr, dict) else thr,
                                noise_false_alarms=fa.hits, noise_decisions=fa.total,
                                detections=c.hits, opportunities=c.total, pd=c.rate, pd_lo=lo,
                                pd_hi=hi))
    return out


def figure_roc(res: CompareResult, path: pathlib.Path) -> None:
    """ROC as PNG: Pd (95 % Wilson bars) against the false-alarm rate per decision (log
    axis), one panel per SNR, one line per detector (:func:`roc_rows`)."""
    records = roc_rows(res)
    n = len(res.snrs_db)
    cols = min(n, 3)
    rows = -(-n // cols)
    fig, axes = new_figure(3.2 * cols, 3.0 * rows + 0.4, nrows=rows, ncols=cols, dpi=100)
    axes = list(np.ravel(axes))
    for ax in axes[n:]:
        ax.set_visible(False)
    for ax, s in zip(axes, res.snrs_db):
        for name in res.detectors:
            mine = [r for r in records if r["detector"] == name and r["snr_db"] == s]
            pd = [r["pd"] for r in mine]
            below = [0.0 if math.isnan(r["pd"]) else r["pd"] - r["pd_lo"] for r in mine]
            above = [0.0 if math.isnan(r["pd"]) else r["pd_hi"] - r["pd"] for r in mine]
            ax.errorbar([r["false_alarm_rate"] for r in mine], pd, yerr=[below, above], marker="o",
                        ms=3, capsize=2, label=name)
        ax.set_xscale("log")
        ax.set_ylim(-0.02, 1.02)
        ax.grid(alpha=0.3, which="both")
        ax.set_title(f"{s:g} dB", fontsize=10)
        ax.set_xlabel("Pfa per decision")
    for ax in axes[::cols]:
        ax.set_ylabel("Pd (per scored frame)")
    axes[n - 1].legend(fontsize=7, loc="best")
    p = res.params
    fig.suptitle(f"ROC, {p['scene']} scenes, {p['frames']} frames, {p['noise_trials']} noise-only "
                 f"scenes", fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)


def write_folder(res: CompareResult, out: pathlib.Path, table: str, note: str, arguments: dict,
                 force: bool = False) -> pathlib.Path:
    """``table.md``, ``table.csv``, ``result.json``, ``pd_vs_snr.png`` into ``out``, all or
    nothing (:func:`dptbd.output_folder.staged_folder`: ``force`` replaces only an earlier
    ``dptbd detectors`` folder)."""
    records = rows(res)
    with staged_folder(out, force, marker="result.json", tool=TOOL) as tmp:
        (tmp / "table.md").write_text(table + "\n\n" + note + "\n")
        with open(tmp / "table.csv", "w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(records[0]))
            writer.writeheader()
            writer.writerows(records)
        params = {k: (list(v) if isinstance(v, tuple) else v) for k, v in res.params.items()}
        result = dict(tool=TOOL, arguments=arguments, note=note, params=params, rows=records)
        if res.roc_pfas:
            result["roc"] = roc_rows(res)
        (tmp / "result.json").write_text(json_text(result, indent=1, default=str) + "\n")
        figure_pd_vs_snr(res, tmp / "pd_vs_snr.png")
    return out
