"""Statistics, files and tables of ``dptbd compare`` (:mod:`dptbd.evaluation.compare`).

:func:`summarise` turns the per-trial counts into statistics (every Pd and Pfa with its
95 % interval clustered by trial, agreement with float, SNR losses with their bootstrap
intervals, verdicts, the sweep's choice); :func:`write_outputs` writes them as CSV and JSON
and draws the figures (:mod:`dptbd.evaluation.compare.figures`);
:func:`markdown_tables` gives the tables ``dptbd compare`` prints.
"""

from __future__ import annotations

import csv
import math
import pathlib
from typing import Any, Mapping

import numpy as np

from dptbd.evaluation import sweep
from dptbd.evaluation.snr_loss import clustered_wilson
from dptbd.evaluation.stats import wilson_interval
from dptbd.evaluation.compare.figures import draw_figures
from dptbd.output_folder import json_text

__all__ = ["TOOL", "MARKER", "summarise", "write_outputs", "markdown_tables", "DATA_FILES",
           "paired_difference", "identical_curves"]

#: The ``tool`` field of ``compare_summary.json``: marks an output folder that ``--force`` may
#: replace (:func:`dptbd.output_folder.staged_folder`).
TOOL = "dptbd compare"
#: The file of an output folder that carries :data:`TOOL`.
MARKER = "compare_summary.json"

DATA_FILES = ("compare_pd.csv", "compare_pfa.csv", "compare_equal_pfa.csv", "compare_configs.csv",
              "compare_summary.json")


def _num(x):
    """JSON-safe number: NaN -> None, +-inf -> "inf"/"-inf"."""
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        x = float(x)
        if math.isnan(x):
            return None
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
    return x


def paired_difference(a, b, n, z: float = 1.959963984540054) -> tuple[float, float, float]:
    """Difference of two proportions measured on the same clusters, with a 95 % interval.

    ``a``, ``b``: successes per cluster (trial) of the two detectors, ``n``: trials per
    cluster. Estimate ``(sum a - sum b) / sum n``; its standard error is the
    cluster-robust (ratio-estimator) one of the per-cluster differences, so the pairing —
    both detectors saw the same scenes — is used: identical outcomes cancel. Normal
    interval; ``(0, 0, 0)`` for identical detectors.
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    n = np.asarray(n, dtype=np.float64)
    total = n.sum()
    if total <= 0:
        return (math.nan, math.nan, math.nan)
    delta = float((a - b).sum() / total)
    k = len(n)
    if k < 2:
        return (delta, math.nan, math.nan)
    resid = (a - b) - delta * n
    se = math.sqrt(float(np.sum(resid ** 2)) * k / (k - 1)) / total
    return (delta, delta - z * se, delta + z * se)


def identical_curves(result, names: list[str]) -> dict[str, str | None]:
    """Detectors whose every count is identical on every trial share one curve in the figures.

    Returns detector name -> the curve's label (the names joined by " = ") for the first
    detector of each group, ``None`` for the others.
    """
    c = result.counts
    keys = sorted(c)
    out: dict[str, str | None] = {}
    groups: list[list[int]] = []
    for d in range(len(names)):
        for g in groups:
            if all(np.array_equal(c[k][:, d], c[k][:, g[0]]) for k in keys if k not in ("agree_frac", "agree_same")):
                if names[d].startswith("float ") == names[g[0]].startswith("float "):
                    g.append(d)
                    break
        else:
            groups.append([d])
    for g in groups:
        out[names[g[0]]] = " = ".join(names[d] for d in g)
        for d in g[1:]:
            out[names[d]] = None
    return out


def equal_pfa(result) -> list[dict]:
    """The second operating point: every detector at each false-alarm probability per pixel
    of ``spec.pfa``, one row per (detector, Pfa, SNR).

    The threshold is the detector's own: of the N = trials x segments x size**2 noise-only
    E, with n = floor(pfa N), the (n+1)-th largest (:func:`dptbd.evaluation.pfa.pixel_threshold`'s
    rule, from the run's merged largest values, ``result.noise_top``); ``threshold_z`` is it in
    the float model's noise units of a K-frame path, ``(E_float - K mu) / (sqrt(K) sigma)``,
    a fixed configuration's E mapped back through its ADC. A segment detects the target
    when an E within the detection gate is strictly above the threshold; Pd with its
    interval clustered by trial, and the paired difference from the float model with the
    same LUT *at its own threshold*. False alarms per map: noise-only pixels above the
    threshold per accumulated image (at most n / (trials x segments)).
    """
    plan = result.plan
    spec = plan.spec
    c = result.counts
    names = plan.detector_names()
    n_seg = result.segments
    maps = spec.trials * n_seg
    pixels = maps * spec.size * spec.size
    opp = result.opportunities
    k = spec.segment_frames
    n_float = len(plan.floats)
    thresholds = {}
    for d in range(len(names)):
        v = result.noise_top[d]
        for p in spec.pfa:
            n = int(math.floor(p * pixels))
            thr = float(v[v.size - n - 1])
            thresholds[(d, p)] = (thr, int(v.size - np.searchsorted(v, thr, side="right")))
    detected = {key: (c["near_max"][:, key[0]] > thr).sum(axis=2)  # (trials, SNRs)
                for key, (thr, _) in thresholds.items()}
    rows = []
    for d, name in enumerate(names):
        ref = d if d < n_float else plan.fixed_float[d - n_float]
        if d < n_float:
            gain, offset = 1.0, 0.0
        else:
            _, gain, offset = plan.adcs[plan.fixed_adc[d - n_float]]
        for p in spec.pfa:
            thr, above = thresholds[(d, p)]
            z = ((thr - k * offset) / gain - k * spec.mu) / (math.sqrt(k) * spec.sigma)
            for j, snr in enumerate(spec.snr):
                det = detected[(d, p)][:, j]
                pd, lo, hi, deff = clustered_wilson(det, opp[j])
                delta, dlo, dhi = paired_difference(det, detected[(ref, p)][:, j], opp[j])
                rows.append({"detector": name, "pfa": p, "snr": snr, "snr_db": float(spec.snr_db[j]),
                             "threshold": thr, "threshold_z": z, "noise_false_alarms": above,
                             "noise_pixels": pixels, "measured_pfa": above / pixels,
                             "false_alarms_per_map": above / maps,
                             "detections": int(det.sum()), "opportunities": int(opp[j].sum()),
                             "pd": pd, "pd_lo": lo, "pd_hi": hi, "design_effect": deff,
                             "delta_pd": delta, "delta_pd_lo": dlo, "delta_pd_hi": dhi})
    return rows


def summarise(result, hardware: Mapping[str, Any] | None = None) -> dict:
    """Statistics of a :class:`~dptbd.evaluation.compare.CompareResult` as plain data.

    ``hardware``: configuration name -> :class:`~dptbd.evaluation.sweep.HardwareCost` (or a
    dict of its fields), for the configurations that were synthesised. The ``"tool"`` field
    (:data:`TOOL`) marks the output folder as a ``dptbd compare`` run's.
    """
    plan = result.plan
    spec = plan.spec
    c = result.counts
    n_trials = spec.trials
    n_seg = result.segments
    names = plan.detector_names()
    pixels = n_seg * spec.size * spec.size
    opp = result.opportunities  # (S, N)

    pd_rows = []
    n_float = len(plan.floats)
    for d, name in enumerate(names):
        ref = d if d < n_float else plan.fixed_float[d - n_float]
        for j, snr in enumerate(spec.snr):
            det = c["detections"][:, d, j]
            p, lo, hi, deff = clustered_wilson(det, opp[j])
            delta, dlo, dhi = paired_difference(det, c["detections"][:, ref, j], opp[j])
            pd_rows.append({
                "detector": name, "snr": snr, "snr_db": float(spec.snr_db[j]),
                "detections": int(det.sum()), "opportunities": int(opp[j].sum()),
                "pd": p, "pd_lo": lo, "pd_hi": hi, "design_effect": deff,
                "delta_pd": delta, "delta_pd_lo": dlo, "delta_pd_hi": dhi,
                "false_points_per_frame": float(c["false_points"][:, d, j].sum()) / (n_trials * n_seg),
                "candidates_per_frame": float(c["candidates"][:, d, j].sum()) / (n_trials * n_seg)})

    pfa_rows = []
    for d, name in enumerate(names):
        for k, z in enumerate(spec.thresholds):
            exc = c["exceed"][:, d, k]
            p, lo, hi, deff = clustered_wilson(exc, np.full(n_trials, pixels))
            pfa_rows.append({"detector": name, "threshold_z": z, "level": float(plan.levels[d, k]),
                             "exceedances": int(exc.sum()), "pixels": pixels * n_trials,
                             "pfa": p, "pfa_lo": lo, "pfa_hi": hi, "design_effect": deff})

    equal_pfa_rows = equal_pfa(result)

    losses = sweep.config_losses(result)
    verdicts = {f.name: sweep.verdict(losses[f.name], spec.tolerance_db) for f in spec.configs}
    hardware = {k: (v.to_dict() if hasattr(v, "to_dict") else dict(v))
                for k, v in (hardware or {}).items()}
    choice = sweep.choose(spec.configs, verdicts, hardware)

    config_rows = []
    kinds = len(spec.snr) + 1
    images = n_trials * n_seg * kinds
    for f, d in zip(spec.configs, plan.config_detector):
        same = int(c["agree_same"][:, d, :].sum())
        lo, hi = wilson_interval(same, images)
        noise_cand = float(c["candidates"][:, d, -1].sum()) / (n_trials * n_seg)
        row = dict(f.to_dict())
        row.update({
            "widths": f.widths, "sigma_lsb": f.adc_gain * spec.sigma,
            "state_bits_per_pixel": f.cfg.state_bits,
            "state_store_kbit": sweep.state_store_bits(f.cfg) / 1024.0,
            "agreement": float(c["agree_frac"][:, d, :].sum()) / images,
            "identical_images": same / images, "identical_lo": lo, "identical_hi": hi,
            "noise_candidates_per_frame": noise_cand,
            "verdict": verdicts[f.name],
            "differs_from_float": any(e.differs() for e in losses[f.name]),
            "detector": names[d]})
        if spec.tie_rule == "gateware-bins":  # the histogram the candidates were selected on
            row.update({"histogram_bits": f.cfg.histogram_bits, "bin_shift": f.cfg.bin_shift})
        for e in losses[f.name]:
            tag = f"pd{int(round(e.level * 100)):02d}"
            row.update({f"loss_{tag}_db": e.loss, f"loss_{tag}_lo": e.lo, f"loss_{tag}_hi": e.hi,
                        f"snr_db_{tag}": e.snr_db, f"float_snr_db_{tag}": e.ref_snr_db})
        hw = hardware.get(f.name)
        for key in ("lut4", "ff", "bram", "carry", "fmax_median_mhz", "fits", "logic_cells"):
            row[f"hw_{key}"] = None if hw is None else hw.get(key)
        config_rows.append(row)

    widths = {}
    for level in spec.pd_levels:
        tag = f"pd{int(round(level * 100)):02d}"
        halves = [(r[f"loss_{tag}_hi"] - r[f"loss_{tag}_lo"]) / 2 for r in config_rows
                  if math.isfinite(r[f"loss_{tag}_hi"]) and math.isfinite(r[f"loss_{tag}_lo"])]
        widths[tag] = {"median_half_width_db": float(np.median(halves)) if halves else None,
                       "min_half_width_db": float(np.min(halves)) if halves else None}

    run = spec.run_params()
    run.update({"candidate_count": spec.candidate_count, "segments_per_trial": n_seg,
                "opportunities_per_snr": int(opp.sum(axis=1)[0]),
                "seconds": result.seconds, "workers": result.workers,
                "trials_per_second": result.trials_per_second,
                "engine": "rtl" if getattr(result, "rtl", None) else "model",
                "rtl": getattr(result, "rtl", None)})
    return {"tool": TOOL, "run": run, "detectors": names,
            "curves": identical_curves(result, names), "pd": pd_rows, "pfa": pfa_rows,
            "equal_pfa": equal_pfa_rows,
            "configs": config_rows, "choice": choice, "resolution": widths,
            "hardware": hardware}


# ==== files ================================================================================

def _write_csv(path: pathlib.Path, rows: list[dict]) -> None:
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with path.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in keys})


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_jsonable(v) for v in obj.tolist()]
    if isinstance(obj, (np.bool_,)):
        return bool(obj)
    return _num(obj)


def write_outputs(summary: dict, out_dir: pathlib.Path, *, figures: bool = True) -> list[pathlib.Path]:
    """Write the CSV and JSON files (and the figures) into ``out_dir`` (which must exist)."""
    out_dir = pathlib.Path(out_dir)
    _write_csv(out_dir / "compare_pd.csv", summary["pd"])
    _write_csv(out_dir / "compare_pfa.csv", summary["pfa"])
    _write_csv(out_dir / "compare_equal_pfa.csv", summary["equal_pfa"])
    cfg_rows = [{k: v for k, v in r.items()} for r in summary["configs"]]
    _write_csv(out_dir / "compare_configs.csv", cfg_rows)
    (out_dir / "compare_summary.json").write_text(json_text(_jsonable(summary), indent=1))
    paths = [out_dir / n for n in DATA_FILES]
    if figures:
        paths += draw_figures(summary, out_dir)
    return paths


# ==== Markdown =============================================================================

def _fmt_loss(v, lo, hi) -> str:
    def f(a):
        if a is None or (isinstance(a, float) and math.isnan(a)):
            return "?"
        if math.isinf(a):
            return "∞" if a > 0 else "−∞"
        return f"{a:+.2f}"
    return f"{f(v)} [{f(lo)}, {f(hi)}]"


def markdown_tables(summary: dict) -> str:
    """The configurations table (losses, verdicts, agreement, hardware) and the float Pd row.

    "≠ float" is "yes" when a loss interval excludes 0 at some Pd level (the configuration
    is shown to differ from float), "no" when every interval contains 0.
    """
    run = summary["run"]
    levels = run["pd_levels"]
    head = ["configuration", "B_in/B_E/F", "σ (LSB)", "cand./frame (noise)"]
    head += [f"loss @Pd={lv:g} dB [95% CI]" for lv in levels]
    head += [f"verdict (≤{run['tolerance_db']:g} dB)", "≠ float", "identical cand. lists",
             "agreement"]
    has_hw = any(r["hw_lut4"] is not None for r in summary["configs"])
    if has_hw:
        head += ["SB_LUT4", "FF", "BRAM", "Fmax MHz"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    rows = sorted(summary["configs"], key=lambda r: (not r["explicit"], r["state_bits_per_pixel"],
                                                     r["input_bits"], r["weight_frac_bits"]))
    for r in rows:
        cells = [r["name"], r["widths"], f"{r['sigma_lsb']:.2g}", f"{r['noise_candidates_per_frame']:.2f}"]
        for lv in levels:
            tag = f"pd{int(round(lv * 100)):02d}"
            cells.append(_fmt_loss(r[f"loss_{tag}_db"], r[f"loss_{tag}_lo"], r[f"loss_{tag}_hi"]))
        cells += [r["verdict"], "yes" if r["differs_from_float"] else "no",
                  f"{r['identical_images']:.3f}", f"{r['agreement']:.3f}"]
        if has_hw:
            fm = r["hw_fmax_median_mhz"]
            cells += [str(r["hw_lut4"] or "—"), str(r["hw_ff"] or "—"), str(r["hw_bram"] if r["hw_bram"] is not None else "—"),
                      "—" if fm is None else f"{fm:.1f}"]
        lines.append("| " + " | ".join(cells) + " |")
    floats = [n for n in summary["detectors"] if n.startswith("float ")]
    pd_lines = ["| detector | " + " | ".join(f"{r['snr']:g} ({r['snr_db']:.1f} dB)" for r in summary["pd"]
                                          if r["detector"] == floats[0]) + " |"]
    pd_lines.append("|" + "---|" * (1 + len(run["snr"])))
    for name in floats:
        pts = [r for r in summary["pd"] if r["detector"] == name]
        pd_lines.append(f"| {name} | " + " | ".join(f"{p['pd']:.3f} [{p['pd_lo']:.3f}, {p['pd_hi']:.3f}]"
                                                   for p in pts) + " |")
    shown = floats + [r["detector"] for r in rows if r["explicit"]]
    eq_lines = []
    for p in run["pfa"]:
        eq_lines += [f"\nPd at equal Pfa {p:g} per pixel (thresholds calibrated on the noise-only "
                     f"scenes) [95 % CI]:\n",
                     "| detector | threshold (z) | false alarms per map | "
                     + " | ".join(f"{s:g}" for s in run["snr"]) + " |",
                     "|" + "---|" * (3 + len(run["snr"]))]
        for name in dict.fromkeys(shown):
            pts = [r for r in summary["equal_pfa"] if r["detector"] == name and r["pfa"] == p]
            eq_lines.append(f"| {name} | {pts[0]['threshold_z']:.2f} | {pts[0]['false_alarms_per_map']:.2f} | "
                            + " | ".join(f"{q['pd']:.3f} [{q['pd_lo']:.3f}, {q['pd_hi']:.3f}]" for q in pts)
                            + " |")
    choice = summary["choice"]
    res = summary["resolution"]
    notes = [f"Smallest sweep configuration shown within {run['tolerance_db']:g} dB of float: "
             f"**{choice['within'] or 'none'}**; smallest not shown beyond it: "
             f"**{choice['not_beyond'] or 'none'}**.",
             "Loss resolution of this run (median half-width of the 95 % intervals): " + ", ".join(
                 f"Pd {tag[2:]}%: {v['median_half_width_db']:.3f} dB" for tag, v in res.items()
                 if v["median_half_width_db"] is not None) + "."]
    return ("\n".join(lines) + "\n\nFloat model Pd [95 % CI]:\n\n" + "\n".join(pd_lines) + "\n"
            + "\n".join(eq_lines) + "\n\n" + "\n".join(notes))
