"""The detection chain end to end on a named scenario over seeds: clean runs, frames until output.

    python benchmarks/bench_chain.py --scenario paper001-experiment-2 --seeds 0-39
    python benchmarks/bench_chain.py --scenario manoeuvring --seeds 0-39 --workers 2
    python benchmarks/bench_chain.py --scenario crossing --seeds 0-39 --runs runs.csv
    python benchmarks/bench_chain.py --seeds 100-199 --dp segment_frames=8 --set link_gate=2
    python benchmarks/bench_chain.py --seeds 100-199 --false-alarm-rate 0.003

Today's default chain (K = 6 segments, ``--lists`` ideal or gateware, the DSP association
with its default settings) on ``--scenario`` (``paper001-experiment-2``, ``manoeuvring``,
``crossing``) for every seed of ``--seeds A-B``; prints the summary (clean runs, all targets
confirmed, false tracks, median frames until output with its 95 % interval) and, with
``--runs FILE.csv``, writes one row per run. ``--workers`` / ``--scheduler``: the execution
layer. Another chain on the same scenes: ``--dp segment_frames=8`` (``[dp]`` fields),
``--set KEY=VALUE`` (``[association]`` fields), as in a scenario file;
``--false-alarm-rate R`` (``[segmentation]``: n = R x pixels candidates per list, default
0.002: n = 33). Definitions:
``docs/association.md`` §8, "The chain end to end".

Library: ``dptbd.evaluation.end_to_end``. This script reports; it asserts nothing.
"""

from __future__ import annotations

import argparse
import csv
import pathlib
import tomllib

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


def _pairs(option: str, items: list[str]) -> dict:
    """``KEY=VALUE`` items, each value a TOML value (``8``, ``2.5``, ``true``, ``"x"``)."""
    out = {}
    for item in items:
        key, eq, val = item.partition("=")
        try:
            if not eq or not key.strip():
                raise ValueError
            out[key.strip()] = tomllib.loads(f"v = {val.strip()}")["v"]
        except (ValueError, tomllib.TOMLDecodeError):
            raise e2e.ChainError(f"{option} takes KEY=VALUE with a TOML value, got {item!r}") from None
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default=e2e.SCENARIOS[0], help=", ".join(e2e.SCENARIOS))
    ap.add_argument("--seeds", default="0-39", help="A-B, both included")
    ap.add_argument("--lists", default="ideal", help=", ".join(LISTS))
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--scheduler", default=None)
    ap.add_argument("--runs", type=pathlib.Path, default=None, help="write one row per run (CSV)")
    ap.add_argument("--dp", action="append", default=[], metavar="KEY=VALUE",
                    help="a [dp] (DPConfig) field of the chain, e.g. segment_frames=8 (repeatable)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="an [association] field of the chain (repeatable)")
    ap.add_argument("--false-alarm-rate", type=float, default=None, metavar="R",
                    help="[segmentation] false_alarm_rate: n = R x pixels candidates per list "
                         "(default 0.002)")
    args = ap.parse_args(argv)
    try:
        sc = e2e.scenario(args.scenario)
        if args.dp or args.set or args.false_alarm_rate is not None:
            sc = e2e.variant(sc, dp=_pairs("--dp", args.dp), association=_pairs("--set", args.set),
                             false_alarm_rate=args.false_alarm_rate)
        seeds = e2e.parse_seeds(args.seeds)
        if args.lists not in LISTS:
            raise e2e.ChainError(f"lists must be one of {', '.join(map(repr, LISTS))}, "
                                 f"got {args.lists!r}")
    except DptbdError as exc:
        ap.error(str(exc))
    if args.dp or args.set or args.false_alarm_rate is not None:
        print(f"chain: [dp] {dict(sc.dp)}, [association] {dict(sc.association)}, "
              f"false_alarm_rate {sc.false_alarm_rate:g}")
    report(e2e.run_chain(sc, seeds, lists=args.lists, workers=args.workers,
                         scheduler=args.scheduler), args.runs)


if __name__ == "__main__":
    main()
