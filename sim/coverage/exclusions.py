"""The exclusion list of code coverage: points that cannot be reached, each with why.

``sim/coverage/exclusions.toml`` holds one ``[[exclude]]`` table per point::

    [[exclude]]
    design = "segmenter"             # the top level (dptbd.sim.verilator.cache.DESIGNS)
    point = "hw/segmenter.py:201"    # the Amaranth file:line (not the Verilog line)
    kind = "branch"                  # line, branch or toggle
    what = "else"                    # optional: Verilator's if / elsif / else / case /
                                     # block, or the signal bit of a toggle; absent: all
    reason = "..."                   # why no stimulus can reach it
    bits = "20-31"                   # optional, toggle only: the bits lo-hi of the register
                                     # named by what (a bit class, e.g. a counter's high bits)

An entry names the point by its Amaranth source, so it survives a renumbering of the
Verilog. The report counts excluded points apart and lists an entry as stale when it
matches no point (the source changed) or every point it matches was covered.
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import tomllib

__all__ = ["EXCLUSIONS", "Exclusion", "load_exclusions"]

EXCLUSIONS = pathlib.Path(__file__).resolve().parent / "exclusions.toml"

_KINDS = ("line", "branch", "toggle")
_KEYS = {"design", "point", "kind", "what", "reason", "bits"}


@dataclasses.dataclass(frozen=True)
class Exclusion:
    design: str
    point: str
    kind: str
    what: str | None
    reason: str
    bits: tuple[int, int] | None = None

    def matches(self, entry) -> bool:
        """Whether the located point ``entry`` (:class:`~dptbd.sim.coverage.report.Entry`)
        is this one."""
        if not (entry.design == self.design and entry.kind == self.kind
                and entry.src == self.point):
            return False
        if self.bits is not None:
            name, _, index = entry.what.partition("[")
            return (name == self.what and index.endswith("]") and index[:-1].isdigit()
                    and self.bits[0] <= int(index[:-1]) <= self.bits[1])
        return self.what is None or entry.what == self.what


def load_exclusions(path: str | os.PathLike = EXCLUSIONS) -> list[Exclusion]:
    """The entries of ``path``; ValueError naming the entry and what is wrong with it."""
    from dptbd.sim.verilator.cache import DESIGNS

    data = tomllib.loads(pathlib.Path(path).read_text())
    unknown = set(data) - {"exclude"}
    if unknown:
        raise ValueError(f"{path}: unknown table(s) {', '.join(sorted(unknown))}; the file "
                         f"holds [[exclude]] tables only")
    out = []
    for i, item in enumerate(data.get("exclude", []), 1):
        where = f"{path}: exclusion {i}"
        extra = set(item) - _KEYS
        if extra:
            raise ValueError(f"{where}: unknown key(s) {', '.join(sorted(extra))}; keys are "
                             f"design, point, kind, what, reason")
        missing = [k for k in ("design", "point", "kind", "reason") if not item.get(k)]
        if missing:
            raise ValueError(f"{where}: {', '.join(missing)} missing; every exclusion names "
                             f"its design, point, kind and the reason it cannot be reached")
        if item["design"] not in DESIGNS:
            raise ValueError(f"{where}: design {item['design']!r} is not one of "
                             f"{', '.join(DESIGNS)}")
        if item["kind"] not in _KINDS:
            raise ValueError(f"{where}: kind {item['kind']!r} is not one of "
                             f"{', '.join(_KINDS)}")
        file, _, line = item["point"].rpartition(":")
        if not file or not line.isdigit():
            raise ValueError(f"{where}: point {item['point']!r} is not file.py:line")
        bits = None
        if "bits" in item:
            lo, sep, hi = str(item["bits"]).partition("-")
            if item["kind"] != "toggle" or not item.get("what"):
                raise ValueError(f"{where}: bits is for a toggle exclusion whose what names "
                                 f"the register")
            if not (sep and lo.isdigit() and hi.isdigit() and int(lo) <= int(hi)):
                raise ValueError(f"{where}: bits {item['bits']!r} is not lo-hi (bit indices, "
                                 f"lo <= hi)")
            bits = (int(lo), int(hi))
        out.append(Exclusion(item["design"], item["point"], item["kind"], item.get("what"),
                             item["reason"], bits))
    return out
