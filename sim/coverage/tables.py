"""The coverage report's text (:class:`~dptbd.sim.coverage.summary.Summary` written out): the
terminal table against the goals (:func:`~dptbd.sim.coverage.tables.format_table`,
:data:`~dptbd.sim.coverage.tables.GOALS`), ``report.md`` and ``coverage.json``.
"""

from __future__ import annotations

import collections
from typing import Sequence

from dptbd.sim.coverage.summary import Entry, Summary

__all__ = ["GOALS", "TOP_NAMES", "format_table"]

#: Goals per design: percent of line, branch and toggle points outside the exclusions.
GOALS = {"axi": {"line": 100.0, "branch": 100.0, "toggle": 95.0},
         "segmenter": {"line": 100.0, "branch": 100.0, "toggle": 95.0}}

TOP_NAMES = {"dp": "dptbd_dp", "core": "DPCore (dptbd_dp)", "segmenter": "dptbd_seg",
             "axi": "dptbd_axi"}


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
