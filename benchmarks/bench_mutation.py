"""The mutation score of ``dptbd_seg`` and ``dptbd_axi`` (and ``dptbd_dp``, at P = 1, 2 and
4 pixels per clock), measured: N mutants of each top (Yosys ``mutate``,
:mod:`dptbd.sim.mutation`) through the verification slice, then every survivor the
equivalence registry (:mod:`dptbd.sim.mutation.equivalents`) does not list tried for formal
equivalence: by Yosys ``equiv_*`` from every paired state (``--prove-method equiv``, the
default) or by the miter from reset (``--prove-method reachable``: ABC's ``&scorr`` and PDR,
:mod:`dptbd.sim.mutation.reachable`; ``reachable-scorr``: ABC's ``scorr`` instead).

Reported per design (:func:`dptbd.commands.verify.format_mutation_result`): the score, MCY's:
killed / (total − shown equivalent), and killed / total next to it; survivors proven
equivalent, argued equivalent (the registry) and not shown equivalent, timeouts, crashes and
mutations Yosys refused, one line each (Amaranth source line, mutation); wall time, time per
mutant (the slice) and per proof. ``--json`` keeps every mutant's outcome.

    python benchmarks/bench_mutation.py                        # 300 mutants each, seed 1
    python benchmarks/bench_mutation.py --mutants 100 --designs segmenter --workers 2
    python benchmarks/bench_mutation.py --designs dp           # dptbd_dp (not by default)
    python benchmarks/bench_mutation.py --designs dp2          # dptbd_dp at P = 2 (neither)
    python benchmarks/bench_mutation.py --designs dp4          # dptbd_dp at P = 4 (neither)
    python benchmarks/bench_mutation.py --no-prove --json mutation.json
    python benchmarks/bench_mutation.py --designs dp --prove-method reachable
    python benchmarks/bench_mutation.py --rescore mutation.json   # today's registry, no runs
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import pathlib
import time

from dptbd.commands.verify import format_mutation_result
from dptbd.sim.mutation.equivalents import load_registry
from dptbd.sim.mutation.netlist import DESIGN_TOPS, parse_mutations
from dptbd.sim.mutation.reachable import PROVE_METHODS, prover
from dptbd.sim.mutation.run import MutantOutcome, MutationResult, config, run_mutants


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mutants", type=int, default=300)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--designs", nargs="+", default=["segmenter", "axi"],
                        choices=list(DESIGN_TOPS),
                        help="segmenter (dptbd_seg), axi (dptbd_axi), dp (dptbd_dp), dp2 "
                             "and dp4 (dptbd_dp at 2 and 4 pixels per clock); default "
                             "segmenter axi")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--no-prove", action="store_true", help="skip the equivalence proofs")
    parser.add_argument("--prove-method", choices=PROVE_METHODS, default=None,
                        help="how survivors are proven equivalent: equiv (Yosys equiv_*, "
                             "from every paired state; the default), reachable (the miter "
                             "from reset, ABC's &scorr and PDR) or reachable-scorr (the "
                             "same with ABC's scorr)")
    parser.add_argument("--json", type=pathlib.Path, default=None)
    parser.add_argument("--rescore", type=pathlib.Path, default=None, metavar="JSON",
                        help="report the runs saved by --json again with today's registry "
                             "(no simulation, no proofs)")
    args = parser.parse_args(argv)
    if args.prove_method is not None and (args.no_prove or args.rescore is not None):
        parser.error(f"--prove-method {args.prove_method} proves survivors; it cannot be "
                     f"given with {'--no-prove' if args.no_prove else '--rescore'}, which "
                     f"proves none")
    prove = prover(args.prove_method or "equiv")
    if args.rescore is not None:
        for design, saved in json.loads(args.rescore.read_text()).items():
            print(format_mutation_result(saved_result(design, saved), {}, load_registry(design)))
        return
    report = {}
    for design in args.designs:
        result = run_mutants(design, args.mutants, args.seed, workers=args.workers)
        registry = load_registry(design)
        proofs, start = {}, time.perf_counter()
        listed = result.shown_equivalent(registry)
        survivors = ([(o, m) for o, m in result.of("survived") if o.index not in listed]
                     if not args.no_prove else [])
        if survivors:                   # the proofs on the same workers as the mutants
            from dptbd.evaluation.execution import job_execution, map_tasks

            execution = job_execution(args.workers, tasks=len(survivors))
            tasks = [(config(design), design, mutation) for _, mutation in survivors]

            def said(i, proof):
                print(f"  proof #{survivors[i][0].index}: {proof.verdict} "
                      f"({proof.seconds:.0f} s) {proof.detail}", flush=True)

            with execution.client() as client:
                done = map_tasks(prove, tasks, client, on_result=said)
            proofs = {outcome.index: proof for (outcome, _), proof in zip(survivors, done)}
        prove_seconds = time.perf_counter() - start
        print(format_mutation_result(result, proofs, registry))
        shown = result.shown_equivalent(registry, proofs)
        slice_seconds = sum(o.seconds for o in result.outcomes)
        print(f"slice: {slice_seconds / result.total:.2f} s per mutant (sum of runs), "
              f"proofs: {prove_seconds / max(1, len(proofs)):.0f} s each "
              f"({len(proofs)} tried, {args.prove_method or 'equiv'})\n", flush=True)
        report[design] = {
            "killed": result.killed, "total": result.total, "score": result.score(shown),
            "killed_fraction": result.killed_fraction,
            "counts": {v: result.count(v) for v in ("survived", "timeout", "crashed",
                                                    "no-build")},
            "shown_equivalent": {how: sum(h == how for h in shown.values()) for how in
                                 ("proven", "argued", "proven in this run")},
            "wall_seconds": result.wall_seconds, "prove_seconds": prove_seconds,
            "prove_method": None if args.no_prove else args.prove_method or "equiv",
            "seed": result.seed, "workers": result.workers,
            "runs": [list(r) for r in result.runs],
            "original": dataclasses.asdict(result.original),
            "mutants": [dict(dataclasses.asdict(o), source=m.source, mutation=m.command,
                             shown_equivalent=shown.get(o.index),
                             proof=proofs[o.index].verdict if o.index in proofs else None)
                        for o, m in zip(result.outcomes, result.mutations)]}
    if args.json is not None:
        args.json.write_text(json.dumps(report, indent=1) + "\n")


def saved_result(design: str, saved: dict) -> MutationResult:
    """The :class:`MutationResult` of one design's entry of a ``--json`` report."""
    fields = [f.name for f in dataclasses.fields(MutantOutcome)]
    outcomes = tuple(MutantOutcome(**{k: m[k] for k in fields}) for m in saved["mutants"])
    mutations = tuple(parse_mutations("\n".join(m["mutation"] for m in saved["mutants"])))
    return MutationResult(design, saved["seed"], mutations, MutantOutcome(**saved["original"]),
                          outcomes, tuple(tuple(r) for r in saved["runs"]),
                          saved["wall_seconds"], saved["workers"])


if __name__ == "__main__":
    main()
