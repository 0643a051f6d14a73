"""Code coverage of a campaign: runs on coverage builds, merged, mapped, reported.

:func:`run_coverage` runs the campaign's cases (:mod:`dptbd.sim.campaign`) on coverage builds
(each run checked bit-exact against the golden model, as every campaign run is; its
``VerilatedCov`` file ``runs/<case>-<seed>.dat``), plus the AXI top's runs
(:func:`axi_cases`: the scenario of ``tests/sim/verilator/test_axi.py`` — every fault
class, register writes refused and taken, a LUT rewrite, a soft reset — scored by
:func:`~dptbd.sim.verilator.axi.check_axi`), as tasks of the Dask execution layer; merges
each run's file into its build's as the run finishes (``verilator_coverage --write``,
:class:`RunMerger`) and writes the report (:func:`write_report`; with ``prove_constants``,
register bits proven constant by Yosys are excluded: :mod:`dptbd.sim.coverage.constant_bits`).

How the points add up is :mod:`dptbd.sim.coverage.summary`'s (:func:`summarise`); the report's
text (terminal table, ``report.md``, ``coverage.json``) :mod:`dptbd.sim.coverage.tables`'s.
"""

from __future__ import annotations

import collections
import contextlib
import json
import os
import pathlib
import shutil
from typing import Callable, Sequence

from dptbd.sim.coverage.code import annotate, merge, read_dat
from dptbd.sim.coverage.summary import (  # re-exported: their home was this module
    Entry,
    Summary,
    entries,
    reachable_toggle,
    reachable_width,
    summarise,
)
from dptbd.sim.coverage.tables import GOALS, _jsonable, _markdown, format_table
from dptbd.sim.coverage.run_sets import (  # re-exported: their home was this module
    AxiCase,
    _config,
    axi_cases,
    coverage_run,
    extra_cases,
)

__all__ = ["GOALS", "Entry", "Summary", "AxiCase", "axi_cases", "extra_cases", "entries",
           "summarise",
           "coverage_run", "RunMerger", "run_coverage", "write_report", "format_table",
           "reachable_width", "reachable_toggle"]


class RunMerger:
    """The coverage files of one build merged as their runs finish: ``add(dat)`` merges
    ``dat`` into ``target`` (``verilator_coverage --write`` into ``target.part``, then
    renamed, so ``target`` is never half-written) and deletes ``dat`` unless ``keep``."""

    def __init__(self, target: pathlib.Path, keep: bool = False):
        self.target, self.keep, self.runs = pathlib.Path(target), keep, 0

    def add(self, dat) -> None:
        dat = pathlib.Path(dat)
        if not dat.exists():
            raise RuntimeError(f"coverage run wrote no coverage file {dat}")
        part = self.target.with_name(self.target.name + ".part")
        merge([self.target, dat] if self.target.exists() else [dat], part)
        os.replace(part, self.target)
        self.runs += 1
        if not self.keep:
            dat.unlink()


# ---- the campaign on coverage builds -------------------------------------------------------

def run_coverage(out: pathlib.Path, cases: Sequence, *, axi: Sequence[AxiCase] = (),
                 runs_scale: float = 1.0, base_seed: int = 0, workers: int | None = None,
                 scheduler: str | None = None, dashboard: bool = False, root=None,
                 on_outcome: Callable | None = None, keep_runs: bool = False):
    """Run ``cases`` and ``axi`` on coverage builds, as tasks of the execution layer
    (:func:`dptbd.evaluation.execution.run_tasks`: ``workers`` local processes, or the
    cluster at ``scheduler``; the run files are written where the workers see ``out``, so a
    remote cluster needs ``out`` on a shared file system). Each run writes
    ``out/runs/<case>-<seed>.dat``; as it finishes, the file is merged into its build's
    ``out/merged/<build>.dat`` (:class:`RunMerger`) and deleted (kept with ``keep_runs``).
    Returns (outcomes in task order, builds: {directory name: (design, build,
    [merged file])})."""
    from dptbd.evaluation.execution import job_execution, run_tasks
    from dptbd.sim.verilator import build

    runs_dir = _mkdir(out / "runs")
    merged_dir = _mkdir(out / "merged")
    every = [(c, c.cfg) for c in cases] + [(a, _config(a.config)) for a in axi]
    tasks, mergers, builds = [], [], {}
    execution = job_execution(workers, scheduler=scheduler, dashboard=dashboard,
                              tasks=sum(max(1, round(c.runs * runs_scale)) for c, _ in every))
    sims = [build(cfg, case.design, root=root, coverage=True, family=case.family)
            for case, cfg in every]
    by_build: dict[str, RunMerger] = {}
    for i, ((case, _), sim) in enumerate(zip(every, sims)):
        name = sim.directory.name
        target = merged_dir / f"{name}.dat"
        builds.setdefault(name, (case.design, sim, [target]))
        merger = by_build.setdefault(name, RunMerger(target, keep_runs))
        for r in range(max(1, round(case.runs * runs_scale))):
            seed = base_seed * 1_000_003 + 7919 * i + r
            dat = runs_dir / f"{case.name}-{seed}.dat"
            tasks.append((case, seed, root, str(dat)))
            mergers.append(merger)

    def done(i: int, outcome) -> None:
        mergers[i].add(tasks[i][3])
        if on_outcome is not None:
            on_outcome(outcome)

    outcomes, _ = run_tasks(coverage_run, tasks, execution, on_result=done)
    if not keep_runs:
        with contextlib.suppress(OSError):
            runs_dir.rmdir()
    return outcomes, builds


def write_report(out: pathlib.Path, builds: dict, exclusions: Sequence = (),
                 annotate_sources: bool = True, prove_constants: bool = False,
                 proof_time_limit: float | None = None) -> Summary:
    """Merge each build's run files, map, summarise and write ``out``: ``report.md``,
    ``coverage.json``, ``merged/<build>.dat``, ``verilog/<build>/`` and ``annotated/``
    (``verilog/<build>/``: ``verilator_coverage --annotate``; ``amaranth/<design>/``: the
    Amaranth files, each line prefixed with its covered / total line and branch points)."""
    all_entries: list[Entry] = []
    constant: set = set()
    proofs: dict = {}
    for name, (design, sim, dats) in sorted(builds.items()):
        dats = [pathlib.Path(d) for d in dats if pathlib.Path(d).exists()]
        if not dats:
            continue
        merged = _mkdir(out / "merged") / f"{name}.dat"
        if dats != [merged]:                   # run files (not merged yet by run_coverage)
            merge(dats, merged)
        verilog_src = sim.directory / f"{sim.toplevel}.v"
        vdir = _mkdir(out / "verilog" / name)
        shutil.copyfile(verilog_src, vdir / verilog_src.name)
        text = verilog_src.read_text()
        if annotate_sources:
            annotate(merged, vdir, _mkdir(out / "annotated" / "verilog" / name))
        all_entries += entries(design, name, text, read_dat(merged))
        if prove_constants:
            from dptbd.sim.coverage.constant_bits import build_constant_bits
            proofs[name] = build_constant_bits(sim, **({} if proof_time_limit is None else
                                                       {"time_limit": proof_time_limit}))
            constant |= {(name, m, bit) for m, bit in proofs[name].bits}
    summary = summarise(all_entries, exclusions, constant)
    summary.proofs = proofs
    summary.reachable = reachable_toggle(all_entries, exclusions, constant, {
        name: sim.cfg for name, (_, sim, _) in builds.items()})
    if annotate_sources:
        _annotate_amaranth(out / "annotated" / "amaranth", all_entries)
    (out / "coverage.json").write_text(json.dumps(_jsonable(summary), indent=1) + "\n")
    (out / "report.md").write_text(_markdown(summary))
    return summary


def _mkdir(path: pathlib.Path) -> pathlib.Path:
    path.mkdir(parents=True, exist_ok=True)
    return path


def _annotate_amaranth(out: pathlib.Path, all_entries: Sequence[Entry]) -> None:
    from dptbd.sim.coverage.code import _REPO

    per_line = collections.defaultdict(lambda: [0, 0])       # (design, file, line) -> [c, t]
    by_name: dict[tuple, bool] = {}
    for e in all_entries:
        if e.kind != "toggle" and e.src:
            by_name[e.name] = by_name.get(e.name, False) or e.count > 0
    for (design, _, _, src, _), covered in by_name.items():
        path, _, line = src.rpartition(":")
        slot = per_line[(design, path, int(line))]
        slot[1] += 1
        slot[0] += covered
    files = collections.defaultdict(dict)
    for (design, path, line), counts in per_line.items():
        files[(design, path)][line] = counts
    for (design, path), lines in files.items():
        source = _REPO / path
        if not source.is_file():
            continue
        target = _mkdir((out / design / path).parent) / pathlib.Path(path).name
        rows = []
        for number, text in enumerate(source.read_text().splitlines(), 1):
            if number in lines:
                c, t = lines[number]
                mark = "  " if c == t else "!!"
                rows.append(f"{mark}{c:3d}/{t:<3d} {text}")
            else:
                rows.append(f"{'':10s}{text}")
        target.write_text("\n".join(rows) + "\n")


