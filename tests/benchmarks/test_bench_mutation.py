"""``benchmarks/bench_mutation.py``: ``--prove-method`` picks the function the survivors are
proven with (``equiv``, the default, ``reachable`` or ``reachable-scorr``), and is refused, as
a usage error before any run, with an unknown method or beside ``--no-prove`` / ``--rescore``."""

from __future__ import annotations

import contextlib
import json

import pytest

from helpers.benches import load_bench

from dptbd.sim.mutation.equivalence import Equivalence, prove_equivalent
from dptbd.sim.mutation.netlist import parse_mutations
from dptbd.sim.mutation.reachable import prove_reachable
from dptbd.sim.mutation.run import MutantOutcome, MutationResult

MUT = "mutate -mode inv -module dptbd_dp -cell $flatten\\core.$1 -port Y -portbit 0"


@pytest.mark.parametrize("argv, message", [
    (["--prove-method", "sat"], "argument --prove-method: invalid choice: 'sat' (choose from "
                                "'equiv', 'reachable', 'reachable-scorr')"),
    (["--prove-method", "reachable", "--no-prove"],
     "--prove-method reachable proves survivors; it cannot be given with --no-prove, which "
     "proves none"),
    (["--prove-method", "equiv", "--rescore", "x.json"],
     "--prove-method equiv proves survivors; it cannot be given with --rescore, which proves "
     "none"),
])
def test_refusals_are_usage_errors(argv, message, capsys, monkeypatch):
    bench = load_bench("bench_mutation")
    monkeypatch.setattr(bench, "run_mutants", lambda *a, **k: pytest.fail("ran after a refusal"))
    with pytest.raises(SystemExit) as exc:
        bench.main(argv)
    assert exc.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1].endswith(f"error: {message}")


def _one_survivor(design, count, seed, **_kwargs) -> MutationResult:
    (mutation,) = parse_mutations(MUT)
    outcome = MutantOutcome(1, "survived", "", "", 0.5)
    return MutationResult(design, seed, (mutation,), MutantOutcome(0, "survived", "", "", 0.5),
                          (outcome,), (("clean", 1),), 1.0, 1)


@pytest.mark.parametrize("argv, function, method", [
    ([], (prove_equivalent, {}), "equiv"),
    (["--prove-method", "equiv"], (prove_equivalent, {}), "equiv"),
    (["--prove-method", "reachable"], (prove_reachable, {}), "reachable"),
    (["--prove-method", "reachable-scorr"], (prove_reachable, {"correspondence": "scorr"}),
     "reachable-scorr"),
])
def test_the_method_proves_the_survivors(argv, function, method, monkeypatch, tmp_path,
                                         capsys):
    import dptbd.evaluation.execution as execution

    bench = load_bench("bench_mutation")
    seen = []

    class Execution:
        def client(self):
            return contextlib.nullcontext()

    def map_tasks(prove, tasks, client, on_result):
        seen.append((prove, [task[1:] for task in tasks]))
        on_result(0, Equivalence("equivalent", "proven", 2.0))
        return [Equivalence("equivalent", "proven", 2.0)]

    monkeypatch.setattr(bench, "run_mutants", _one_survivor)
    monkeypatch.setattr(bench, "load_registry", lambda design: {})
    monkeypatch.setattr(execution, "job_execution", lambda *a, **k: Execution())
    monkeypatch.setattr(execution, "map_tasks", map_tasks)
    out = tmp_path / "m.json"
    bench.main(["--designs", "dp", "--mutants", "1", "--json", str(out), *argv])
    ((prove, tasks),) = seen
    assert (getattr(prove, "func", prove), getattr(prove, "keywords", {})) == function
    assert [(design, m.command) for design, m in tasks] == [("dp", MUT)]
    report = json.loads(out.read_text())["dp"]
    assert (report["prove_method"], report["shown_equivalent"]["proven in this run"]) == (
        method, 1)
    assert f"(1 tried, {method})" in capsys.readouterr().out


def test_no_prove_tries_no_survivor(monkeypatch, tmp_path):
    bench = load_bench("bench_mutation")
    monkeypatch.setattr(bench, "run_mutants", _one_survivor)
    monkeypatch.setattr(bench, "load_registry", lambda design: {})
    out = tmp_path / "m.json"
    bench.main(["--designs", "dp", "--mutants", "1", "--no-prove", "--json", str(out)])
    report = json.loads(out.read_text())["dp"]
    assert (report["prove_method"], report["mutants"][0]["proof"]) == (None, None)
