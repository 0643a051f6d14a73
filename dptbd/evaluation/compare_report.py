"""Tables, files and figures of ``dptbd compare`` (:mod:`dptbd.evaluation.compare`).

:func:`summarise` turns the per-trial counts into statistics (every Pd and Pfa with its
95 % interval clustered by trial, agreement with float, SNR losses with their bootstrap
intervals, verdicts, the sweep's choice); :func:`write_outputs` writes them as CSV and JSON
and draws the figures:

* ``compare_pd.png`` — left: Pd vs SNR of the float model and of every fixed
  configuration (configurations computing identical bits share a curve), with 95 % bands;
  right: Pd(fixed) − Pd(float) with its paired 95 % band;
* ``compare_pfa.png`` — false-alarm probability per pixel vs threshold (noise-only
  scenes);
* ``compare_loss.png`` — SNR loss at each Pd level against the configurations ordered by
  size, with the hardware cost (SB_LUT4 when synthesised, else the state word
  B_E + B_d) on the right axis.
"""

from __future__ import annotations

import csv
import json
import math
import pathlib
from typing import Any, Mapping

import numpy as np

from dptbd.evaluation import sweep
from dptbd.evaluation.snr_loss import clustered_wilson
from dptbd.evaluation.stats import wilson_interval

__all__ = ["summarise", "write_outputs", "markdown_tables", "FIGURES", "DATA_FILES"]

FIGURES = ("compare_pd.png", "compare_pfa.png", "compare_loss.png")
DATA_FILES = ("compare_pd.csv", "compare_pfa.csv", "compare_configs.csv", "compare_summary.json")


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


def summarise(result, hardware: Mapping[str, Any] | None = None) -> dict:
    """Statistics of a :class:`~dptbd.evaluation.compare.CompareResult` as plain data.

    ``hardware``: configuration name -> :class:`~dptbd.evaluation.sweep.HardwareCost` (or a
    dict of its fields), for the configurations that were synthesised.
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
            "state_bits_per_pixel": f.cfg.energy_bits + f.cfg.direction_bits,
            "state_store_kbit": sweep.state_store_bits(f.cfg) / 1024.0,
            "agreement": float(c["agree_frac"][:, d, :].sum()) / images,
            "identical_images": same / images, "identical_lo": lo, "identical_hi": hi,
            "noise_candidates_per_frame": noise_cand,
            "verdict": verdicts[f.name],
            "differs_from_float": any(e.differs() for e in losses[f.name]),
            "detector": names[d]})
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
    return {"run": run, "detectors": names, "curves": identical_curves(result, names), "pd": pd_rows, "pfa": pfa_rows,
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
    cfg_rows = [{k: v for k, v in r.items()} for r in summary["configs"]]
    _write_csv(out_dir / "compare_configs.csv", cfg_rows)
    (out_dir / "compare_summary.json").write_text(json.dumps(_jsonable(summary), indent=1))
    paths = [out_dir / n for n in DATA_FILES]
    if figures:
        paths += draw_figures(summary, out_dir)
    return paths


# ==== figures ==============================================================================

def draw_figures(summary: dict, out_dir: pathlib.Path) -> list[pathlib.Path]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    run = summary["run"]
    floats = [n for n in summary["detectors"] if n.startswith("float ")]
    pd_by = {}
    for r in summary["pd"]:
        pd_by.setdefault(r["detector"], []).append(r)
    pfa_by = {}
    for r in summary["pfa"]:
        pfa_by.setdefault(r["detector"], []).append(r)
    subtitle = (f"{run['size']}x{run['size']}, K={run['segment_frames']}, {run['trials']} trials x "
                f"{run['segments_per_trial']} segments, {run['candidate_count']} candidates/frame, "
                f"seed {run['seed']}")
    paths = []

    def curves(ax, by, xkey, ykey, lokey, hikey, rows, logy=False, floor=None, with_floats=True):
        shown = set()
        rows = sorted(rows, key=lambda r: (r["input_bits"], r["energy_bits"], r["weight_frac_bits"],
                                           r["rounding"], r["lut"]))
        dets = list(dict.fromkeys(r["detector"] for r in rows))
        cmap = plt.get_cmap("tab10" if len(dets) <= 10 else "tab20")
        for i, name in enumerate(floats if with_floats else []):
            pts = by[name]
            x = [p[xkey] for p in pts]
            y = np.array([p[ykey] for p in pts], dtype=float)
            lo = np.array([p[lokey] for p in pts], dtype=float)
            if logy:
                y = np.where(y > 0, y, np.nan)
                lo = np.maximum(lo, floor)
            ax.plot(x, y, color="k", lw=2.2, ls=["-", "--", ":"][i % 3], label=name, zorder=5)
            ax.fill_between(x, lo, [p[hikey] for p in pts], color="k", alpha=0.15, lw=0, zorder=4)
        dets = [d for d in dets if summary["curves"].get(d)]
        cmap = plt.get_cmap("tab10" if len(dets) <= 10 else "tab20")
        for row in rows:
            det = row["detector"]
            if det in shown or not summary["curves"].get(det):
                continue
            shown.add(det)
            pts = by[det]
            col = cmap(dets.index(det) % cmap.N)
            x = [p[xkey] for p in pts]
            y = np.array([p[ykey] for p in pts], dtype=float)
            lo = np.array([p[lokey] for p in pts], dtype=float)
            hi = np.array([p[hikey] for p in pts], dtype=float)
            if logy:
                y = np.where(y > 0, y, np.nan)
                lo = np.maximum(lo, floor)
            label = summary["curves"][det]
            ax.plot(x, y, color=col, lw=1.3, marker="o", ms=3, label=label)
            ax.fill_between(x, lo, hi, color=col, alpha=0.15, lw=0)
        if logy:
            ax.set_yscale("log")

    fixed_rows = [r for r in summary["configs"]]

    # --- Pd vs SNR, and the paired difference to float
    fig, (ax, axd) = plt.subplots(1, 2, figsize=(13.0, 6.4))
    curves(ax, pd_by, "snr_db", "pd", "pd_lo", "pd_hi", fixed_rows)
    for level in run["pd_levels"]:
        ax.axhline(level, color="grey", lw=0.6, ls=":")
    ax.set_xlabel("SNR (dB, 20 lg of paper 001's SNR)")
    ax.set_ylabel("first-level Pd (95 % CI band, clustered Wilson)")
    ax.set_ylim(0, 1)
    ax.grid(alpha=0.3)
    top = ax.secondary_xaxis("top", functions=(lambda d: 10 ** (d / 20),
                                               lambda v: 20 * np.log10(np.maximum(v, 1e-9))))
    top.set_xlabel("SNR (linear)", fontsize=8)
    curves(axd, pd_by, "snr_db", "delta_pd", "delta_pd_lo", "delta_pd_hi", fixed_rows,
           with_floats=False)
    axd.axhline(0, color="k", lw=1.5)
    axd.set_xlabel("SNR (dB)")
    axd.set_ylabel("Pd(fixed) − Pd(float), same scenes (paired 95 % CI band)")
    axd.grid(alpha=0.3)
    lo_all = [r["delta_pd"] for r in summary["pd"] if r["delta_pd"] is not None]
    axd.set_ylim(max(-0.3, min(lo_all) - 0.02) if lo_all else -0.3, 0.05)
    fig.suptitle("Pd vs SNR, fixed point against float on the same scenes\n" + subtitle, fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.04 + 0.025 * math.ceil(len(labels) / 3), 1, 1))
    p = out_dir / "compare_pd.png"
    fig.savefig(p, dpi=110)
    plt.close(fig)
    paths.append(p)

    # --- Pfa vs threshold
    fig, ax = plt.subplots(figsize=(8.0, 5.4))
    floor = 0.3 / (run["trials"] * run["segments_per_trial"] * run["size"] ** 2)
    curves(ax, pfa_by, "threshold_z", "pfa", "pfa_lo", "pfa_hi", fixed_rows, logy=True, floor=floor)
    ax.set_ylim(floor, 1.5)
    ax.set_xlabel("threshold z = (E − K·mu) / (sqrt(K)·sigma); fixed: E mapped back through its ADC")
    ax.set_ylabel("false-alarm probability per pixel (95 % CI band)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="lower left")
    ax.set_title("Pfa vs threshold on noise-only scenes\n" + subtitle, fontsize=9)
    fig.tight_layout()
    p = out_dir / "compare_pfa.png"
    fig.savefig(p, dpi=110)
    plt.close(fig)
    paths.append(p)

    # --- loss vs bits, hardware on the right axis
    rows = [r for r in summary["configs"] if r["in_sweep"]] or list(summary["configs"])
    rows = sorted(rows, key=lambda r: (r["state_bits_per_pixel"], r["hw_lut4"] or 0,
                                       r["input_bits"], r["weight_frac_bits"]))
    vary_round = len({r["rounding"] for r in rows}) > 1
    vary_lut = len({r["lut"] for r in rows}) > 1
    labels = []
    for r in rows:
        lab = r["widths"]
        if vary_round:
            lab += " " + r["rounding"][:5]
        if vary_lut:
            lab += " " + r["lut"]
        labels.append(lab)
    x = np.arange(len(rows))
    fig, ax = plt.subplots(figsize=(max(7.0, 0.55 * len(rows) + 3), 5.2))
    tol = run["tolerance_db"]
    big = 10.0
    markers = ["o", "s", "^", "D"]
    for i, level in enumerate(run["pd_levels"]):
        tag = f"pd{int(round(level * 100)):02d}"
        dx = (i - (len(run["pd_levels"]) - 1) / 2) * 0.18
        ys, lo_err, hi_err, inf_x = [], [], [], []
        for k, r in enumerate(rows):
            v, lo, hi = r[f"loss_{tag}_db"], r[f"loss_{tag}_lo"], r[f"loss_{tag}_hi"]
            if not math.isfinite(v):
                ys.append(np.nan)
                lo_err.append(0)
                hi_err.append(0)
                inf_x.append(k)
                continue
            ys.append(v)
            lo_err.append(v - lo if math.isfinite(lo) else v + big)
            hi_err.append(hi - v if math.isfinite(hi) else big - v)
        ax.errorbar(x + dx, ys, yerr=[lo_err, hi_err], fmt=markers[i % 4], ms=5, capsize=3,
                    color=f"C{i}", label=f"loss at Pd = {level:g} (95 % bootstrap CI)")
        if inf_x:
            ax.scatter(np.array(inf_x) + dx, np.full(len(inf_x), big), marker="^", s=40,
                       facecolors="none", edgecolors=f"C{i}",
                       label=f"Pd = {level:g} not reached in the SNR grid (∞)")
    ax.axhline(tol, color="r", lw=1, ls="--", label=f"tolerance {tol:g} dB")
    ax.axhline(0, color="k", lw=0.6)
    ax.set_yscale("symlog", linthresh=0.2)
    ax.set_ylim(-0.5, big * 1.6)
    ax.set_xticks(x)
    ax.set_xticklabels(labels, rotation=60, ha="right", fontsize=8)
    ax.set_xlabel("configuration B_in/B_E/F, ordered by state bits per pixel (then SB_LUT4 when synthesised)")
    ax.set_ylabel("SNR loss vs float (dB, symlog)")
    choice = summary["choice"].get("within")
    if choice is not None:
        for k, r in enumerate(rows):
            if r["name"] == choice:
                ax.axvspan(k - 0.45, k + 0.45, color="g", alpha=0.12, lw=0,
                           label="smallest shown within tolerance")
    ax2 = ax.twinx()
    lut = [r["hw_lut4"] for r in rows]
    if any(v is not None for v in lut):
        ax2.bar(x, [v or 0 for v in lut], width=0.6, color="grey", alpha=0.25, zorder=0)
        fmax = [r["hw_fmax_median_mhz"] for r in rows]
        bram = [r["hw_bram"] for r in rows]
        for k, (v, f, b) in enumerate(zip(lut, fmax, bram)):
            if v is not None and f is not None:
                ax2.text(k, v, f"{f:.0f}\nMHz\n{b} BR", ha="center", va="bottom", fontsize=6,
                         color="dimgrey")
        ax2.set_ylabel("SB_LUT4 (grey bars)\nabove: median Fmax, block RAMs (BR)")
        ax2.set_ylim(0, max(v or 0 for v in lut) * 1.5)
    else:
        ax2.plot(x, [r["state_bits_per_pixel"] for r in rows], color="grey", marker="_", ms=14,
                 ls="none", alpha=0.7)
        ax2.set_ylabel("state word B_E + B_d (bits per pixel, grey)")
        ax2.set_ylim(0, max(r["state_bits_per_pixel"] for r in rows) * 1.3)
    ax.set_zorder(ax2.get_zorder() + 1)
    ax.patch.set_visible(False)
    ax.legend(fontsize=7, loc="lower left")
    ax.grid(alpha=0.3, axis="y")
    hw = run.get("synth") or {}
    where = (f"\nhardware: {hw.get('variant', '?')} at {hw.get('size', '?')}x{hw.get('size', '?')}, "
             f"iCE40 {hw.get('device', '?').upper()} {hw.get('package', '')}, Yosys synth_ice40 + "
             f"nextpnr-ice40, seeds {hw.get('seeds', '?')}" if hw and any(v is not None for v in lut)
             else "")
    ax.set_title("SNR loss of each configuration and what it costs\n" + subtitle + where, fontsize=9)
    fig.tight_layout()
    p = out_dir / "compare_loss.png"
    fig.savefig(p, dpi=110)
    plt.close(fig)
    paths.append(p)
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
    choice = summary["choice"]
    res = summary["resolution"]
    notes = [f"Smallest sweep configuration shown within {run['tolerance_db']:g} dB of float: "
             f"**{choice['within'] or 'none'}**; smallest not shown beyond it: "
             f"**{choice['not_beyond'] or 'none'}**.",
             "Loss resolution of this run (median half-width of the 95 % intervals): " + ", ".join(
                 f"Pd {tag[2:]}%: {v['median_half_width_db']:.3f} dB" for tag, v in res.items()
                 if v["median_half_width_db"] is not None) + "."]
    return "\n".join(lines) + "\n\nFloat model Pd [95 % CI]:\n\n" + "\n".join(pd_lines) + "\n\n" + "\n".join(notes)
