"""``dptbd verify``: the verification campaign (:mod:`dptbd.sim.campaign`) — every parameter
set's seeded runs through the compiled RTL (Verilator), every output word compared with the
golden model, plus the 4-state checks of DPCore's external store on Icarus.

Prints one line per case (design, runs, words in, words compared, words per second of
simulation, verdict with the first failing run's report), the totals and the functional
coverage (:mod:`dptbd.sim.coverage.bins`: every bin the campaign's designs fill, the designs
whose cases fill it, its hits); exit 1 on any mismatch or any empty bin (named). ``--json``
writes every run's outcome and the bins. ``--coverage DIR`` runs the cases (and the
AXI top's coverage runs) on coverage builds instead and writes the code-coverage report
(:mod:`dptbd.sim.coverage.report`) into DIR. The runs go to the Dask execution layer
(``--workers``, ``--scheduler``, ``--dashboard``: ``docs/distributed.md``).

``--formal`` runs the formal proofs instead (:mod:`dptbd.sim.formal`): one line per proof
and cover run (verdict, mode, depth reached, seconds; on a failure the Amaranth line of the
assertion and the counterexample trace kept under ``--out``); exit 1 unless every verdict is
the expected one.

``--mutants N`` runs the mutation score instead (:mod:`dptbd.sim.mutation`): N mutants of
``--design`` (``seg``: ``dptbd_seg``, ``axi``: ``dptbd_axi``, ``dp``: ``dptbd_dp``, ``dp2`` /
``dp4``: ``dptbd_dp`` at 2 / 4 pixels per clock) sampled
with ``--seed``, each through the verification slice; prints the score, MCY's: killed /
(total − shown equivalent), with killed / total next to it, and every mutant not killed
with its Amaranth source line and mutation: the survivors proven equivalent, argued
equivalent (both from the equivalence registry, :mod:`dptbd.sim.mutation.equivalents`) and
not shown equivalent, then the timeouts, crashes and mutations Yosys refused (``--prove``:
each survivor the registry does not list is tried for formal equivalence, and one proven
counts as proven, marked as not yet in the registry). Exit 1 if a mutant survives without
being shown equivalent.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import pathlib

from dptbd.commands.options import add_execution_arguments
from dptbd.errors import check_int, check_real
from dptbd.evaluation.execution import check_worker_count
from dptbd.output_folder import check_output_file


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--runs-scale", type=float, default=1.0, metavar="X",
                        help="multiply every case's number of runs (default 1: about 10^8 "
                             "compared words; 0.01 for a quick look)")
    parser.add_argument("--seed", type=int, default=0, help="base seed (default 0)")
    add_execution_arguments(parser)
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
    parser.add_argument("--force", action="store_true",
                        help="overwrite --json, --coverage or --out")
    parser.add_argument("--formal", action="store_true",
                        help="run the formal proofs (SymbiYosys, Boolector) instead of the "
                             "campaign")
    parser.add_argument("--out", type=pathlib.Path, metavar="DIR",
                        help="with --formal: keep every run (SBY files, logs, counterexample "
                             "traces) and formal.json in this new folder")

    mutation = parser.add_argument_group('mutation score (docs/gateware.md, "Mutation testing")')
    mutation.add_argument("--mutants", type=int, default=None, metavar="N",
                          help="run N mutants of --design through the verification slice "
                               "instead of the campaign (Yosys mutate, seed --seed)")
    mutation.add_argument("--design", choices=("seg", "axi", "dp", "dp2", "dp4"), default="seg",
                          help="the top level of --mutants: seg (dptbd_seg, default), axi "
                               "(dptbd_axi), dp (dptbd_dp), dp2 or dp4 (dptbd_dp at 2 or 4 "
                               "pixels per clock)")
    mutation.add_argument("--prove", action="store_true",
                          help="try to prove every survivor the equivalence registry does "
                               "not list equivalent to the original (Yosys equiv_*, "
                               "minutes each)")


#: Options of the campaign, refused with --formal: (attribute, option, default).
CAMPAIGN_OPTIONS = (("runs_scale", "--runs-scale", 1.0), ("seed", "--seed", 0),
                    ("workers", "--workers", None), ("cases", "--cases", None),
                    ("list", "--list", False), ("no_x_store", "--no-x-store", False),
                    ("json", "--json", None), ("coverage", "--coverage", None))


def main(args: argparse.Namespace) -> int:
    if args.formal:
        given = [option for name, option, default in CAMPAIGN_OPTIONS
                 if getattr(args, name) != default]
        if given:
            raise ValueError(f"{', '.join(given)}: option(s) of the campaign, not of "
                             f"--formal (which takes --out and --force)")
        return formal_main(args)
    if args.out is not None:
        raise ValueError("--out is an option of --formal (the campaign writes --json)")
    from tqdm import tqdm

    from dptbd.sim.campaign import default_cases, run_campaign

    if args.mutants is not None:
        return mutants_main(args)
    cases = default_cases()
    if args.list:
        for c in cases:
            cfg = c.cfg
            built = "" if c.family is None else f", {c.family} build"
            print(f"{c.name:28s} {c.design:9s} {cfg.describe()}{built}  {c.runs} runs x "
                  f"{c.frames} frames  faults: "
                  f"{', '.join(c.faults) or '-'}{', random LUT' if c.random_lut else ''}")
        from dptbd.sim.coverage.report import axi_cases, extra_cases
        for c in [*extra_cases(), *axi_cases()]:
            print(f"{c.name:28s} {c.design:9s} {c.runs} runs  (--coverage only)")
        return 0
    check_real("--runs-scale", args.runs_scale, 0.0, lo_open=True)
    if args.workers is not None:
        check_worker_count(args.workers)
    axi = []
    if args.coverage is not None:
        from dptbd.sim.coverage.report import axi_cases, extra_cases
        axi = axi_cases()
        # the --state-store axi builds have no coverage build: their cases run without
        # --coverage
        cases = [c for c in cases if c.design not in ("dp_axi", "axi_store")] + extra_cases()
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

    try:
        result = run_campaign(cases, runs_scale=args.runs_scale, base_seed=args.seed,
                              workers=args.workers, x_store=not args.no_x_store,
                              on_outcome=seen, scheduler=args.scheduler,
                              dashboard=args.dashboard)
    finally:
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
    bins, empty = _print_bins(result.bins)
    if args.json is not None:
        tmp = args.json.with_name(args.json.name + ".tmp")
        tmp.write_text(json.dumps({
            "passed": result.passed, "words_compared": result.words_out,
            "words_in": result.words_in, "wall_seconds": result.wall_seconds,
            "workers": result.workers, "bins": bins, "empty_bins": empty,
            "cases": [dict(dataclasses.asdict(c), first_failure=None) for c in result.cases],
            "runs": [dataclasses.asdict(o) for o in result.outcomes]}, indent=1) + "\n")
        tmp.replace(args.json)
    return 0 if result.passed and not empty else 1


def _print_bins(bins: dict) -> tuple[dict, list[str]]:
    """Print the functional coverage table and its verdict; the bins in table order and the
    empty ones."""
    from dptbd.sim.coverage.bins import empty_bins, empty_message, table

    rows = table(bins)
    if not rows:
        return {}, []
    width = max(len(name) for name, _, _ in rows)
    print(f"\n{'bin':{width}s}  {'filled by cases of':28s} {'hits':>12s}")
    for name, designs, hits in rows:
        print(f"{name:{width}s}  {designs:28s} {hits:12d}")
    empty = empty_bins(bins)
    print("\n" + (empty_message(empty) if empty else
                  f"functional coverage: all {len(rows)} bins hit"))
    return {name: hits for name, _, hits in rows}, empty


def formal_main(args: argparse.Namespace) -> int:
    """``dptbd verify --formal``: every task of :data:`dptbd.sim.formal.tasks.TASKS`."""
    from dptbd.output_folder import json_text, staged_folder
    from dptbd.sim.formal.runner import find_tools, run_task
    from dptbd.sim.formal.tasks import TASKS

    tools = find_tools()
    print(f"{'task':24s} {'run':6s} {'mode':6s} {'verdict':8s} {'depth':>5s} {'seconds':>8s}")

    def run_all(out):
        results, ok = [], True
        for t in TASKS:
            for r in run_task(t, out=out, tools=tools):
                ok &= r.as_expected
                note = "" if r.as_expected else f"  expected {r.expected}"
                if r.as_expected and r.verdict == "FAIL":
                    note = "  (known-bad: expected)"
                print(f"{t.name:24s} {r.kind:6s} {r.mode:6s} {r.verdict:8s} {r.depth:5d} "
                      f"{r.seconds:8.1f}{note}")
                for failed in r.failed:
                    print(f"    {'unreached' if r.kind == 'cover' else 'failed'}: {failed}")
                if r.trace:
                    print(f"    trace: {(args.out / r.trace) if args.out else r.trace}")
                results.append(dict(dataclasses.asdict(r), workdir=None))
        return results, ok

    if args.out is None:
        results, ok = run_all(None)
    else:
        with staged_folder(args.out, args.force, marker="formal.json",
                           tool="dptbd verify --formal") as tmp:
            results, ok = run_all(tmp)
            (tmp / "formal.json").write_text(json_text(
                {"tool": "dptbd verify --formal", "passed": ok, "runs": results}, indent=1))
    print(f"\n{'all verdicts as expected' if ok else 'UNEXPECTED VERDICTS'}: "
          f"{len(results)} runs of {len(TASKS)} tasks")
    return 0 if ok else 1


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
                                        scheduler=args.scheduler, dashboard=args.dashboard,
                                        on_outcome=seen)
        bar.close()
        summary = write_report(tmp, builds, exclusions, prove_constants=True)
        data = json.loads((tmp / "coverage.json").read_text())
        data = {"tool": COVERAGE_TOOL, "runs": len(outcomes), "mismatches": len(failed),
                "cases": [c.name for c in [*cases, *axi]], "runs_scale": args.runs_scale,
                **data}
        (tmp / "coverage.json").write_text(json.dumps(data, indent=1) + "\n")
    print("\n" + format_table(summary))
    print(f"\n{len(outcomes)} runs on coverage builds, {len(failed)} mismatching; report: "
          f"{args.coverage / 'report.md'}")
    return 0 if not failed else 1


def mutants_main(args: argparse.Namespace) -> int:
    """``--mutants N``: the mutation score of ``--design`` (see the module doc)."""
    from tqdm import tqdm

    from dptbd.sim.mutation.equivalents import load_registry
    from dptbd.sim.mutation.netlist import require_yosys
    from dptbd.sim.mutation.run import run_mutants

    check_int("--mutants", args.mutants, 1)
    if args.workers is not None:
        check_worker_count(args.workers)
    check_output_file(args.json, "--json", args.force, ".json")
    require_yosys()
    design = {"seg": "segmenter", "axi": "axi", "dp": "dp", "dp2": "dp2", "dp4": "dp4"}[args.design]
    bar = tqdm(total=args.mutants, unit="mutant", desc=f"dptbd verify --mutants ({args.design})")
    result = run_mutants(design, args.mutants, args.seed, workers=args.workers,
                         scheduler=args.scheduler, bar=bar)
    bar.close()
    registry = load_registry(design)
    proofs = {}
    if args.prove:                      # the survivors the registry does not list
        from dptbd.sim.mutation.equivalence import prove_equivalent
        from dptbd.sim.mutation.run import config
        listed = result.shown_equivalent(registry)
        for outcome, mutation in result.of("survived"):
            if outcome.index not in listed:
                proofs[outcome.index] = prove_equivalent(config(design), design, mutation)
    print(format_mutation_result(result, proofs, registry))
    shown = result.shown_equivalent(registry, proofs)
    if args.json is not None:
        tmp = args.json.with_name(args.json.name + ".tmp")
        tmp.write_text(json.dumps({
            "design": design, "seed": result.seed, "total": result.total,
            "killed": result.killed, "shown_equivalent": len(shown),
            "score": result.score(shown), "killed_fraction": result.killed_fraction,
            "wall_seconds": result.wall_seconds, "workers": result.workers,
            "runs": [list(r) for r in result.runs],
            "mutants": [dict(dataclasses.asdict(o), source=m.source, mutation=m.command,
                             shown_equivalent=shown.get(o.index),
                             equivalence=(dataclasses.asdict(proofs[o.index])
                                          if o.index in proofs else None))
                        for o, m in zip(result.outcomes, result.mutations)]}, indent=1) + "\n")
        tmp.replace(args.json)
    unshown = [o for o, _ in result.of("survived") if o.index not in shown]
    return 1 if unshown else 0


def format_mutation_result(result, proofs: dict | None = None,
                           registry: dict | None = None) -> str:
    """The score (MCY's: killed / (total − shown equivalent)) with killed / total next to
    it, the counts of the mutants not killed, then every one of them by class: survivors
    proven equivalent, argued equivalent (``registry``, default the design's file in
    :mod:`dptbd.sim.mutation.equivalents`; ``proofs``: this run's proofs, index ->
    :class:`~dptbd.sim.mutation.equivalence.Equivalence`), not shown equivalent, then the
    timeouts, crashes and no-builds: index, Amaranth source line, mutation."""
    from dptbd.sim.mutation.equivalents import load_registry
    from dptbd.sim.mutation.netlist import DESIGN_TOPS
    from dptbd.sim.mutation.run import config

    proofs = proofs or {}
    registry = load_registry(result.design) if registry is None else registry
    shown = result.shown_equivalent(registry, proofs)
    left = result.total - len(shown)
    proven = [i for i, how in shown.items() if how != "argued"]
    here = [i for i, how in shown.items() if how == "proven in this run"]
    survivors = result.of("survived")
    p = config(result.design).pixels_per_clock
    top = DESIGN_TOPS[result.design] + (f" at {p} pixels per clock" if p > 1 else "")
    lines = [f"{top}: score (MCY's: killed / (total - shown "
             f"equivalent)) {result.killed} / {left} = {100 * result.score(shown):.1f} %; "
             f"killed / total {result.killed} / {result.total} = "
             f"{100 * result.killed_fraction:.1f} %",
             f"seed {result.seed}, {len(result.runs)} runs per mutant at most, "
             f"{result.wall_seconds:.1f} s wall on {result.workers} workers",
             f"not killed: {len(survivors)} survived ({len(proven)} proven equivalent, "
             f"{len(shown) - len(proven)} argued equivalent, {len(survivors) - len(shown)} not "
             f"shown equivalent), " + ", ".join(f"{result.count(v)} {v}" for v in
                                                 ("timeout", "crashed", "no-build"))]

    def line(outcome, mutation, note: str = "") -> str:
        where = f" ({outcome.run}: {outcome.report[:120]})" if outcome.run else ""
        return (f"  #{outcome.index:<4d} {mutation.source}  {mutation.describe()}{note}"
                f"{where}")

    groups = [("survived, proven equivalent", [
                  (o, m, " [proven in this run, not in the registry]" if o.index in here else "")
                  for o, m in survivors if o.index in proven]),
              ("survived, argued equivalent",
               [(o, m, "") for o, m in survivors if shown.get(o.index) == "argued"]),
              ("survived, not shown equivalent", [
                  (o, m, f" [proof: {proofs[o.index].verdict}]" if o.index in proofs else "")
                  for o, m in survivors if o.index not in shown])]
    groups += [(verdict, [(o, m, "") for o, m in result.of(verdict)])
               for verdict in ("timeout", "crashed", "no-build")]
    for title, members in groups:
        if members:
            lines.append(f"{title} ({len(members)}):")
            lines += [line(o, m, note) for o, m, note in members]
    wrong = result.registered_not_surviving(registry)
    if wrong:
        lines.append(f"in the registry as equivalent but not surviving ({len(wrong)}): "
                     + ", ".join(f"#{o.index} {o.verdict}" for o, _ in wrong))
    return "\n".join(lines)
