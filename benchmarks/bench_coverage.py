"""The cost of code coverage (``dptbd verify --coverage``), measured in one run.

1. **Build**: the plain and the coverage build of one top level from an empty build root
   each (the runtime library compiled too), wall and CPU seconds of this process' children,
   and the ratio.
2. **Run**: the same campaign run (``dptbd.sim.campaign.make_run`` of the case, one seed) on
   both builds, both checked bit-exact; simulated cycles per second of the harness loop and
   the slowdown; the size of the coverage file.
3. **Campaign with coverage** (``--campaign``): ``dptbd verify --coverage`` of the given
   cases at ``--runs-scale``, its wall time and the report's table.

    python benchmarks/bench_coverage.py                          # segmenter-33x17-k2-n3
    python benchmarks/bench_coverage.py --case 37x23-k3-in8-e12-f4
    python benchmarks/bench_coverage.py --campaign --runs-scale 0.25
"""

from __future__ import annotations

import argparse
import os
import pathlib
import sys
import tempfile
import time


def _cpu() -> float:
    """CPU seconds of this process (the Verilog generation, Yosys in-process) and of its
    finished children (Verilator, make, the C++ compiler, the simulation)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def build_and_run(case_name: str, seed: int) -> None:
    from dptbd.sim.campaign import default_cases, make_run
    from dptbd.sim.rtl.check import check_stream
    from dptbd.sim.verilator import build

    case = next(c for c in default_cases() if c.name == case_name)
    words, stim, _ = make_run(case, seed)
    with tempfile.TemporaryDirectory(prefix="bench-coverage-") as tmp:
        tmp = pathlib.Path(tmp)
        figures = {}
        for coverage in (False, True):
            cpu, start = _cpu(), time.perf_counter()
            sim = build(case.cfg, case.design, root=tmp / ("cov" if coverage else "plain"),
                        coverage=coverage)
            wall, build_cpu = time.perf_counter() - start, _cpu() - cpu
            dat = tmp / "run.dat" if coverage else None
            result = check_stream(sim, words, stim, coverage=dat)
            figures[coverage] = (wall, build_cpu, result)
            print(f"{'coverage' if coverage else 'plain':8s} build of {case.name} "
                  f"({sim.toplevel}): {wall:7.1f} s wall, {build_cpu:.1f} s CPU; run: "
                  f"{result.raw.cycles} "
                  f"cycles, {result.raw.cycles_per_second / 1e6:.3f} M cycles/s, "
                  f"{'bit-exact' if result.passed else 'MISMATCH ' + result.report}"
                  + (f", coverage file {dat.stat().st_size / 1e6:.1f} MB" if dat else ""))
        (pw, pc, pr), (cw, cc, cr) = figures[False], figures[True]
        print(f"coverage / plain: build {cw / pw:.2f} x wall, {cc / pc:.2f} x CPU; run "
              f"{pr.raw.cycles_per_second / cr.raw.cycles_per_second:.2f} x slower "
              f"(cycles per second of the harness loop)")


def campaign(cases: list[str], runs_scale: float, workers: int | None) -> None:
    from dptbd.cli import main

    with tempfile.TemporaryDirectory(prefix="bench-coverage-") as tmp:
        out = pathlib.Path(tmp) / "coverage"
        argv = ["verify", "--coverage", str(out), "--runs-scale", str(runs_scale)]
        argv += ["--cases", *cases] if cases else []
        argv += ["--workers", str(workers)] if workers else []
        start = time.perf_counter()
        code = main(argv)
        print(f"dptbd {' '.join(argv)}: exit {code}, {time.perf_counter() - start:.1f} s wall "
              f"(builds included)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", default="segmenter-33x17-k2-n3",
                        help="campaign case for the build and run ratios")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--campaign", action="store_true",
                        help="also time dptbd verify --coverage")
    parser.add_argument("--cases", nargs="*", default=[],
                        help="cases of the --campaign run (default all)")
    parser.add_argument("--runs-scale", type=float, default=0.25)
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args(argv)
    build_and_run(args.case, args.seed)
    if args.campaign:
        campaign(args.cases, args.runs_scale, args.workers)
    return 0


if __name__ == "__main__":
    sys.exit(main())
