"""``dptbd verify``: the verification campaign (:mod:`dptbd.sim.campaign`) — every parameter
set's seeded runs through the compiled RTL (Verilator), every output word compared with the
golden model, plus the 4-state checks of DPCore's external store on Icarus.

Prints one line per case (design, runs, words in, words compared, words per second of
simulation, verdict with the first failing run's report) and the totals; exit 1 on any
mismatch. ``--json`` writes every run's outcome. ``--coverage DIR`` runs the cases (and the
AXI top's runs) on coverage builds instead and writes the code-coverage report
(:mod:`dptbd.sim.coverage.report`) into DIR.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import pathlib

from dptbd.errors import check_int, check_real
from dptbd.output_folder import check_output_file


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--runs-scale", type=float, default=1.0, metavar="X",
                        help="multiply every case's number of runs (default 1: about 10^8 "
                             "compared words; 0.01 for a quick look)")
    parser.add_argument("--seed", type=int, default=0, help="base seed (default 0)")
    parser.add_argument("--workers", type=int, default=None,
                        help="processes (default: the machine's cores)")
    parser.add_argument("--cases", nargs="+", metavar="NAME",
                        help="only these cases (default all; --list names them)")
    parser.add_argument("--list", action="store_true", help="list the cases and exit")
    parser.add_argument("--no-x-store", action="store_true",
                        help="skip the 4-state (Icarus) external-store checks")
    parser.add_argument("--json", type=pathlib.Path, metavar="FILE.json",
                        help="write every run's outcome as JSON (refused if it exists, unless "
                             "--force)")
    parser.add_argument("--coverage", type=pathlib.Path, metavar="DIR",
                        help="run on coverage builds and write the code-coverage report (line, "
                             "branch, toggle per module, uncovered points with their Amaranth "
                             "source line, annotated sources) into DIR (refused if it exists, "
                             "unless --force)")
    parser.add_argument("--force", action="store_true", help="overwrite --json / --coverage")


def main(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from dptbd.sim.campaign import default_cases, run_campaign

    cases = default_cases()
    if args.list:
        for c in cases:
            cfg = c.cfg
            print(f"{c.name:28s} {c.design:9s} {cfg.describe()}  {c.runs} runs x {c.frames} "
                  f"frames  faults: "
                  f"{', '.join(c.faults) or '-'}{', random LUT' if c.random_lut else ''}")
        from dptbd.sim.coverage.report import axi_cases, extra_cases
        for c in [*extra_cases(), *axi_cases()]:
            print(f"{c.name:28s} {c.design:9s} {c.runs} runs  (--coverage only)")
        return 0
    check_real("--runs-scale", args.runs_scale, 0.0, lo_open=True)
    if args.workers is not None:
        check_int("--workers", args.workers, 1)
    axi = []
    if args.coverage is not None:
        from dptbd.sim.coverage.report import axi_cases, extra_cases
        axi = axi_cases()
        cases = cases + extra_cases()
    if args.cases:
        known = {c.name for c in cases} | {a.name for a in axi}
        unknown = [n for n in args.cases if n not in known]
        if unknown:
            raise ValueError(f"unknown case(s) {', '.join(unknown)}; dptbd verify --list "
                             f"names them")
        cases = [c for c in cases if c.name in args.cases]
        axi = [a for a in axi if a.name in args.cases]
    if args.coverage is not None:
        return _coverage(args, cases, axi)
    check_output_file(args.json, "--json", args.force, ".json")

    total = sum(max(1, round(c.runs * args.runs_scale)) for c in cases)
    bar = tqdm(total=total + (0 if args.no_x_store else 4), unit="run", desc="dptbd verify")

    def seen(outcome) -> None:
        bar.update(1)
        if not outcome.passed:
            bar.write(f"MISMATCH {outcome.case} seed {outcome.seed}: {outcome.report} "
                      f"({'; '.join(outcome.notes)})")

    result = run_campaign(cases, runs_scale=args.runs_scale, base_seed=args.seed,
                          workers=args.workers, x_store=not args.no_x_store, on_outcome=seen)
    bar.close()
    print(f"\n{'case':28s} {'design':22s} {'runs':>5s} {'words in':>12s} "
          f"{'words compared':>15s} {'words/s':>10s}  verdict")
    for c in result.cases:
        rate = f"{c.words_per_second / 1e6:8.2f} M" if c.sim_seconds > 0 else f"{'-':>10s}"
        verdict = "bit-exact" if c.passed else (
            f"MISMATCH (seed {c.first_failure.seed}): {c.first_failure.report}")
        print(f"{c.name:28s} {c.design:22s} {c.runs:5d} {c.words_in:12d} {c.words_out:15d} "
              f"{rate}  {verdict}")
    rate = result.words_out / result.wall_seconds if result.wall_seconds else 0.0
    print(f"\ntotal: {result.words_out} words compared ({result.words_in} in), "
          f"{result.mismatches} mismatching runs of {len(result.outcomes)}, "
          f"{result.wall_seconds:.1f} s wall on {result.workers} workers "
          f"({rate / 1e6:.2f} M compared words/s overall)")
    if args.json is not None:
        tmp = args.json.with_name(args.json.name + ".tmp")
        tmp.write_text(json.dumps({
            "passed": result.passed, "words_compared": result.words_out,
            "words_in": result.words_in, "wall_seconds": result.wall_seconds,
            "workers": result.workers,
            "cases": [dict(dataclasses.asdict(c), first_failure=None) for c in result.cases],
            "runs": [dataclasses.asdict(o) for o in result.outcomes]}, indent=1) + "\n")
        tmp.replace(args.json)
    return 0 if result.passed else 1


COVERAGE_TOOL = "dptbd verify --coverage"


def _coverage(args: argparse.Namespace, cases: list, axi: list) -> int:
    """``--coverage DIR``: the runs on coverage builds, the report (terminal table too)."""
    from tqdm import tqdm

    from dptbd.output_folder import staged_folder
    from dptbd.sim.coverage.code import find_verilator_coverage
    from dptbd.sim.coverage.exclusions import load_exclusions
    from dptbd.sim.coverage.report import format_table, run_coverage, write_report

    find_verilator_coverage()
    exclusions = load_exclusions()
    total = sum(max(1, round(c.runs * args.runs_scale)) for c in [*cases, *axi])
    with staged_folder(args.coverage, args.force, marker="coverage.json",
                       tool=COVERAGE_TOOL, option="--coverage") as tmp:
        bar = tqdm(total=total, unit="run", desc="dptbd verify --coverage")
        failed = []

        def seen(outcome) -> None:
            bar.update(1)
            if not outcome.passed:
                failed.append(outcome)
                bar.write(f"MISMATCH {outcome.case} seed {outcome.seed}: {outcome.report} "
                          f"({'; '.join(outcome.notes)})")

        outcomes, builds = run_coverage(tmp, cases, axi=axi, runs_scale=args.runs_scale,
                                        base_seed=args.seed, workers=args.workers,
                                        on_outcome=seen)
        bar.close()
        summary = write_report(tmp, builds, exclusions)
        data = json.loads((tmp / "coverage.json").read_text())
        data = {"tool": COVERAGE_TOOL, "runs": len(outcomes), "mismatches": len(failed),
                "cases": [c.name for c in [*cases, *axi]], "runs_scale": args.runs_scale,
                **data}
        (tmp / "coverage.json").write_text(json.dumps(data, indent=1) + "\n")
    print("\n" + format_table(summary))
    print(f"\n{len(outcomes)} runs on coverage builds, {len(failed)} mismatching; report: "
          f"{args.coverage / 'report.md'}")
    return 0 if not failed else 1
