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

How points add up (:func:`summarise`): a **line** or **branch** point is named by its
design, Verilog module (the Amaranth hierarchy), kind, Amaranth ``file:line`` and what
(``if``, ``else``, ``case``, …); a **toggle** point, a register bit, by design, module,
register and bit index. The points of one name — the same ``m.If`` in several processes, or
in the builds of several parameter sets of one design — count once, covered if any run
covered any of them (a bit that exists in a wide parameter set only counts there). Points
listed in the exclusion
list (:mod:`dptbd.sim.coverage.exclusions`) are counted apart; the figures are covered /
total outside them.
"""

from __future__ import annotations

import collections
import contextlib
import dataclasses
import json
import os
import pathlib
import shutil
from typing import Callable, Sequence

from dptbd.sim.coverage.code import (
    Point,
    annotate,
    locate,
    merge,
    read_dat,
    registers,
    source_map,
    unescape,
    usable,
)

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

#: Goals per design: percent of line, branch and toggle points outside the exclusions.
GOALS = {"axi": {"line": 100.0, "branch": 100.0, "toggle": 95.0},
         "segmenter": {"line": 100.0, "branch": 100.0, "toggle": 95.0}}

TOP_NAMES = {"dp": "dptbd_dp", "core": "DPCore (dptbd_dp)", "segmenter": "dptbd_seg",
             "axi": "dptbd_axi"}


@dataclasses.dataclass(frozen=True)
class Entry:
    """One coverage point of one build, located in the Amaranth source."""

    design: str
    build: str        # the build's directory name
    module: str
    kind: str
    src: str          # Amaranth file:line (repository-relative), or "" if none
    what: str         # Verilator's o, unescaped
    verilog_line: int
    count: int

    @property
    def name(self) -> tuple:
        if self.kind == "toggle":                    # a register bit: its name and index
            return (self.design, self.module, self.kind, "", self.what)
        return (self.design, self.module, self.kind, self.src, self.what)


def entries(design: str, build: str, verilog: str, points: Sequence[Point]) -> list[Entry]:
    """The points of one build, located (:func:`~dptbd.sim.coverage.code.locate`)."""
    srcmap, artefacts = source_map(verilog)
    regs = registers(verilog)
    out = []
    for p in usable(points, artefacts):
        what = unescape(p.what)
        if p.kind == "toggle" and (p.module, what.split("[")[0]) not in regs:
            continue                                  # not a register bit
        out.append(Entry(design, build, p.module, p.kind, locate(p, srcmap) or "", what,
                         p.line, p.count))
    return out


@dataclasses.dataclass
class Summary:
    """Covered / total / excluded per (design, module, kind); the uncovered names; the
    exclusion list's verdicts."""

    counts: dict                 # (design, module, kind) -> [covered, total, excluded]
    uncovered: list              # list of (name, [Entry, ...])
    stale: list                  # list of (Exclusion, reason)
    constant: list = dataclasses.field(default_factory=list)  # names proven constant
    proofs: dict = dataclasses.field(default_factory=dict)    # build -> constant_bits.Proof
    # design -> [covered, total, builds counted, builds]: toggle over the builds of reachable
    # width only (reachable_width_builds)
    reachable: dict = dataclasses.field(default_factory=dict)

    def figure(self, design: str, kind: str, module: str | None = None) -> tuple[int, int]:
        covered = total = 0
        for (d, m, k), (c, t, _) in self.counts.items():
            if d == design and k == kind and (module is None or m == module):
                covered += c
                total += t
        return covered, total

    def percent(self, design: str, kind: str, module: str | None = None) -> float | None:
        covered, total = self.figure(design, kind, module)
        return 100.0 * covered / total if total else None


def summarise(all_entries: Sequence[Entry], exclusions: Sequence = (),
              constant: set = frozenset()) -> Summary:
    """Add the points up by name (see the module doc) and apply the exclusion list.

    ``constant``: (build, module, bit) of the register bits proven constant in that build
    (:mod:`dptbd.sim.coverage.constant_bits`); a toggle name proven constant in every build
    where it exists is excluded (``Summary.constant``), one that exists elsewhere too is
    judged on the other builds."""
    by_name: dict[tuple, list[Entry]] = collections.defaultdict(list)
    for entry in all_entries:
        by_name[entry.name].append(entry)
    matched: dict[int, list[bool]] = {i: [] for i in range(len(exclusions))}
    counts: dict[tuple, list[int]] = collections.defaultdict(lambda: [0, 0, 0])
    uncovered, proven = [], []
    for name, group in sorted(by_name.items()):
        first = group[0]
        if constant and first.kind == "toggle":
            group = [e for e in group if (e.build, e.module, e.what) not in constant]
            if not group:
                counts[(first.design, first.module, first.kind)][2] += 1
                proven.append(name)
                continue
            first = group[0]
        covered = any(e.count > 0 for e in group)
        hits = [i for i, ex in enumerate(exclusions) if ex.matches(first)]
        slot = counts[(first.design, first.module, first.kind)]
        if hits:
            for i in hits:
                matched[i].append(covered)
            slot[2] += 1
            continue
        slot[1] += 1
        slot[0] += covered
        if not covered:
            uncovered.append((name, group))
    stale = []
    designs = {e.design for e in all_entries}
    for i, ex in enumerate(exclusions):
        if ex.design not in designs:          # that top level was not run: no verdict
            continue
        if not matched[i]:
            stale.append((ex, "no such point (the source changed?)"))
        elif all(matched[i]):
            stale.append((ex, "covered: the point is reached"))
    return Summary(dict(counts), uncovered, stale, proven)


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
    sims = [build(cfg, case.design, root=root, coverage=True) for case, cfg in every]
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


def reachable_width(cfg) -> bool:
    """Whether a build's widths are all reachable: ``B_E`` no wider than the largest E any
    input reaches (:attr:`~dptbd.config.DPConfig.energy_reach_bits`), as ``dptbd verilog``
    builds it (:meth:`~dptbd.config.DPConfig.build_config`)."""
    return cfg.energy_bits == cfg.energy_reach_bits


def reachable_toggle(all_entries: Sequence[Entry], exclusions: Sequence, constant: set,
                     configs: dict) -> dict:
    """Toggle covered / total per design over the builds of reachable width only
    (:func:`reachable_width`; ``configs``: build name -> its DPConfig): a build wider than
    that has E's headroom bits, which no input reaches and the default build does not have.
    design -> [covered, total, builds counted, builds]."""
    keep = {name for name, cfg in configs.items() if reachable_width(cfg)}
    out = {}
    for design in sorted({e.design for e in all_entries}):
        names = {e.build for e in all_entries if e.design == design}
        sub = summarise([e for e in all_entries if e.design == design and e.build in keep
                         and e.kind == "toggle"], exclusions, constant)
        covered, total = sub.figure(design, "toggle")
        out[design] = [covered, total, len(names & keep), len(names)]
    return out


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


def _jsonable(summary: Summary) -> dict:
    return {
        "modules": [{"design": d, "module": m, "kind": k, "covered": c, "total": t,
                     "excluded": x} for (d, m, k), (c, t, x) in sorted(summary.counts.items())],
        "uncovered": [{"design": g[0].design, "module": g[0].module, "kind": g[0].kind,
                       "src": g[0].src, "what": g[0].what,
                       "verilog": sorted({f"{e.build}:{e.verilog_line}" for e in g})}
                      for _, g in summary.uncovered],
        "proven_constant": [{"design": d, "module": m, "bit": w}
                            for d, m, _, _, w in summary.constant],
        "toggle_reachable_width": {d: {"covered": c, "total": t, "builds": n, "of": a}
                                   for d, (c, t, n, a) in sorted(summary.reachable.items())},
        "proofs": {name: {"bits": len(p.bits), "script": p.script,
                          "seconds": round(p.seconds, 1), "stopped_after": p.stopped_after}
                   for name, p in sorted(summary.proofs.items())},
        "stale_exclusions": [{"point": ex.point, "kind": ex.kind, "design": ex.design,
                              "what": ex.what, "reason": why} for ex, why in summary.stale],
    }


def _pct(covered: int, total: int) -> str:
    return f"{100.0 * covered / total:6.2f} %" if total else f"{'-':>8s}"


def format_table(summary: Summary) -> str:
    """The terminal table: per design, line / branch / toggle against the goals."""
    designs = sorted({d for d, _, _ in summary.counts})
    rows = [f"{'design':22s} " + " ".join(f"{k + ' (covered/total)':>22s}"
                                          for k in ("line", "branch", "toggle"))]
    for d in designs:
        cells = []
        for kind in ("line", "branch", "toggle"):
            c, t = summary.figure(d, kind)
            goal = GOALS.get(d, {}).get(kind)
            ok = "" if goal is None or not t else (" ok" if 100.0 * c >= goal * t else " <goal")
            cells.append(f"{_pct(c, t)} {c:>6d}/{t:<6d}{ok}")
        rows.append((f"{TOP_NAMES.get(d, d):22s} " + " ".join(f"{x:>22s}" for x in cells))
                    .rstrip())
    for d, (c, t, n, a) in sorted(summary.reachable.items()):
        goal = GOALS.get(d, {}).get("toggle")
        ok = "" if goal is None or not t else (" ok" if 100.0 * c >= goal * t else " <goal")
        rows.append(f"{TOP_NAMES.get(d, d)}: toggle on the builds of reachable width "
                    f"({n} of {a}): {_pct(c, t).strip()} {c}/{t}{ok}")
    rows.append(f"goals (dptbd_axi, dptbd_seg): line {GOALS['axi']['line']:.0f} %, branch "
                f"{GOALS['axi']['branch']:.0f} %, toggle {GOALS['axi']['toggle']:.0f} %, "
                f"outside the exclusions; {len(summary.uncovered)} uncovered line/branch/"
                f"toggle names, {len(summary.stale)} stale exclusion(s)")
    return "\n".join(rows)


def _verilog(group: Sequence[Entry]) -> str:
    """Where a name's points are: ``verilog/<build>/…:line`` of the first, and how many more."""
    first = min(group, key=lambda e: (e.build, e.verilog_line))
    more = f" and {len(group) - 1} more" if len(group) > 1 else ""
    return f"Verilog line {first.verilog_line} of `verilog/{first.build}/`{more}"


def _proof(proof) -> str:
    """One build's proof: its script, its seconds, and the time limit it fell back from."""
    from dptbd.sim.coverage.constant_bits import SCRIPT
    text = f"{len(proof.bits)} bits, `{proof.script}`, {proof.seconds:.0f} s"
    if proof.script != SCRIPT and proof.stopped_after is not None:
        text += f" (`{SCRIPT}` stopped at its limit of {proof.stopped_after} s of CPU time)"
    return text


def _markdown(summary: Summary) -> str:
    lines = ["# Code coverage of the RTL", "",
             "Figures are covered / total outside the exclusions "
             "(`sim/coverage/exclusions.toml`); see `docs/simulation.md`, \"Code coverage\".",
             "", "```", format_table(summary), "```", ""]
    for d in sorted({d for d, _, _ in summary.counts}):
        lines += [f"## {TOP_NAMES.get(d, d)} (`{d}`)", "",
                  "| module | line | branch | toggle | excluded |", "|---|---|---|---|---|"]
        modules = sorted({m for dd, m, _ in summary.counts if dd == d})
        for m in modules:
            cells = []
            excluded = 0
            for kind in ("line", "branch", "toggle"):
                c, t, x = summary.counts.get((d, m, kind), [0, 0, 0])
                excluded += x
                cells.append(f"{_pct(c, t).strip()} ({c}/{t})")
            lines.append(f"| `{m}` | " + " | ".join(cells) + f" | {excluded} |")
        lines.append("")
        missing = [(n, g) for n, g in summary.uncovered if g[0].design == d]
        toggles = [g for _, g in missing if g[0].kind == "toggle"]
        points = [g for _, g in missing if g[0].kind != "toggle"]
        if points:
            lines += ["Uncovered line and branch points (Amaranth source, what, Verilog):", ""]
            for g in points:
                e = g[0]
                lines.append(f"- `{e.src or '?'}` {e.kind} `{e.what}` in `{e.module}` "
                             f"({_verilog(g)})")
            lines.append("")
        if toggles:
            lines += [f"Signal bits never toggled ({len(toggles)}; Amaranth declaration, "
                      "module, bit):", ""]
            for g in toggles[:400]:
                e = g[0]
                lines.append(f"- `{e.src or '?'}` `{e.module}` `{e.what}` ({_verilog(g)})")
            if len(toggles) > 400:
                lines.append(f"- … and {len(toggles) - 400} more (coverage.json)")
            lines.append("")
    if summary.constant or summary.proofs:
        from dptbd.sim.coverage.constant_bits import REASON
        lines += [f"## Register bits excluded as proven constant ({len(summary.constant)})", "",
                  f"Reason: {REASON}.", ""]
        lines += [f"- `{name}`: {_proof(proof)}" for name, proof in sorted(summary.proofs.items())]
        lines.append("")
        by_reg = collections.defaultdict(list)
        for d, m, _, _, w in summary.constant:
            reg, _, bit = w.partition("[")
            by_reg[(d, m, reg)].append(bit.rstrip("]") or "0")
        lines += [f"- `{d}` `{m}` `{reg}` bits {', '.join(sorted(bits, key=int))}"
                  for (d, m, reg), bits in sorted(by_reg.items())]
        lines.append("")
    if summary.stale:
        lines += ["## Stale exclusions", ""]
        lines += [f"- `{ex.point}` {ex.kind} `{ex.what or '*'}` ({ex.design}): {why}"
                  for ex, why in summary.stale]
        lines.append("")
    return "\n".join(lines)
