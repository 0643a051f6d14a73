"""Time per formal proof (``dptbd verify --formal``'s tasks, :mod:`dptbd.sim.formal.tasks`).

    python benchmarks/bench_formal.py                       # every task
    python benchmarks/bench_formal.py --tasks m_axis_cand dp_pipeline
    python benchmarks/bench_formal.py --json build/bench_formal.json

Each task's proof run and cover run are timed one after the other (wall seconds of
``yowasp-sby``, and the CPU seconds of it and its solver processes); printed with the mode,
the verdict and the depth reached (a task's CPU seconds are split between its two runs in
proportion to their wall times). The machine's load average is printed: on a shared
machine the wall time is the machine's, the CPU seconds are the figure to compare.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import sys


def _cpu_children() -> float:
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return kids.ru_utime + kids.ru_stime


def main(argv=None) -> int:
    from dptbd.sim.formal.runner import find_tools, run_task
    from dptbd.sim.formal.tasks import TASKS, task

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tasks", nargs="+", metavar="NAME", help="only these tasks")
    ap.add_argument("--json", metavar="PATH", help="also write the numbers as JSON")
    args = ap.parse_args(argv)
    chosen = [task(n) for n in args.tasks] if args.tasks else list(TASKS)
    tools = find_tools()
    print(f"python {platform.python_version()}, load average {os.getloadavg()[0]:.1f}")
    print(f"{'task':24s} {'run':6s} {'mode':6s} {'verdict':8s} {'depth':>5s} {'wall s':>8s} "
          f"{'CPU s':>8s}")
    rows = []
    for t in chosen:
        before = _cpu_children()
        results = run_task(t, tools=tools)
        cpu = _cpu_children() - before
        wall = sum(r.seconds for r in results)
        for r in results:
            share = cpu * r.seconds / wall if wall else 0.0   # CPU split by wall time
            print(f"{t.name:24s} {r.kind:6s} {r.mode:6s} {r.verdict:8s} {r.depth:5d} "
                  f"{r.seconds:8.1f} {share:8.1f}")
            rows.append({"task": t.name, "run": r.kind, "mode": r.mode, "verdict": r.verdict,
                         "depth": r.depth, "wall_seconds": r.seconds, "cpu_seconds": share})
    print(f"load average after: {os.getloadavg()[0]:.1f}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"load_average": os.getloadavg()[0], "runs": rows}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
