"""Running the mutants: each mutant of a top level through the verification slice, one
verdict per mutant, and the mutation score.

The slices (:mod:`dptbd.sim.mutation.slices`: ``segmenter``, ``dptbd_seg``: seeded runs of
the campaign checked by :func:`dptbd.sim.rtl.check.check_stream`; ``axi``, ``dptbd_axi``:
seeded runs of :func:`dptbd.sim.verilator.axi.check_axi` and random AXI runs of the
campaign; ``dp``, ``dptbd_dp``, and ``dp2`` / ``dp4``, ``dptbd_dp`` at P = 2 / 4 pixels per
clock: seeded runs of the campaign and K and LUT stimulus of their own, checked by
``check_stream``) are the checks the default suite runs, on small frames and narrow widths
(every bit of the datapath is reached).

A mutant's verdict (:class:`MutantOutcome`) is the first of its runs that is not passed:

* ``killed``: a run finished (the harness saw every word in and the output drain) and the
  check failed: a wrong, missing or extra word, a wrong flag, response, register or counter;
* ``timeout``: a run ran out of its cycle budget with every word the model expects
  delivered right (:func:`hang_verdict`: the mutant hangs where no more output is due; one
  that delivered a wrong or extra word, or left out words the model expects, is killed; in
  ``dptbd_seg``'s runs without resets, the model is fed every offered word, so a mutant
  that stops taking input while the model gives lists for the words it refused is killed
  with ``hang: …``) or ran past the wall-clock limit (:data:`WALL_SECONDS`, exit 124 of the
  harness): never counted as killed;
* ``crashed``: the simulation process failed otherwise (e.g. Verilator's model did not
  converge): never counted as killed;
* ``survived``: every run passed.

A mutation Yosys cannot apply is ``no-build`` (:func:`mutant_design`). The runs stop at a
mutant's first failing run. Mutants are independent tasks of the Dask execution layer
(:func:`dptbd.evaluation.execution.map_tasks`); index 0, the original design, is run first
and must pass every run of the slice.

The score is MCY's: killed / (total − shown equivalent) (:meth:`MutationResult.score`),
where a survivor is shown equivalent by its entry in the equivalence registry
(:mod:`dptbd.sim.mutation.equivalents`: proven or argued) or by a proof of this run
(:meth:`MutationResult.shown_equivalent`); killed / total (:attr:`MutationResult.killed_fraction`)
is reported next to it.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import time
import warnings

from typing import Callable, Mapping, Sequence

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.sim.mutation.equivalents import Equivalent, load_registry, mutation_key
from dptbd.sim.mutation.netlist import (BUILD_DESIGNS, DESIGN_TOPS, Mutation, mutation_list,
                                        run_yosys)
from dptbd.sim.mutation.slices import BACKPRESSURE, CONFIGS, RUNNERS, SLICE_RUNS
from dptbd.sim.mutation.slices.axi import RANDOM_AXI_FRAMES, RANDOM_AXI_RUNS, axi_scenario
from dptbd.sim.mutation.verdict import VERDICTS, MutantOutcome, hang_verdict

__all__ = ["CONFIGS", "RANDOM_AXI_RUNS", "RANDOM_AXI_FRAMES", "SLICE_RUNS", "BACKPRESSURE",
           "WALL_SECONDS", "VERDICTS", "MutantOutcome",
           "MutationResult", "Equivalent", "load_registry", "mutation_key", "config", "slice_runs",
           "slice_design", "run_slice", "mutant_task",
           "mutant_design", "run_mutants", "axi_scenario", "hang_verdict"]

#: Wall-clock seconds one run of a mutant may take (the harness exits with status 124).
WALL_SECONDS = 60


def config(design: str) -> DPConfig:
    """The :class:`DPConfig` of ``design``'s mutants (:data:`CONFIGS`)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        return DPConfig(**CONFIGS[design])


def slice_runs(design: str, scale: float = 1.0) -> tuple[tuple[str, int], ...]:
    """The runs of ``design``'s slice (:data:`SLICE_RUNS`), each kind's seeds scaled by
    ``scale`` (at least one run per kind)."""
    runs = SLICE_RUNS[design]
    kinds = dict.fromkeys(kind for kind, _ in runs)
    out = []
    for kind in kinds:
        seeds = [s for k, s in runs if k == kind]
        out += [(kind, s) for s in seeds[:max(1, round(len(seeds) * scale))]]
    return tuple(out)


def slice_design(sim) -> str:
    """The design with mutants (:data:`CONFIGS`) of the build ``sim``: the one whose
    Verilator design (:data:`~dptbd.sim.mutation.netlist.BUILD_DESIGNS`) and pixels per
    clock are ``sim``'s (``dp`` at P = 1, ``dp2`` at P = 2, ``dp4`` at P = 4).

    Raises
    ------
    ValueError
        No design with mutants is built so."""
    p = sim.cfg.pixels_per_clock
    for design, build in BUILD_DESIGNS.items():
        if build == sim.design and CONFIGS[design].get("pixels_per_clock", 1) == p:
            return design
    raise ValueError(f"no design with mutants is a build of {sim.design!r} at "
                     f"pixels_per_clock={p}; they are "
                     + ", ".join(f"{d} ({b}, P = {CONFIGS[d].get('pixels_per_clock', 1)})"
                                 for d, b in BUILD_DESIGNS.items()))


@contextlib.contextmanager
def _selected(index: int, wall_seconds: int):
    """``DPTBD_MUTANT`` / ``DPTBD_MUTANT_SECONDS`` for the harness (a worker runs one task
    at a time)."""
    saved = {k: os.environ.get(k) for k in ("DPTBD_MUTANT", "DPTBD_MUTANT_SECONDS")}
    os.environ["DPTBD_MUTANT"] = str(int(index))
    os.environ["DPTBD_MUTANT_SECONDS"] = str(int(wall_seconds))
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def run_slice(sim, index: int, runs: Sequence[tuple[str, int]], *,
              wall_seconds: int = WALL_SECONDS,
              runner: Callable | None = None) -> MutantOutcome:
    """Mutant ``index`` of the mutant build ``sim`` through ``runs``, stopping at the first
    run that is not passed (see the module doc for the verdicts). ``runner(sim, kind,
    seed) -> (verdict, report)`` replaces the design's runner (tests; the default: the
    runner of :func:`slice_design`)."""
    runner = runner or RUNNERS[slice_design(sim)]
    start = time.perf_counter()
    with _selected(index, wall_seconds):
        for kind, seed in runs:
            label = f"{kind} seed {seed}"
            try:
                verdict, report = runner(sim, kind, seed)
            except RuntimeError as exc:
                text = str(exc)
                if "(exit 124)" in text:
                    verdict, report = "timeout", f"wall-clock limit of {wall_seconds} s"
                else:
                    verdict, report = "crashed", text.strip().splitlines()[0][:300]
            if verdict != "survived":
                return MutantOutcome(index, verdict, label, report,
                                     time.perf_counter() - start)
    return MutantOutcome(index, "survived", "", "", time.perf_counter() - start)


def mutant_task(design: str, commands: tuple[str, ...], index: int,
                runs: tuple[tuple[str, int], ...], wall_seconds: int,
                root: str | None = None) -> MutantOutcome:
    """One task of :func:`run_mutants` (picklable arguments; the build is cached on disk)."""
    from dptbd.sim.verilator.cache import build

    sim = build(config(design), BUILD_DESIGNS[design], root=root, mutations=commands)
    return run_slice(sim, index, runs, wall_seconds=wall_seconds)


def mutant_design(cfg: DPConfig, design: str, mutations: Sequence[Mutation]
                  ) -> tuple[tuple[str, ...], list[int]]:
    """The commands of the mutations Yosys can apply and write as Verilog (a mutation it
    refuses is replaced by ``""``, which applies nothing, so every mutant keeps its index)
    and the 1-based indices of the refused ones (``no-build``). All are tried at once; only
    if that fails, each half in turn, down to the single mutations Yosys refuses."""
    from dptbd.sim.mutation.netlist import MUTSEL_WIDTH, _prepared, top_rtlil

    commands = [m.command for m in mutations]
    text, _ = top_rtlil(cfg, design)
    base = _prepared(text, design)

    def applies(lines: list[str]) -> bool:
        try:
            run_yosys("\n".join([base, *lines, "write_verilog mutant.v"]))
        except RuntimeError:
            return False
        return True

    def refused_of(lines: list[tuple[int, str]]) -> list[int]:
        """The indices of the refused mutations among ``lines``, by halves."""
        if applies([line for _, line in lines]):
            return []
        if len(lines) == 1:
            return [lines[0][0]]
        half = len(lines) // 2
        return refused_of(lines[:half]) + refused_of(lines[half:])

    refused = refused_of([(i, f"{c} -ctrl mutsel {MUTSEL_WIDTH} {i}")
                          for i, c in enumerate(commands, 1)])
    return tuple("" if i in refused else c for i, c in enumerate(commands, 1)), refused


@dataclasses.dataclass(frozen=True)
class MutationResult:
    """Every mutant's outcome (index 1 … N), the mutations, the original's outcome."""

    design: str
    seed: int
    mutations: tuple[Mutation, ...]
    original: MutantOutcome
    outcomes: tuple[MutantOutcome, ...]
    runs: tuple[tuple[str, int], ...]
    wall_seconds: float
    workers: int

    def count(self, verdict: str) -> int:
        return sum(o.verdict == verdict for o in self.outcomes)

    @property
    def killed(self) -> int:
        return self.count("killed")

    @property
    def total(self) -> int:
        return len(self.outcomes)

    @property
    def killed_fraction(self) -> float:
        """Killed / total: survivors, timeouts, crashes and no-builds all count against."""
        return self.killed / self.total if self.total else float("nan")

    def of(self, verdict: str) -> list[tuple[MutantOutcome, Mutation]]:
        return [(o, self.mutations[o.index - 1]) for o in self.outcomes if o.verdict == verdict]

    def shown_equivalent(self, registry: Mapping[str, Equivalent] | None = None,
                         proofs: Mapping[int, object] | None = None) -> dict[int, str]:
        """Each survivor shown equivalent, index -> how: ``proven`` / ``argued`` (its entry
        in ``registry``, :mod:`dptbd.sim.mutation.equivalents`, by :func:`mutation_key`;
        default: the design's file) or ``proven in this run`` (``proofs[index]``, an
        :class:`~dptbd.sim.mutation.equivalence.Equivalence`, says ``equivalent`` and the
        registry does not list it). Only survivors: a killed mutant, a timeout, a crash or
        a no-build is never left out of the score."""
        registry = load_registry(self.design) if registry is None else registry
        proofs = proofs or {}
        out = {}
        for outcome, mutation in self.of("survived"):
            entry = registry.get(mutation_key(mutation.command))
            if entry is not None:
                out[outcome.index] = entry.shown
            elif getattr(proofs.get(outcome.index), "verdict", None) == "equivalent":
                out[outcome.index] = "proven in this run"
        return out

    def registered_not_surviving(self, registry: Mapping[str, Equivalent] | None = None
                                 ) -> list[tuple[MutantOutcome, Mutation]]:
        """The mutants ``registry`` lists as equivalent that did not survive (a wrong entry
        or a broken slice: an equivalent mutant cannot be killed)."""
        registry = load_registry(self.design) if registry is None else registry
        return [(o, m) for o, m in zip(self.outcomes, self.mutations)
                if o.verdict != "survived" and mutation_key(m.command) in registry]

    def score(self, shown: Mapping[int, str] | int) -> float:
        """MCY's score: killed / (total − shown equivalent); ``shown``: the mutants shown
        equivalent (:meth:`shown_equivalent`) or their count."""
        left = self.total - (shown if isinstance(shown, int) else len(shown))
        return self.killed / left if left else float("nan")


def run_mutants(design: str, count: int, seed: int = 1, *, workers: int | None = 1,
                scheduler: str | None = None, scale: float = 1.0,
                wall_seconds: int = WALL_SECONDS, root: str | None = None,
                bar=None, mutations: Sequence[Mutation] | None = None) -> MutationResult:
    """Sample ``count`` mutations of ``design`` (``mutate -list count -seed seed``), build
    the mutant design once, check the original passes the slice, then run every mutant
    through it (``workers`` / ``scheduler``: :func:`~dptbd.evaluation.execution.job_execution`).
    ``mutations``: run these instead of the sample (e.g. a sample without the mutants shown
    equivalent; ``count`` and ``seed`` are then only recorded).

    Raises
    ------
    RuntimeError
        The original design fails the slice (a broken slice scores nothing).
    """
    from dptbd.evaluation.execution import job_execution, map_tasks
    from dptbd.sim.verilator.cache import build

    if design not in DESIGN_TOPS:
        raise ValueError(f"design must be one of {', '.join(DESIGN_TOPS)}, got {design!r}")
    start = time.perf_counter()
    cfg = config(design)
    mutations = tuple(mutation_list(cfg, design, count, seed) if mutations is None
                      else mutations)
    commands, refused = mutant_design(cfg, design, mutations)
    sim = build(cfg, BUILD_DESIGNS[design], root=root, mutations=commands)
    runs = slice_runs(design, scale)
    original = run_slice(sim, 0, runs, wall_seconds=wall_seconds)
    if original.verdict != "survived":
        raise RuntimeError(f"the original {DESIGN_TOPS[design]} fails the mutation slice "
                           f"({original.run}: {original.verdict}): {original.report}")
    todo = [i for i in range(1, len(mutations) + 1) if i not in refused]
    execution = job_execution(workers, scheduler=scheduler, tasks=len(todo))
    tasks = [(design, commands, i, runs, wall_seconds, root) for i in todo]
    with execution.client() as client:
        done = map_tasks(mutant_task, tasks, client, bar=bar)
    by_index = {o.index: o for o in done}
    by_index.update({i: MutantOutcome(i, "no-build", "", "Yosys refused the mutation", 0.0)
                     for i in refused})
    outcomes = tuple(by_index[i] for i in range(1, len(mutations) + 1))
    return MutationResult(design, seed, mutations, original, outcomes, runs,
                          time.perf_counter() - start, execution.workers or 1)
