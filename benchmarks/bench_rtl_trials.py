"""RTL in the loop against the golden model: trials per second of ``dptbd compare`` both ways.

    python benchmarks/bench_rtl_trials.py                       # default comparison, 24 trials
    python benchmarks/bench_rtl_trials.py --trials 48 --workers 2
    python benchmarks/bench_rtl_trials.py --config my.toml --json build/bench_rtl.json

The same run (the default :func:`dptbd.evaluation.compare.build_spec`, or ``--config``'s) is
timed twice in this process, one after the other: on the golden model
(``run_compare(spec)``) and with the fixed-point configurations on the compiled gateware
(``run_compare(spec, rtl=True)``, :mod:`dptbd.sim.rtl.trials`). The RTL executables are
built (or taken from the cache) first, outside the clock: :attr:`CompareResult.seconds` is
the Monte Carlo alone in both cases (the float model runs in both). Printed: trials per
second of each, their ratio, the pixel updates that went through the RTL, the Verilator
cycle rate, and that both runs gave identical counts (checked; the script fails
otherwise). The load average is printed too: the machine is shared.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import sys
import time
import tomllib

import numpy as np

from dptbd.evaluation.compare import build_spec, make_plan, run_compare


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", type=pathlib.Path, help="a dptbd compare TOML file")
    ap.add_argument("--trials", type=int, default=24, help="trials (default 24)")
    ap.add_argument("--workers", type=int, default=1, help="worker processes (default 1)")
    ap.add_argument("--json", metavar="PATH", help="also write the numbers as JSON")
    args = ap.parse_args(argv)
    mapping = tomllib.loads(args.config.read_text()) if args.config else {}
    spec = build_spec(mapping, trials=args.trials, bootstrap=0)

    from dptbd.sim.rtl.trials import prepare_builds
    start = time.perf_counter()
    for cfg in make_plan(spec).fixed:     # compile or find in the cache, outside the clock
        prepare_builds(cfg)
    build_seconds = time.perf_counter() - start

    load0 = os.getloadavg()[0]
    model = run_compare(spec, workers=args.workers)
    rtl = run_compare(spec, workers=args.workers, rtl=True)
    load1 = os.getloadavg()[0]
    same = all(np.array_equal(model.counts[k], rtl.counts[k]) for k in model.counts)
    info = rtl.rtl
    row = {
        "trials": spec.trials, "workers": args.workers,
        "fixed_behaviours": len(rtl.plan.fixed), "float_models": len(rtl.plan.floats),
        "model_seconds": model.seconds, "model_trials_per_second": model.trials_per_second,
        "rtl_seconds": rtl.seconds, "rtl_trials_per_second": rtl.trials_per_second,
        "ratio_model_over_rtl": model.seconds and rtl.seconds / model.seconds,
        "rtl_pixel_updates": info["pixel_updates"], "rtl_state_words": info["state_words"],
        "rtl_lists": info["lists"], "rtl_cycles": info["cycles"],
        "rtl_sim_seconds": info["sim_seconds"],
        "verilator_cycles_per_second": info["cycles"] / info["sim_seconds"]
        if info["sim_seconds"] else None,
        "build_seconds": build_seconds, "identical_counts": same,
        "load_average": [load0, load1],
    }
    print(f"{spec.trials} trials, {row['fixed_behaviours']} fixed-point behaviours + "
          f"{row['float_models']} float model(s), {args.workers} worker(s), load {load0:.1f} -> "
          f"{load1:.1f}")
    print(f"golden model : {model.seconds:8.1f} s  {model.trials_per_second:8.3f} trials/s")
    print(f"RTL in loop  : {rtl.seconds:8.1f} s  {rtl.trials_per_second:8.3f} trials/s  "
          f"({row['ratio_model_over_rtl']:.1f}x slower)")
    print(f"through the RTL: {info['pixel_updates']:,} pixel updates (DPPipeline) + "
          f"{info['segmenter_pixels']:,} (DP + segmenter), {info['cycles']:,} cycles in "
          f"{info['sim_seconds']:.1f} s simulated "
          f"({row['verilator_cycles_per_second'] / 1e6:.1f} M cycles/s)")
    print(f"counts identical: {same}; {info['verdict']}")
    if args.json:
        path = pathlib.Path(args.json)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(row, indent=1) + "\n")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
