"""The tables, files and figure of ``dptbd detectors``: a :func:`.compare.run_comparison`
result as a Markdown table, CSV records, ``result.json`` and the Pd-vs-SNR figure.
"""

from __future__ import annotations

import csv
import json
import pathlib

from dptbd.evaluation.detectors.pd_vs_snr import CompareResult
from dptbd.evaluation.stats import wilson_interval
from dptbd.figures import new_figure, save_figure
from dptbd.output_folder import staged_folder

__all__ = ["DEFAULT_SNRS_DB", "TOOL", "OUT_FILES", "format_table", "figure_pd_vs_snr",
           "describe_run", "rows", "write_folder"]

#: SNRs (dB) of each scene kind when none are given
DEFAULT_SNRS_DB = {"rd": (0.0, 3.0, 6.0, 9.0, 12.0, 15.0), "image": (4.0, 6.0, 8.0, 10.0, 12.0, 14.0)}


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


def figure_pd_vs_snr(res: CompareResult, path: pathlib.Path) -> None:
    """Pd (95 % Wilson interval bars) against SNR, one line per detector, as PNG."""
    fig, ax = new_figure(6.4, 4.2, dpi=100)
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
        (tmp / "result.json").write_text(json.dumps(
            dict(tool=TOOL, arguments=arguments, note=note, params=params, rows=records), indent=1,
            default=str) + "\n")
        figure_pd_vs_snr(res, tmp / "pd_vs_snr.png")
    return out
