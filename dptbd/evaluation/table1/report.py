"""The table of ``dptbd table1``: paper 001's Table 1 beside the measured rows
(:func:`dptbd.evaluation.table1.experiment.run_table1`)."""

from __future__ import annotations

from dptbd.evaluation.stats import wilson_interval
from dptbd.evaluation.table1.experiment import DETECTORS, PAPER_TABLE1, Table1Row

__all__ = ["format_table"]


def format_table(rows: list[Table1Row]) -> str:
    """Paper 001's Table 1 beside the measured first-level Pd (95 % Wilson CI) and false points."""
    head = ["SNR", "V", "paper Pd", "paper false pts"]
    for name in DETECTORS:
        head += [f"{name} Pd [95% CI]", f"{name} false pts"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    by_setting: dict = {}
    for row in rows:
        by_setting.setdefault((row.snr, row.velocity), {})[row.detector] = row.counts
    for (snr, vel), counts in by_setting.items():
        paper = PAPER_TABLE1[(snr, vel)]
        cells = [f"{snr}", f"({vel[0]:g}, {vel[1]:g})", f"{paper[1]:.2f}", f"{paper[2]:.1f}"]
        for name in DETECTORS:
            c = counts[name]
            lo, hi = wilson_interval(c.detections, c.opportunities)
            cells += [f"{c.pd:.2f} [{lo:.2f}, {hi:.2f}]", f"{c.mean_false_points:.1f}"]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)
