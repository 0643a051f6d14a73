"""The detection chain end to end on a named scenario over seeds: clean runs, frames until output.

    python benchmarks/bench_chain.py --scenario paper001-experiment-2 --seeds 0-39
    python benchmarks/bench_chain.py --scenario manoeuvring --seeds 0-39 --workers 2
    python benchmarks/bench_chain.py --scenario crossing --seeds 0-39 --runs runs.csv

Today's default chain (K = 6 segments, ``--lists`` ideal or gateware, the DSP association
with its default settings) on ``--scenario`` (``paper001-experiment-2``, ``manoeuvring``,
``crossing``) for every seed of ``--seeds A-B``; prints the summary (clean runs, all targets
confirmed, false tracks, median frames until output with its 95 % interval) and, with
``--runs FILE.csv``, writes one row per run. ``--workers`` / ``--scheduler``: the execution
layer. Definitions: ``docs/association.md``, "The chain end to end".

Library: ``dptbd.evaluation.end_to_end``. This script reports; it asserts nothing.
"""

from __future__ import annotations

import argparse
import csv
import pathlib

from dptbd.errors import DptbdError
from dptbd.evaluation import end_to_end as e2e
from dptbd.evaluation.chain import LISTS


def report(summary: e2e.ChainSummary, runs_csv: pathlib.Path | None) -> None:
    print("\n".join(summary.lines()), flush=True)
    if runs_csv is not None:
        with open(runs_csv, "w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            n = len(summary.runs[0].frames_until_output)
            w.writerow(["seed", *(f"frames_until_output_{j + 1}" for j in range(n)),
                        "false_tracks", "clean"])
            for r in summary.runs:
                w.writerow([r.seed, *("" if f is None else f for f in r.frames_until_output),
                            r.false_tracks, int(r.clean)])


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default=e2e.SCENARIOS[0], help=", ".join(e2e.SCENARIOS))
    ap.add_argument("--seeds", default="0-39", help="A-B, both included")
    ap.add_argument("--lists", default="ideal", help=", ".join(LISTS))
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--scheduler", default=None)
    ap.add_argument("--runs", type=pathlib.Path, default=None, help="write one row per run (CSV)")
    args = ap.parse_args(argv)
    try:
        sc = e2e.scenario(args.scenario)
        seeds = e2e.parse_seeds(args.seeds)
        if args.lists not in LISTS:
            raise e2e.ChainError(f"lists must be one of {', '.join(map(repr, LISTS))}, "
                                 f"got {args.lists!r}")
    except DptbdError as exc:
        ap.error(str(exc))
    report(e2e.run_chain(sc, seeds, lists=args.lists, workers=args.workers,
                         scheduler=args.scheduler), args.runs)


if __name__ == "__main__":
    main()
