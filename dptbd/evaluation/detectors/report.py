"""The tables, files and figure of ``dptbd detectors`` (:func:`.compare.run_comparison`'s result).
"""

from __future__ import annotations

import contextlib
import csv
import json
import os
import pathlib
import shutil
import tempfile

from dptbd.evaluation.detectors.compare import CompareResult
from dptbd.evaluation.stats import wilson_interval

__all__ = ["format_table", "plot", "rows", "write_folder", "MARKER", "OUT_FILES"]


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


def _is_out_folder(path: pathlib.Path) -> bool:
    try:
        return json.loads((path / "result.json").read_text()).get("tool") == MARKER
    except (OSError, ValueError, AttributeError):
        return False


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
