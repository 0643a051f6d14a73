"""Throughput of ``dptbd compare``'s Monte Carlo on 1 and on 2 worker processes.

    python benchmarks/bench_compare.py                 # the default comparison (240 trials)
    python benchmarks/bench_compare.py --trials 96 --workers 1 2 4
    python benchmarks/bench_compare.py --json build/bench_compare.json

The same run (the default :func:`dptbd.evaluation.compare.build_spec`, or ``--config``'s) is
timed once per worker count, one after the other; each time is
:attr:`CompareResult.seconds`: the Monte Carlo alone (scenes, both models, counts), after
the kernels are compiled or loaded from numba's cache, excluding the start-up, the
statistics and the figures (about 5 s more with the kernels cached, about 15 s when numba
compiles them; ``docs/compare_results.md``). Reported: trials per second per worker count and the speed-up
over one worker. The runs must give identical counts (checked; the script fails
otherwise). The machine's load average is printed beside the numbers, and the **CPU
share**: the CPU seconds this process and its workers got during the run over
``workers x wall seconds`` (1.0: every worker had a core to itself). On a shared machine
other jobs take cores away; a share well below 1 means the speed-up is the machine's, not
the code's, and the trials per CPU-second column is then the figure to compare.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import platform
import resource
import sys
import time
import tomllib

import numpy as np

from dptbd.evaluation.compare import build_spec, run_compare


def _cpu_seconds() -> float:
    """User + system CPU seconds of this process and of its finished children (the workers)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", type=pathlib.Path, help="a dptbd compare TOML file")
    ap.add_argument("--trials", type=int, default=None, help="trials (default: the run's, 240)")
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--json", metavar="PATH", help="also write the numbers as JSON")
    ap.add_argument("--repeat", type=int, default=1,
                    help="run the worker counts this many times, alternating (default 1)")
    args = ap.parse_args(argv)
    mapping = tomllib.loads(args.config.read_text()) if args.config else {}
    spec = build_spec(mapping, trials=args.trials, bootstrap=0)
    rows = []
    first = None
    for w in [w for _ in range(max(1, args.repeat)) for w in args.workers]:
        load0 = os.getloadavg()[0]
        cpu0 = _cpu_seconds()
        wall0 = time.perf_counter()
        res = run_compare(spec, workers=w)
        wall = time.perf_counter() - wall0
        cpu = _cpu_seconds() - cpu0
        load1 = os.getloadavg()[0]
        if first is None:
            first = res
        else:
            for key in first.counts:
                if not np.array_equal(first.counts[key], res.counts[key]):
                    print(f"counts differ between {first.workers} and {w} workers: {key}")
                    return 1
        rows.append({"workers": w, "seconds": round(res.seconds, 2),
                     "trials_per_second": round(res.trials_per_second, 3),
                     "cpu_seconds": round(cpu, 2), "cpu_share": round(cpu / (w * wall), 3),
                     "trials_per_cpu_second": round(spec.trials / cpu, 3),
                     "load_before": round(load0, 2), "load_after": round(load1, 2)})
    base = rows[0]["trials_per_second"]
    for r in rows:
        r["speedup"] = round(r["trials_per_second"] / base, 3)
    print(f"dptbd compare Monte Carlo: {spec.trials} trials, {spec.size}x{spec.size}, "
          f"{spec.frames} frames, K={spec.segment_frames}, {len(spec.snr)} SNRs + noise only, "
          f"{len(spec.configs)} configurations; {os.cpu_count()} CPUs, {platform.processor() or platform.machine()}")
    print("| workers | seconds | trials/s | speed-up | CPU share | trials per CPU-s | "
          "load avg before/after |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['workers']} | {r['seconds']:.1f} | {r['trials_per_second']:.2f} | "
              f"{r['speedup']:.2f} | {r['cpu_share']:.2f} | {r['trials_per_cpu_second']:.2f} | "
              f"{r['load_before']:.1f} / {r['load_after']:.1f} |")
    print("counts identical across worker counts: yes")
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps({
            "trials": spec.trials, "configs": len(spec.configs), "rows": rows,
            "cpus": os.cpu_count(), "when": time.strftime("%Y-%m-%d %H:%M:%S")}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
