"""Long reproductions of papers 000 and 004 (``docs/detection_results.md`` quotes their output).

    nice -n 10 .venv/bin/python benchmarks/bench_detectors.py --all --json bench_detectors.json

(from the repository root, with the project's virtual environment; ``--json`` is optional).

Parts (each also on its own): ``--paper000`` (§5.1/§5.2 cases), ``--gain`` (Pd vs SNR of
000's DPs against single-frame detection), ``--scenario1`` (004 Pfa vs entropy
threshold), ``--scenario2`` (004 Pd vs SNR at equal Pfa on the 200 x 500 grid),
``--timing`` (one frame on 200 x 500 against 004's Table 2). Scenario 2 runs 004's methods
and its particle-filter TBD (``--s2-detectors``), and with ``--s2-roc-pfa`` their ROC. Figures go to
``docs/figures/`` (``--figures``), Markdown tables to stdout.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import platform
import sys
import time

import numpy as np

from dptbd.evaluation.detectors import paper000, paper004, unified
from dptbd.evaluation.detectors.pd_vs_snr import SceneSpec, run_comparison
from dptbd.evaluation.detectors.report import figure_pd_vs_snr, figure_roc, format_table, roc_rows

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def bench_paper000(seeds: int, figures: pathlib.Path | None) -> dict:
    out = {}
    lines = ["| case | mode | paper | target h_20 (median) | largest noise h_20 (median) | "
             "false cells > V_T | false tracks > V_T | V_T leaving 2 false tracks | "
             "noise cells >= target | path on truth | seed 0: target / noise max |",
             "|" + "---|" * 11]
    for case in paper000.CASES:
        for mode in ("datapath", "exact"):
            n = seeds if mode == "datapath" else max(1, seeds // 2)
            t0 = time.perf_counter()
            r = paper000.run_case(case, range(n), mode=mode)
            cells = ", ".join(f"{v:g}: {np.median(r.false_cells[v]):.0f}" for v in case.thresholds)
            tracks = ", ".join(f"{v:g}: {np.median(r.false_tracks[v]):.0f}" for v in case.thresholds)
            lines.append(
                f"| {case.label} | {mode} | {case.paper} | {np.median(r.target):.2f} | "
                f"{np.median(r.noise_max):.2f} | {cells} | {tracks} | {np.median(r.two_track_level):.2f} | "
                f"{np.median(r.target_rank):.0f} | {np.mean(r.on_track):.2f} | "
                f"{r.target[0]:.2f} / {r.noise_max[0]:.2f} |")
            out[f"{case.label} {mode}"] = dict(
                seeds=n, target_median=float(np.median(r.target)), noise_max_median=float(np.median(r.noise_max)),
                false_cells={str(v): float(np.median(c)) for v, c in r.false_cells.items()},
                false_tracks={str(v): float(np.median(c)) for v, c in r.false_tracks.items()},
                two_track_level=float(np.median(r.two_track_level)),
                target_rank=float(np.median(r.target_rank)), on_track=float(np.mean(r.on_track)),
                p_target_is_max=float(np.mean(r.target > r.noise_max)),
                seed0=(float(r.target[0]), float(r.noise_max[0])), seconds=time.perf_counter() - t0)
    for case in paper000.CASES[:2]:  # how much of the noise maximum is the window's selection bias
        r = paper000.run_case(case, range(seeds), radius=1)
        lines.append(f"| {case.label} | datapath, radius 1 (3 x 3) | - | {np.median(r.target):.2f} | "
                     f"{np.median(r.noise_max):.2f} | | | | | | |")
        out[f"{case.label} radius 1"] = dict(seeds=seeds, target_median=float(np.median(r.target)),
                                             noise_max_median=float(np.median(r.noise_max)))
    print("\n".join(lines))
    if figures is not None:
        _fig_paper000(figures / "p000_tracks.png")
    return out


def _fig_paper000(path: pathlib.Path) -> None:
    from dptbd.scenes import synthetic as scenes
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(8.4, 4.0), dpi=80)
    for ax, case in zip(axes, (paper000.CASES[1], paper000.CASES[3])):
        sc = scenes.paper000_scenario(case.snr_db, seed=0)
        res = unified.run_unified(sc.frames, case.merit_fn(), case.transition(), radius=2, history=True)
        y, x = sc.truth[0].pixel[-1]
        gate = np.zeros(res.value.shape, bool)
        gate[y - 1:y + 2, x - 1:x + 2] = True
        peaks = np.argwhere(paper000.peak_mask(res.value) & ~gate)
        order = np.argsort(res.value[peaks[:, 0], peaks[:, 1]])[::-1][:2]
        ax.imshow(res.value, cmap="gray")
        truth = sc.truth[0].pixel
        ax.plot(truth[:, 1], truth[:, 0], "g-", lw=3, alpha=0.5, label="true track")
        p = unified.backtrack(res, (y, x))
        ax.plot(p[:, 1], p[:, 0], "c.-", lw=1, label=f"DP path to target, h={res.value[y, x]:.1f}")
        for k, i in enumerate(order):
            q = unified.backtrack(res, tuple(peaks[i]))
            ax.plot(q[:, 1], q[:, 0], "r.-", lw=1,
                    label=f"false tracks, h={res.value[tuple(peaks[i])]:.1f}" if k == 0 else None)
        ax.set_title(f"000 {case.label}, seed 0", fontsize=9)
        ax.legend(fontsize=6, loc="upper left")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def bench_gain(trials: int, figures: pathlib.Path | None) -> dict:
    g = paper000.snr_gain(snrs_db=range(0, 16), trials=trials, noise_trials=trials)
    names = list(g.pd)
    lines = ["| SNR (dB) | " + " | ".join(names) + " |", "|" + "---|" * (len(names) + 1)]
    for i, s in enumerate(g.snrs_db):
        lines.append(f"| {s:g} | " + " | ".join(f"{g.pd[n][i]:.2f}" for n in names) + " |")
    cross = {n: {lv: paper000.crossing_snr(g.snrs_db, g.pd[n], lv) for lv in (0.5, 0.9)} for n in names}
    lines.append("| SNR at Pd 0.5 | " + " | ".join(f"{cross[n][0.5]:.1f}" for n in names) + " |")
    lines.append("| SNR at Pd 0.9 | " + " | ".join(f"{cross[n][0.9]:.1f}" for n in names) + " |")
    print("\n".join(lines))
    if figures is not None:
        plt = _plt()
        fig, ax = plt.subplots(figsize=(6.0, 4.0), dpi=80)
        for n in names:
            ax.plot(g.snrs_db, g.pd[n], marker="o", ms=3, label=n)
        ax.set_xlabel("SNR (dB, 000 eq (8))")
        ax.set_ylabel("Pd")
        ax.set_title(f"000's scene, 20 frames, Pfa {g.pfa:g} per cell, {g.trials} trials", fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(figures / "p000_gain.png")
        plt.close(fig)
    return dict(snrs_db=list(g.snrs_db), pd={n: g.pd[n].tolist() for n in names}, trials=g.trials,
                pfa=g.pfa, crossing=cross, thresholds=g.thresholds)


def bench_scenario1(runs: int, frames: int, presets: list[float], figures: pathlib.Path | None) -> dict:
    from tqdm import tqdm
    t0 = time.perf_counter()
    thr = [0.001, 0.01, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 3.0, 4.0, 6.0, 8.0]
    lines = ["| preset SNR channel | " + " | ".join(f"H_thr {t:g}" for t in thr) + " | median H_k |",
             "|" + "---|" * (len(thr) + 2)]
    results = {}
    for preset in presets:
        r = paper004.scenario1(runs, frames, preset_snr_db=preset,
                               progress=lambda it: tqdm(list(it), desc=f"scenario 1, {preset:g} dB"))
        pfa = r.pfa(thr)
        results[preset] = r
        lines.append(f"| {preset:g} dB | " + " | ".join(f"{p:.2g}" for p in pfa)
                     + f" | {np.median(r.entropy[:, 10:]):.2f} |")
    n = runs * frames
    lines.append(f"\nPfa = fraction of all {n} frames ({runs} runs x {frames} frames, from H_0 = 16.61 bits) "
                 f"with H_k < H_thr")
    print("\n".join(lines))
    if figures is not None:
        plt = _plt()
        fig, axes = plt.subplots(1, 2, figsize=(8.4, 3.4), dpi=80)
        grid_thr = np.linspace(0.0, 10.0, 201)
        for preset, r in results.items():
            p = r.pfa(grid_thr)
            axes[0].semilogy(grid_thr, np.where(p > 0, p, np.nan), label=f"channel {preset:g} dB")
            axes[1].plot(r.entropy[0, :100], label=f"channel {preset:g} dB")
        axes[0].set_xlabel("entropy threshold H_thr (bits)")
        axes[0].set_ylabel("Pfa per frame")
        axes[0].grid(alpha=0.3, which="both")
        axes[0].legend(fontsize=7)
        axes[0].set_title(f"004 scenario 1: {runs} x {frames} noise-only frames", fontsize=9)
        axes[1].set_xlabel("frame k")
        axes[1].set_ylabel("H_k (bits)")
        axes[1].set_title("one noise-only run (from H_0 = 16.6)", fontsize=9)
        axes[1].grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(figures / "p004_scenario1.png")
        plt.close(fig)
    return dict(runs=runs, frames=frames, thresholds=thr,
                pfa={str(k): r.pfa(thr).tolist() for k, r in results.items()},
                median={str(k): float(np.median(r.entropy[:, 10:])) for k, r in results.items()},
                seconds=time.perf_counter() - t0)


#: Scenario 2's detectors: 004's Fig. 4 methods (001's DP for "the DP") and its particle filter
SCENARIO2_DETECTORS = "dw-dp,info,grid-bayes,ca-cfar,pf-tbd"


def bench_scenario2(trials: int, noise_trials: int, pfa: float, jobs: int, matched: bool,
                    figures: pathlib.Path | None, detectors: str = SCENARIO2_DETECTORS,
                    roc_pfas: tuple = ()) -> dict:
    spec = SceneSpec(kind="rd", frames=50, crop=(0, 0, 200, 500))
    dets = [d for d in detectors.split(",") if d]
    t0 = time.perf_counter()
    res = run_comparison(dets, snrs_db=[0.0, 3.0, 6.0, 9.0, 12.0, 15.0], spec=spec, trials=trials,
                         noise_trials=noise_trials, false_alarm_rate=pfa, matched=matched, jobs=jobs,
                         progress=True, roc_pfas=roc_pfas)
    print(format_table(res))
    if figures is not None:
        figure_pd_vs_snr(res, figures / ("p004_scenario2_matched.png" if matched else "p004_scenario2.png"))
        if roc_pfas:
            figure_roc(res, figures / ("p004_scenario2_matched_roc.png" if matched else "p004_scenario2_roc.png"))
    return dict(table=format_table(res), params={k: str(v) for k, v in res.params.items()},
                roc=roc_rows(res) if roc_pfas else None, seconds=time.perf_counter() - t0)


def bench_timing() -> dict:
    t = paper004.time_one_frame()
    lines = ["| algorithm | here (s/frame) | 004 Table 2 (s/frame) |", "|---|---|---|"]
    paper = {"info": 0.016, "grid-bayes": 0.018, "ca-cfar": 0.003, "dw-dp": 1.2, "dw-dp golden": 1.2,
             "dp-000 datapath": 1.2, "dp-000 exact": 1.2}
    for k, v in t.items():
        lines.append(f"| {k} | {v:.4f} | {paper.get(k, float('nan')):.3f} |")
    print("\n".join(lines))
    return t


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--all", action="store_true")
    ap.add_argument("--paper000", action="store_true")
    ap.add_argument("--gain", action="store_true")
    ap.add_argument("--scenario1", action="store_true")
    ap.add_argument("--scenario2", action="store_true")
    ap.add_argument("--scenario2-matched", action="store_true")
    ap.add_argument("--timing", action="store_true")
    ap.add_argument("--seeds", type=int, default=200, help="paper 000 cases: seeds (exact mode: half)")
    ap.add_argument("--gain-trials", type=int, default=200)
    ap.add_argument("--s1-runs", type=int, default=20)
    ap.add_argument("--s1-frames", type=int, default=500)
    ap.add_argument("--s1-presets", default="0,5,10", help="preset SNR channels (dB) of scenario 1")
    ap.add_argument("--s2-trials", type=int, default=40)
    ap.add_argument("--s2-noise-trials", type=int, default=200)
    ap.add_argument("--s2-pfa", type=float, default=1e-3)
    ap.add_argument("--s2-detectors", default=SCENARIO2_DETECTORS,
                    help=f"scenario 2's detectors (default {SCENARIO2_DETECTORS})")
    ap.add_argument("--s2-roc-pfa", default="",
                    help="further false-alarm rates per decision of scenario 2's ROC, e.g. 0.003,0.01,0.03")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--figures", type=pathlib.Path, default=ROOT / "docs" / "figures")
    ap.add_argument("--no-figures", action="store_true")
    ap.add_argument("--json", type=pathlib.Path)
    args = ap.parse_args(argv)
    figures = None if args.no_figures else args.figures
    roc = tuple(float(v) for v in args.s2_roc_pfa.split(",") if v.strip())
    if figures is not None:
        figures.mkdir(parents=True, exist_ok=True)
    result = dict(machine=dict(cpu=platform.processor() or platform.machine(), cores=os.cpu_count(),
                               load=os.getloadavg(), python=sys.version.split()[0]),
                  command=" ".join(sys.argv))
    parts = [("paper000", lambda: bench_paper000(args.seeds, figures)),
             ("gain", lambda: bench_gain(args.gain_trials, figures)),
             ("scenario1", lambda: bench_scenario1(args.s1_runs, args.s1_frames,
                                                  [float(v) for v in args.s1_presets.split(",")], figures)),
             ("scenario2", lambda: bench_scenario2(args.s2_trials, args.s2_noise_trials, args.s2_pfa,
                                                   args.jobs, False, figures, args.s2_detectors, roc)),
             ("scenario2_matched", lambda: bench_scenario2(args.s2_trials, args.s2_noise_trials, args.s2_pfa,
                                                           args.jobs, True, figures, args.s2_detectors, roc)),
             ("timing", bench_timing)]
    for name, fn in parts:
        if getattr(args, name) or (args.all and name != "scenario2_matched"):
            print(f"\n## {name}\n", flush=True)
            t0 = time.perf_counter()
            result[name] = fn()
            print(f"({name}: {time.perf_counter() - t0:.0f} s, load {os.getloadavg()[0]:.1f})", flush=True)
    if args.json is not None:
        args.json.write_text(json.dumps(result, indent=1, default=float))
    return 0


if __name__ == "__main__":
    sys.exit(main())
