"""The figures of ``dptbd compare``, drawn from its summary
(:func:`~dptbd.evaluation.compare.report.summarise`):

* ``compare_pd.png`` — left: Pd vs SNR of the float model and of every fixed
  configuration (configurations computing identical bits share a curve), with 95 % bands;
  right: Pd(fixed) − Pd(float) with its paired 95 % band (:func:`draw_pd_figure`);
* ``compare_pfa.png`` — false-alarm probability per pixel vs threshold on the noise-only
  scenes (:func:`draw_pfa_figure`);
* ``compare_loss.png`` — SNR loss at each Pd level against the configurations ordered by
  size, with the hardware cost (SB_LUT4 when synthesised, else the state word
  B_E + B_d) on the right axis (:func:`draw_loss_figure`).

Every figure is a :func:`dptbd.figures.new_figure` written by :func:`dptbd.figures.save_figure`.
"""

from __future__ import annotations

import math
import pathlib

import numpy as np

from dptbd.figures import DPI, new_figure, save_figure

__all__ = ["FIGURES", "draw_figures", "draw_pd_figure", "draw_pfa_figure", "draw_loss_figure"]

#: The figures of a run, by file name.
FIGURES = ("compare_pd.png", "compare_pfa.png", "compare_loss.png")

#: The dpi the figures are laid out at (matplotlib's default, as when they were drawn through
#: pyplot); they are saved at :data:`dptbd.figures.DPI`. Laying them out at 110 dpi moves
#: text by a pixel here and there: this keeps the PNGs byte-identical to earlier runs.
_LAYOUT_DPI = 100


def draw_figures(summary: dict, out_dir: pathlib.Path) -> list[pathlib.Path]:
    """Draw :data:`FIGURES` into ``out_dir`` (which must exist); return their paths."""
    out_dir = pathlib.Path(out_dir)
    return [draw_pd_figure(summary, out_dir / FIGURES[0]),
            draw_pfa_figure(summary, out_dir / FIGURES[1]),
            draw_loss_figure(summary, out_dir / FIGURES[2])]


def _by_detector(rows: list[dict]) -> dict[str, list[dict]]:
    """Rows grouped by their ``"detector"``, in order."""
    by: dict[str, list[dict]] = {}
    for r in rows:
        by.setdefault(r["detector"], []).append(r)
    return by


def _subtitle(run: dict) -> str:
    """The run's size, segments, candidates and seed, under every title."""
    return (f"{run['size']}x{run['size']}, K={run['segment_frames']}, {run['trials']} trials x "
            f"{run['segments_per_trial']} segments, {run['candidate_count']} candidates/frame, "
            f"seed {run['seed']}")


def _curves(ax, summary: dict, by: dict, keys: tuple[str, str, str, str], *, logy: bool = False,
            floor: float | None = None, with_floats: bool = True) -> None:
    """One line with its 95 % band per float model (black) and per shown fixed curve.

    ``keys``: the x, y, lower and upper bound fields of ``by``'s rows. A fixed detector is
    drawn once, labelled by ``summary["curves"]`` (identical detectors share a curve), in
    the order of the configurations by widths. ``logy``: a log y axis, the band's lower
    bound floored at ``floor``.
    """
    from matplotlib import colormaps

    xkey, ykey, lokey, hikey = keys
    floats = [n for n in summary["detectors"] if n.startswith("float ")]
    rows = sorted(summary["configs"], key=lambda r: (
        r["input_bits"], r["energy_bits"], r["weight_frac_bits"], r["rounding"], r["lut"]))
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
    dets = [d for d in dict.fromkeys(r["detector"] for r in rows) if summary["curves"].get(d)]
    cmap = colormaps["tab10" if len(dets) <= 10 else "tab20"]
    shown = set()
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
        ax.plot(x, y, color=col, lw=1.3, marker="o", ms=3, label=summary["curves"][det])
        ax.fill_between(x, lo, hi, color=col, alpha=0.15, lw=0)
    if logy:
        ax.set_yscale("log")


def draw_pd_figure(summary: dict, path: pathlib.Path) -> pathlib.Path:
    """Pd vs SNR (left) and the paired difference Pd(fixed) − Pd(float) (right)."""
    run = summary["run"]
    pd_by = _by_detector(summary["pd"])
    fig, (ax, axd) = new_figure(13.0, 6.4, ncols=2, dpi=_LAYOUT_DPI)
    _curves(ax, summary, pd_by, ("snr_db", "pd", "pd_lo", "pd_hi"))
    for level in run["pd_levels"]:
        ax.axhline(level, color="grey", lw=0.6, ls=":")
    ax.set_xlabel("SNR (dB, 20 lg of paper 001's SNR)")
    ax.set_ylabel("first-level Pd (95 % CI band, clustered Wilson)")
    ax.set_ylim(0, 1)
    ax.grid(alpha=0.3)
    top = ax.secondary_xaxis("top", functions=(lambda d: 10 ** (d / 20),
                                               lambda v: 20 * np.log10(np.maximum(v, 1e-9))))
    top.set_xlabel("SNR (linear)", fontsize=8)
    _curves(axd, summary, pd_by, ("snr_db", "delta_pd", "delta_pd_lo", "delta_pd_hi"),
            with_floats=False)
    axd.axhline(0, color="k", lw=1.5)
    axd.set_xlabel("SNR (dB)")
    axd.set_ylabel("Pd(fixed) − Pd(float), same scenes (paired 95 % CI band)")
    axd.grid(alpha=0.3)
    lo_all = [r["delta_pd"] for r in summary["pd"] if r["delta_pd"] is not None]
    axd.set_ylim(max(-0.3, min(lo_all) - 0.02) if lo_all else -0.3, 0.05)
    fig.suptitle("Pd vs SNR, fixed point against float on the same scenes\n" + _subtitle(run),
                 fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.04 + 0.025 * math.ceil(len(labels) / 3), 1, 1))
    return save_figure(fig, path, dpi=DPI)


def draw_pfa_figure(summary: dict, path: pathlib.Path) -> pathlib.Path:
    """False-alarm probability per pixel vs threshold z, on the noise-only scenes."""
    run = summary["run"]
    fig, ax = new_figure(8.0, 5.4, dpi=_LAYOUT_DPI)
    floor = 0.3 / (run["trials"] * run["segments_per_trial"] * run["size"] ** 2)
    _curves(ax, summary, _by_detector(summary["pfa"]), ("threshold_z", "pfa", "pfa_lo", "pfa_hi"),
            logy=True, floor=floor)
    ax.set_ylim(floor, 1.5)
    ax.set_xlabel("threshold z = (E − K·mu) / (sqrt(K)·sigma); fixed: E mapped back through its ADC")
    ax.set_ylabel("false-alarm probability per pixel (95 % CI band)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="lower left")
    ax.set_title("Pfa vs threshold on noise-only scenes\n" + _subtitle(run), fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path, dpi=DPI)


#: Where an unbounded loss (or interval end) is drawn on the loss figure's symlog axis (dB).
_LOSS_CAP_DB = 10.0


def _loss_rows(summary: dict) -> tuple[list[dict], list[str]]:
    """The configurations of the loss figure (the sweep's, else all), smallest first, and
    their tick labels (the widths; the rounding and the LUT when they vary)."""
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
    return rows, labels


def _loss_bars(ax, rows: list[dict], pd_levels) -> None:
    """Per Pd level: the loss and its bootstrap interval per configuration; a hollow
    triangle at the cap where the level is not reached."""
    x = np.arange(len(rows))
    big = _LOSS_CAP_DB
    markers = ["o", "s", "^", "D"]
    for i, level in enumerate(pd_levels):
        tag = f"pd{int(round(level * 100)):02d}"
        dx = (i - (len(pd_levels) - 1) / 2) * 0.18
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


def _cost_axis(ax2, rows: list[dict]) -> bool:
    """The right axis: SB_LUT4 bars (with Fmax and block RAMs) when synthesised, else the
    state word B_E + B_d. True when the synthesis numbers were drawn."""
    x = np.arange(len(rows))
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
        return True
    ax2.plot(x, [r["state_bits_per_pixel"] for r in rows], color="grey", marker="_", ms=14,
             ls="none", alpha=0.7)
    ax2.set_ylabel("state word B_E + B_d (bits per pixel, grey)")
    ax2.set_ylim(0, max(r["state_bits_per_pixel"] for r in rows) * 1.3)
    return False


def _synth_note(run: dict) -> str:
    """The title's line naming the synthesis flow (empty without synthesis numbers)."""
    hw = run.get("synth") or {}
    if not hw:
        return ""
    return (f"\nhardware: {hw.get('variant', '?')} at {hw.get('size', '?')}x{hw.get('size', '?')}, "
            f"iCE40 {hw.get('device', '?').upper()} {hw.get('package', '')}, Yosys synth_ice40 + "
            f"nextpnr-ice40, seeds {hw.get('seeds', '?')}")


def draw_loss_figure(summary: dict, path: pathlib.Path) -> pathlib.Path:
    """SNR loss per configuration (ordered by size) and, on the right axis, its cost."""
    run = summary["run"]
    rows, labels = _loss_rows(summary)
    x = np.arange(len(rows))
    fig, ax = new_figure(max(7.0, 0.55 * len(rows) + 3), 5.2, dpi=_LAYOUT_DPI)
    _loss_bars(ax, rows, run["pd_levels"])
    tol = run["tolerance_db"]
    ax.axhline(tol, color="r", lw=1, ls="--", label=f"tolerance {tol:g} dB")
    ax.axhline(0, color="k", lw=0.6)
    ax.set_yscale("symlog", linthresh=0.2)
    ax.set_ylim(-0.5, _LOSS_CAP_DB * 1.6)
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
    synthesised = _cost_axis(ax2, rows)
    ax.set_zorder(ax2.get_zorder() + 1)
    ax.patch.set_visible(False)
    ax.legend(fontsize=7, loc="lower left")
    ax.grid(alpha=0.3, axis="y")
    where = _synth_note(run) if synthesised else ""
    ax.set_title("SNR loss of each configuration and what it costs\n" + _subtitle(run) + where,
                 fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path, dpi=DPI)
