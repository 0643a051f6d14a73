"""Statistics and Markdown tables of ``dptbd paper000``
(:mod:`dptbd.evaluation.paper000.experiment`).

Fixed against float as ``dptbd compare`` does it: per scene (the cluster) the two outcomes
on the same scene, the paired difference with its 95 % interval
(:func:`dptbd.evaluation.compare.report.paired_difference`; for a real-valued measurement
with one "trial" per scene this is the mean difference and its standard error), Pd with
Wilson intervals (:func:`dptbd.evaluation.stats.wilson_interval`) and the SNR loss at
Pd 0.5 and 0.9 with its paired-bootstrap interval over scenes
(:func:`dptbd.evaluation.snr_loss.bootstrap_losses`).
"""

from __future__ import annotations

import math

import numpy as np

from dptbd.evaluation.compare.report import paired_difference
from dptbd.evaluation.snr_loss import bootstrap_losses
from dptbd.evaluation.stats import wilson_interval

__all__ = ["CASE_METRICS", "DETECTION_METRICS", "LOSS_LEVELS", "summarise", "markdown"]

#: Per-scene measurements of a §5.1/§5.2 case that are compared (besides false tracks at V_T).
CASE_METRICS = ("target", "noise_max", "target_is_max", "target_rank")
LOSS_LEVELS = (0.5, 0.9)


def _paired(fixed, flt) -> dict:
    fixed = np.asarray(fixed, dtype=np.float64)
    flt = np.asarray(flt, dtype=np.float64)
    delta, lo, hi = paired_difference(fixed, flt, np.ones(len(fixed)))
    return dict(fixed=float(fixed.mean()), float=float(flt.mean()), delta=delta, lo=lo, hi=hi,
                zero_inside=bool(lo <= 0.0 <= hi) if not math.isnan(lo) else delta == 0.0)


def summarise(result) -> dict:
    """Plain data: the RTL check per variant, the cases' paired differences, the gain curves
    (Pd fixed / float, paired ΔPd) and the SNR losses, and a verdict per variant."""
    spec = result.spec
    out = {"engine": spec.engine, "seconds": result.seconds, "workers": result.workers,
           "rtl": {name: t.to_dict() for name, t in result.rtl.items()}, "cases": {},
           "gain": {}}
    for label, kinds in result.cases.items():
        metrics = [m for m in kinds["fixed"]
                   if m in CASE_METRICS or m.startswith(("false_tracks@", "false_cells@"))]
        out["cases"][label] = {m: _paired(kinds["fixed"][m], kinds["float"][m]) for m in metrics}
    snrs = np.asarray(spec.gain_snrs_db)
    for dp, g in result.gain.items():
        fixed, flt = g["fixed"].astype(np.int64), g["float"].astype(np.int64)
        n = fixed.shape[1]
        rows = []
        for j, snr in enumerate(snrs):
            row = {"snr_db": float(snr), "threshold_fixed": float(g["thresholds"]["fixed"][j]),
                   "threshold_float": float(g["thresholds"]["float"][j])}
            for kind, det in (("fixed", fixed[j]), ("float", flt[j])):
                lo, hi = wilson_interval(int(det.sum()), n)
                row.update({f"pd_{kind}": float(det.mean()), f"pd_{kind}_lo": lo,
                            f"pd_{kind}_hi": hi})
            row["delta"] = _paired(fixed[j], flt[j])
            rows.append(row)
        losses = []
        if len(snrs) >= 2:
            est = bootstrap_losses(snrs, np.stack([fixed, flt]), np.ones(fixed.shape), [(0, 1)],
                                   LOSS_LEVELS, n_boot=1000, seed=0)[0]
            losses = [dict(level=e.level, loss=e.loss, lo=e.lo, hi=e.hi, snr_fixed=e.snr_db,
                           snr_float=e.ref_snr_db) for e in est]
        out["gain"][dp] = {"rows": rows, "losses": losses, "scenes": n}
    out["verdict"] = _verdicts(out)
    return out


#: The detection outcomes of a case that the verdict reads (the real values h differ by the
#: quantisation of the ADC and the LUTs, and are reported with their paired differences).
DETECTION_METRICS = ("target_is_max",)


def _verdicts(summary: dict) -> dict:
    """Per case / DP: does every paired interval of fixed − float of a *detection outcome*
    (target beats the noise, false cells and tracks above V_T, Pd, SNR loss) contain 0?"""
    verdict = {}
    for label, metrics in summary["cases"].items():
        verdict[label] = all(m["zero_inside"] for k, m in metrics.items()
                             if k in DETECTION_METRICS
                             or k.startswith(("false_tracks@", "false_cells@")))
    for dp, g in summary["gain"].items():
        verdict[dp] = (all(r["delta"]["zero_inside"] for r in g["rows"])
                       and all(not (l["lo"] > 0 or l["hi"] < 0) for l in g["losses"]))
    return verdict


def _ci(d: dict, fmt: str = "{:+.3f}") -> str:
    if math.isnan(d["lo"]):
        return fmt.format(d["delta"])
    return f"{fmt.format(d['delta'])} [{fmt.format(d['lo'])}, {fmt.format(d['hi'])}]"


def markdown(summary: dict) -> str:
    """The tables: RTL check, §5.1/§5.2 cases, gain curves, SNR losses, verdicts."""
    lines = []
    if summary["rtl"]:
        lines += ["| variant | state words compared bit for bit (RTL = golden model) | pixel "
                  "updates | RTL runs |", "|---|---|---|---|"]
        for name, t in summary["rtl"].items():
            lines.append(f"| {name} | {t['state_words']:,} | {t['pixel_updates']:,} | "
                         f"{t['runs']} |")
        lines.append("")
    if summary["cases"]:
        lines += ["| case (000) | measurement | fixed (mean) | float (mean) | fixed − float "
                  "[95 % paired CI] |", "|---|---|---|---|---|"]
        for label, metrics in summary["cases"].items():
            for m, d in metrics.items():
                lines.append(f"| {label} | {m} | {d['fixed']:.3f} | {d['float']:.3f} | "
                             f"{_ci(d)} |")
        lines.append("")
    for dp, g in summary["gain"].items():
        lines += [f"{dp}, {g['scenes']} scenes per SNR:", "",
                  "| SNR (dB) | Pd fixed | Pd float | ΔPd fixed − float [95 % paired CI] |",
                  "|---|---|---|---|"]
        for r in g["rows"]:
            lines.append(f"| {r['snr_db']:g} | {r['pd_fixed']:.3f} | {r['pd_float']:.3f} | "
                         f"{_ci(r['delta'])} |")
        for loss in g["losses"]:
            lines.append(f"\nSNR at Pd {loss['level']:g}: fixed {loss['snr_fixed']:.2f} dB, "
                         f"float {loss['snr_float']:.2f} dB, loss {loss['loss']:+.2f} dB "
                         f"[{loss['lo']:+.2f}, {loss['hi']:+.2f}] (paired bootstrap)")
        lines.append("")
    lines.append("Every paired interval of fixed − float of a detection outcome (target is max, "
                 "false cells / tracks > V_T, Pd, SNR loss) contains 0: " + "; ".join(
        f"{k}: {'yes' if v else 'NO'}" for k, v in summary["verdict"].items()))
    return "\n".join(lines)
