"""How coverage points add up (:func:`~dptbd.sim.coverage.summary.summarise`), each point of a
build located in the Amaranth source (:class:`~dptbd.sim.coverage.summary.Entry`,
:func:`~dptbd.sim.coverage.summary.entries`), and the toggle figure over the builds of
reachable width only (:func:`~dptbd.sim.coverage.summary.reachable_toggle`).

A **line** or **branch** point is named by its design, Verilog module (the Amaranth hierarchy),
kind, Amaranth ``file:line`` and what (``if``, ``else``, ``case``, …); a **toggle** point, a
register bit, by design, module, register and bit index. The points of one name — the same
``m.If`` in several processes, or in the builds of several parameter sets of one design — count
once, covered if any run covered any of them (a bit that exists in a wide parameter set only
counts there). Points listed in the exclusion list (:mod:`dptbd.sim.coverage.exclusions`) are
counted apart; the figures are covered / total outside them.
"""

from __future__ import annotations

import collections
import dataclasses
from typing import Sequence

from dptbd.sim.coverage.code import Point, locate, registers, source_map, unescape, usable

__all__ = ["Entry", "Summary", "entries", "summarise", "reachable_width", "reachable_toggle"]


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
