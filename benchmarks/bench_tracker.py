"""Track association quality of ``dptbd run``'s built-in scenario over several seeds.

    python benchmarks/bench_tracker.py                  # seeds 0-9, the default association
    python benchmarks/bench_tracker.py --seeds 20 --set max_misses=2 --json out.json

For each seed the built-in scenario (paper 001's second experiment, ``dptbd run`` with no
arguments, ``--seed N``) goes through the FPGA stage (golden model) and the DSP stage
exactly as ``dptbd run`` does, and the track metrics of :mod:`dptbd.dsp.track_metrics`
are collected per target. Printed: one line per seed and the means over seeds — frames
until output (over the seeds in which the target was confirmed), how often each target
was confirmed, detected track length after output and whole, confirmed tracks per target
(1 = never split), false tracks per run, RMS position error. This script only reports; it
asserts nothing (the figures are quoted in ``docs/tracking.md``).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time

import numpy as np


def _value(text: str):
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    if text in ("true", "false"):
        return text == "true"
    return text


def run_seed(seed: int, association: dict, snr: float | None = None, lists: str = "gateware",
             dp: dict | None = None, headroom: float = 2.0) -> dict:
    """The built-in scenario with one seed through both stages; per-target metrics."""
    from dptbd.evaluation.chain import run_pipeline
    from dptbd.dsp.track_metrics import evaluate_tracks
    from dptbd.evaluation.run.job import prepare
    from dptbd.evaluation.run.scenario import default_scenario

    changes = {"seed": seed, "association": association, "lists": lists}
    if snr is not None:
        changes["snr"] = snr
    sc = default_scenario()
    if dp:
        changes["dp"] = {**sc.dp, **dp}
    sc = sc.replace(**changes)
    sc.check()
    inp = prepare(sc, headroom=headroom)      # the data and parameters exactly as dptbd run
    res = run_pipeline(inp.frames, inp.cfg, inp.count, inp.assoc, lists=lists)
    ev = evaluate_tracks(res.tracks, res.positions, inp.truth, inp.cfg,
                         len(res.segments.end_frames))
    return {"seed": seed, "false_tracks": ev.false_tracks, "confirmed": ev.confirmed_tracks,
            "targets": [{"frames_until_output": t.frames_until_output,
                         "track_length": t.track_frames,
                         "track_length_after_output": t.track_frames_after_output,
                         "tracks": len(t.track_ids), "rms_error": t.rms_error}
                        for t in ev.targets]}


def summarise(runs: list[dict]) -> dict:
    """Means over seeds, per target."""
    n_t = len(runs[0]["targets"])
    out = {"seeds": len(runs), "false_tracks_mean": float(np.mean([r["false_tracks"] for r in runs])),
           "targets": []}
    for j in range(n_t):
        ts = [r["targets"][j] for r in runs]
        conf = [t for t in ts if t["frames_until_output"] is not None]
        rms = [t["rms_error"] for t in conf if not math.isnan(t["rms_error"])]
        out["targets"].append({
            "confirmed_in": len(conf),
            "frames_until_output_mean": float(np.mean([t["frames_until_output"] for t in conf]))
            if conf else None,
            "track_length_after_output_mean": float(np.mean([t["track_length_after_output"]
                                                             for t in ts])),
            "track_length_mean": float(np.mean([t["track_length"] for t in ts])),
            "tracks_per_confirmed_target": float(np.mean([t["tracks"] for t in conf]))
            if conf else None,
            "rms_error_mean": float(np.mean(rms)) if rms else None,
        })
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seeds", type=int, default=10, help="seeds 0 … N-1 (default 10)")
    p.add_argument("--snr", type=float, default=None, help="SNR (default the scenario's, 2.0)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="an [association] parameter (repeatable)")
    p.add_argument("--dp", action="append", default=[], metavar="KEY=VALUE",
                   help="a [dp] (DPConfig) parameter, e.g. histogram_shift=3 (repeatable)")
    p.add_argument("--lists", choices=("gateware", "ideal"), default="gateware",
                   help="candidate lists the DSP receives (default gateware: what the segmenter "
                        "emits; ideal: each segment's own histogram)")
    p.add_argument("--headroom", type=float, default=2.0,
                   help="the gateware segmenter selects for headroom x n points; the DSP trims "
                        "each list to n (default 2.0, as dptbd run)")
    p.add_argument("--json", metavar="FILE", help="also write the runs and means as JSON")
    args = p.parse_args(argv)
    assoc, dp = {}, {}
    for items, into in ((args.set, assoc), (args.dp, dp)):
        for item in items:
            key, _, val = item.partition("=")
            into[key.strip()] = _value(val.strip())
    start = time.perf_counter()
    runs = []
    for seed in range(args.seeds):
        r = run_seed(seed, assoc, args.snr, args.lists, dp, args.headroom)
        runs.append(r)
        cells = "  ".join(
            f"T{j + 1}: out {t['frames_until_output'] if t['frames_until_output'] is not None else '—':>3} "
            f"len {t['track_length_after_output']:>3}/{t['track_length']:>3} tracks {t['tracks']}"
            for j, t in enumerate(r["targets"]))
        print(f"seed {seed:>2}: {cells}  false {r['false_tracks']}", flush=True)
    s = summarise(runs)
    print(f"\nmeans over {s['seeds']} seeds ({time.perf_counter() - start:.0f} s), association "
          f"{assoc or 'defaults'}, dp {dp or 'defaults'}, {args.lists} lists:")
    for j, t in enumerate(s["targets"]):
        fmt = (lambda v: "—" if v is None else f"{v:.1f}")
        print(f"  target {j + 1}: confirmed in {t['confirmed_in']}/{s['seeds']}, frames until "
              f"output {fmt(t['frames_until_output_mean'])}, track length after output "
              f"{t['track_length_after_output_mean']:.1f} (whole {t['track_length_mean']:.1f}), "
              f"tracks per confirmed target {fmt(t['tracks_per_confirmed_target'])}, RMS error "
              f"{fmt(t['rms_error_mean'])} px")
    print(f"  false tracks per run: {s['false_tracks_mean']:.2f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"association": assoc, "dp": dp, "lists": args.lists, "runs": runs, "summary": s}, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
