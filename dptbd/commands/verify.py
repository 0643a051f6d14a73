"""``dptbd verify``: the verification campaign (:mod:`dptbd.sim.campaign`) — every parameter
set's seeded runs through the compiled RTL (Verilator), every output word compared with the
golden model, plus the 4-state checks of DPCore's external store on Icarus.

Prints one line per case (design, runs, words in, words compared, words per second of
simulation, verdict with the first failing run's report) and the totals; exit 1 on any
mismatch. ``--json`` writes every run's outcome.

``--mutants N`` runs the mutation score instead (:mod:`dptbd.sim.mutation`): N mutants of
``--design`` (``seg``: ``dptbd_seg``, ``axi``: ``dptbd_axi``) sampled with ``--seed``, each
through the verification slice; prints killed / total, the timeouts, crashes and mutations
Yosys refused apart, and every survivor with its Amaranth source line and mutation
(``--prove``: with its formal equivalence verdict). Exit 1 if a mutant survives unproven.
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
    parser.add_argument("--force", action="store_true", help="overwrite --json")
    mutation = parser.add_argument_group("mutation score (docs/verification.md)")
    mutation.add_argument("--mutants", type=int, default=None, metavar="N",
                          help="run N mutants of --design through the verification slice "
                               "instead of the campaign (Yosys mutate, seed --seed)")
    mutation.add_argument("--design", choices=("seg", "axi"), default="seg",
                          help="the top level of --mutants: seg (dptbd_seg, default) or axi "
                               "(dptbd_axi)")
    mutation.add_argument("--prove", action="store_true",
                          help="try to prove every survivor equivalent to the original "
                               "(Yosys equiv_*, minutes each)")
    mutation.add_argument("--scheduler", metavar="tcp://HOST:PORT", default=None,
                          help="run the mutants on this existing dask cluster "
                               "(docs/distributed.md)")


def main(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from dptbd.sim.campaign import default_cases, run_campaign

    if args.mutants is not None:
        return mutants_main(args)
    cases = default_cases()
    if args.list:
        for c in cases:
            cfg = c.cfg
            print(f"{c.name:28s} {c.design:9s} {cfg.describe()}  {c.runs} runs x {c.frames} "
                  f"frames  faults: "
                  f"{', '.join(c.faults) or '-'}{', random LUT' if c.random_lut else ''}")
        return 0
    check_real("--runs-scale", args.runs_scale, 0.0, lo_open=True)
    if args.workers is not None:
        check_int("--workers", args.workers, 1)
    if args.cases:
        known = {c.name for c in cases}
        unknown = [n for n in args.cases if n not in known]
        if unknown:
            raise ValueError(f"unknown case(s) {', '.join(unknown)}; dptbd verify --list "
                             f"names them")
        cases = [c for c in cases if c.name in args.cases]
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


def mutants_main(args: argparse.Namespace) -> int:
    """``--mutants N``: the mutation score of ``--design`` (see the module doc)."""
    from tqdm import tqdm

    from dptbd.sim.mutation.netlist import require_yosys
    from dptbd.sim.mutation.run import run_mutants

    check_int("--mutants", args.mutants, 1)
    if args.workers is not None:
        check_int("--workers", args.workers, 1)
    check_output_file(args.json, "--json", args.force, ".json")
    require_yosys()
    design = {"seg": "segmenter", "axi": "axi"}[args.design]
    bar = tqdm(total=args.mutants, unit="mutant", desc=f"dptbd verify --mutants ({args.design})")
    result = run_mutants(design, args.mutants, args.seed, workers=args.workers,
                         scheduler=args.scheduler, bar=bar)
    bar.close()
    proofs = {}
    if args.prove:
        from dptbd.sim.mutation.equivalence import prove_equivalent
        from dptbd.sim.mutation.run import config
        for outcome, mutation in result.of("survived"):
            proofs[outcome.index] = prove_equivalent(config(design), design, mutation)
    print(format_mutation_result(result, proofs))
    if args.json is not None:
        tmp = args.json.with_name(args.json.name + ".tmp")
        tmp.write_text(json.dumps({
            "design": design, "seed": result.seed, "total": result.total,
            "killed": result.killed, "score": result.score,
            "wall_seconds": result.wall_seconds, "workers": result.workers,
            "runs": [list(r) for r in result.runs],
            "mutants": [dict(dataclasses.asdict(o), source=m.source, mutation=m.command,
                             equivalence=(dataclasses.asdict(proofs[o.index])
                                          if o.index in proofs else None))
                        for o, m in zip(result.outcomes, result.mutations)]}, indent=1) + "\n")
        tmp.replace(args.json)
    unproven = [o for o, _ in result.of("survived")
                if o.index not in proofs or proofs[o.index].verdict != "equivalent"]
    return 1 if unproven else 0


def format_mutation_result(result, proofs: dict | None = None) -> str:
    """The score line, the counts apart from killed, and one line per mutant not killed:
    index, verdict, Amaranth source line, mutation (and the proof's verdict, if any)."""
    from dptbd.sim.mutation.netlist import DESIGN_TOPS

    proofs = proofs or {}
    lines = [f"{DESIGN_TOPS[result.design]}: {result.killed} / {result.total} mutants killed "
             f"({100 * result.score:.1f} %), seed {result.seed}, {len(result.runs)} runs per "
             f"mutant at most, {result.wall_seconds:.1f} s wall on {result.workers} workers",
             "not killed: " + ", ".join(f"{result.count(v)} {v}" for v in
                                        ("survived", "timeout", "crashed", "no-build"))]
    for verdict in ("survived", "timeout", "crashed", "no-build"):
        for outcome, mutation in result.of(verdict):
            proof = proofs.get(outcome.index)
            what = f" [{proof.verdict}]" if proof is not None else ""
            where = f" ({outcome.run}: {outcome.report[:120]})" if outcome.run else ""
            lines.append(f"  #{outcome.index:<4d} {verdict}{what} {mutation.source}  "
                         f"{mutation.describe()}{where}")
    if proofs:
        proven = sum(p.verdict == "equivalent" for p in proofs.values())
        lines.append(f"survivors proven equivalent: {proven} of {len(proofs)}")
    return "\n".join(lines)
