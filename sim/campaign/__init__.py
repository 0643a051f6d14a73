"""The verification campaign: many parameter sets × hostile scenes × random stalls × faults,
every output word of the compiled RTL compared with the golden model.

A campaign is a list of :class:`Case` (a parameter set and a top level) and, per case, a
number of seeded runs. Each run draws, from its own seed only,

* a scene of frames mixing 001's noise with targets on edges and corners, manoeuvring
  targets, all-maximum, all-zero, constant and checkerboard frames (ties) and uniform noise
  (:func:`hostile_frames`);
* input gap and output back-pressure densities, each uniform in [0, 0.7];
* the case's faults (:class:`Case` ``faults``): resets at random cycles, start-of-frame
  markers in the middle of a frame, frames cut short or run long, run-time LUT rewrites
  between and inside frames, an external store powered up with garbage, run-time settings
  (K, n, s) rewritten between and inside frames;

and is checked by :func:`dptbd.sim.rtl.check.check_stream` against the promise of
``docs/gateware.md`` ("Faults and what the output promises"). The 4-state question — an
X-initialised or garbage external store never reaches an output — is asked of Icarus
(:func:`dptbd.sim.x_store.run_x_store_check`): Verilator is 2-state.

:func:`run_campaign` runs the runs on the Dask execution layer
(:mod:`dptbd.evaluation.execution`: in this process, local worker processes or a cluster) and
returns a :class:`CampaignResult` (per case: runs, words compared, words per second, verdict;
the functional coverage bins of every run, :mod:`dptbd.sim.coverage.bins`, added up), the
same for any number of workers. ``dptbd verify`` is the
command; ``tests/sim/campaign/test_campaign.py`` runs a slice of it in the default suite.

This package runs the campaign (a run built, run and checked: :func:`check_run`,
:func:`check_x_store`; the tasks on the execution layer: :func:`run_campaign`); the cases
are in :mod:`dptbd.sim.campaign.cases`, what a run draws in :mod:`dptbd.sim.campaign.draw`
(the runs of ``dptbd_dp --state-store axi``, design ``"dp_axi"``, and of ``dptbd_axi
--state-store axi``, design ``"axi_store"``: :mod:`dptbd.sim.campaign.store`),
the results in :mod:`dptbd.sim.campaign.results`, all importable from here.
"""

from __future__ import annotations

import time
from typing import Callable, Sequence

import numpy as np

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.sim.campaign.cases import (FAULTS, Case, axi_cases, default_cases, store_cases,
                                      x_store_cases)
from dptbd.sim.campaign.draw import MAX_STALL, hostile_frames, make_run, make_stream_run
from dptbd.sim.campaign.results import CampaignResult, CaseResult, RunOutcome, summarise

__all__ = ["FAULTS", "MAX_STALL", "Case", "RunOutcome", "CaseResult", "CampaignResult",
           "default_cases", "axi_cases", "store_cases", "hostile_frames", "make_run",
           "make_stream_run",
           "check_run", "check_x_store", "x_store_cases", "campaign_task", "campaign_tasks",
           "run_campaign", "summarise"]

#: The names these had before the split (imported so elsewhere).
_make_run, _summarise = make_stream_run, summarise


def check_run(case: Case, seed: int, root: str | None = None,
              coverage: str | None = None) -> RunOutcome:
    """Build (cached), run and check run ``seed`` of ``case``, and count its bins; with
    ``coverage`` (a file) on the coverage build, its coverage data written there
    (:mod:`dptbd.sim.coverage`). A case that saturates on purpose gives no
    :class:`~dptbd.config.EnergyWidthWarning` (as :attr:`Case.cfg`), so the workers print
    none."""
    import warnings

    from dptbd.sim.coverage.bins import stream_bins
    from dptbd.sim.rtl.check import check_stream
    from dptbd.sim.verilator import build

    if case.design == "axi":
        from dptbd.sim.axi import runs as axi_runs
        return axi_runs.check_run(case, seed, root, coverage)
    if case.design == "dp_axi":
        from dptbd.sim.campaign.store.dp_axi import check_store_run
        return check_store_run(case, seed, root)
    if case.design == "axi_store":
        from dptbd.sim.campaign.store.axi_store import check_axi_store_run
        return check_axi_store_run(case, seed, root)

    start = time.perf_counter()
    sim = build(case.cfg, case.design, root=root, coverage=coverage is not None,
                family=case.family)
    latency = int(sim.manifest.get("dp_latency", sim.latency))
    words, stim, notes, events = make_stream_run(case, seed, latency)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        result = check_stream(sim, words, stim, coverage=coverage)
    bins = stream_bins(case, stim, result, events, latency)
    return RunOutcome(case.name, seed, result.passed, result.report, result.words_in,
                      result.words_out, result.raw.cycles, result.raw.sim_seconds,
                      time.perf_counter() - start, tuple(notes), bins)


def check_x_store(name: str, config: dict, init: str, seed: int = 1) -> RunOutcome:
    """One 4-state run: no output bit X or Z, every word equal to the model."""
    from dptbd.sim.x_store import run_x_store_check

    start = time.perf_counter()
    cfg = DPConfig(**config)
    rng = np.random.default_rng([seed, 0x5EED])
    frames = hostile_frames(cfg, 3 * cfg.segment_frames, rng)
    ok, report, words = run_x_store_check(cfg, frames, init=init, seed=seed)
    return RunOutcome(name, seed, bool(ok), report.splitlines()[0] if report else "",
                      int(words), int(words), 0, 0.0, time.perf_counter() - start,
                      (f"Icarus, store {init}",))


# ---- the campaign ---------------------------------------------------------------------------

def campaign_task(kind: str, *args) -> RunOutcome:
    """One task of :func:`run_campaign`: ``("run", case, seed, root)`` is
    :func:`check_run`, ``("x_store", name, config, init)`` :func:`check_x_store`."""
    if kind == "run":
        return check_run(*args)
    if kind == "x_store":
        return check_x_store(*args)
    raise ValueError(f"campaign task kind must be 'run' or 'x_store', got {kind!r}")


def campaign_tasks(cases: Sequence[Case], *, runs_scale: float = 1.0, base_seed: int = 0,
                   x_store: bool = True, root: str | None = None) -> list[tuple]:
    """The arguments of every :func:`campaign_task` of a campaign, in task order: each case's
    runs (``round(case.runs * runs_scale)``, at least 1; seed ``base_seed * 1_000_003 +
    7919 * case index + run``), then the 4-state store checks."""
    tasks: list[tuple] = [("run", case, base_seed * 1_000_003 + 7919 * i + r, root)
                          for i, case in enumerate(cases)
                          for r in range(max(1, round(case.runs * runs_scale)))]
    if x_store:
        tasks += [("x_store", n, cfg, init) for n, cfg, init in x_store_cases()]
    return tasks


def run_campaign(cases: Sequence[Case] | None = None, *, runs_scale: float = 1.0,
                 base_seed: int = 0, workers: int | None = None, x_store: bool = True,
                 root: str | None = None,
                 on_outcome: Callable[[RunOutcome], None] | None = None,
                 scheduler: str | None = None, dashboard: bool = False) -> CampaignResult:
    """Run every case's runs and the 4-state store checks (:func:`campaign_tasks`) on the
    execution layer (:mod:`dptbd.evaluation.execution`, ``docs/distributed.md``).

    ``workers``: local worker processes (default: the machine's cores, at most one per
    task; 1 runs in this process); with ``scheduler`` (``tcp://HOST:PORT``, or the
    ``DPTBD_SCHEDULER`` environment variable) the workers that cluster must have (default:
    any). Refusals are the layer's (:class:`~dptbd.evaluation.execution.ExecutionError`),
    before any build. Every Verilator executable is built (or found in the cache) once, here,
    before the tasks; each task calls :func:`~dptbd.sim.verilator.cache` again, which on a
    worker that sees the same build root (this machine, or a shared file system) finds it
    and on any other builds it once into the worker's own cache (``root=None``: the worker's
    :func:`~dptbd.sim.verilator.default_build_root`; the build is locked, so the workers of
    one machine build it once). ``on_outcome`` is called with each outcome as its task
    finishes; the result lists them in task order, the same for any workers or cluster.
    """
    from dptbd.evaluation.execution import job_execution, run_tasks
    from dptbd.sim.verilator import build

    cases = list(default_cases() if cases is None else cases)
    tasks = campaign_tasks(cases, runs_scale=runs_scale, base_seed=base_seed,
                           x_store=x_store, root=root)
    execution = job_execution(workers, scheduler=scheduler, dashboard=dashboard,
                              tasks=len(tasks))

    def build_all() -> None:                  # once, up front (then cached)
        from dptbd.sim.campaign.store.axi_store import build_axi_store
        from dptbd.sim.campaign.store.dp_axi import build_store
        for case in cases:
            if case.design == "dp_axi":
                build_store(case, root=root)
            elif case.design == "axi_store":
                build_axi_store(case, root=root)
            else:
                build(case.cfg, case.design, root=root, family=case.family)

    start = time.perf_counter()
    outcomes, used = run_tasks(
        campaign_task, tasks, execution, prepare=build_all,
        on_result=None if on_outcome is None else lambda _, outcome: on_outcome(outcome))
    by_case: dict[str, list[RunOutcome]] = {c.name: [] for c in cases}
    design = {c.name: c.design for c in cases}
    if x_store:
        for n, _, _ in x_store_cases():
            by_case[n] = []
            design[n] = "core (Icarus, 4-state)"
    for outcome in outcomes:
        by_case[outcome.case].append(outcome)
    results = tuple(summarise(n, design[n], o) for n, o in by_case.items())
    return CampaignResult(results, tuple(o for lst in by_case.values() for o in lst),
                          time.perf_counter() - start, used)
