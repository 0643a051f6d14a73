"""The campaign's bins: the runs' bins merged by addition (:func:`merge`), the table in group
order (:func:`table`) and the verdict on the bins no run hit (:func:`empty_bins`,
:func:`empty_message`)."""

from __future__ import annotations

import re
from typing import Mapping

from dptbd.sim.coverage.bins.groups import BANDS, GROUPS, POSITIONS

__all__ = ["merge", "table", "empty_bins", "empty_message"]


def merge(*runs: Mapping[str, int]) -> dict[str, int]:
    """The bins of several runs: every declared bin, hits added."""
    out: dict[str, int] = {}
    for counts in runs:
        for key, hits in counts.items():
            out[key] = out.get(key, 0) + int(hits)
    return out


_BAND_ORDER = {name: i for i, (name, *_) in enumerate(BANDS)}


def _order(key: str):
    """Group order, then the bands and positions in their order, numbers by value."""
    group, _, label = key.partition(": ")
    index = next((i for i, g in enumerate(GROUPS) if g.name == group), len(GROUPS))
    stall = re.fullmatch(r"gaps (\w+), back-pressure (\w+), (.+)", label)
    if stall:
        g, b, p = stall.groups()
        return index, [_BAND_ORDER.get(g, 9), _BAND_ORDER.get(b, 9),
                       POSITIONS.index(p) if p in POSITIONS else 9]
    return index, [(0, int(t), "") if t.isdigit() else (1, 0, t)
                   for t in re.split(r"(\d+)", label)]


def table(counts: Mapping[str, int]) -> list[tuple[str, str, int]]:
    """(bin, the designs whose runs fill it, hits) of every bin, in group order."""
    designs = {g.name: ", ".join(g.designs) for g in GROUPS}
    return [(key, designs.get(key.split(":", 1)[0], "?"), int(counts[key]))
            for key in sorted(counts, key=_order)]


def empty_bins(counts: Mapping[str, int]) -> list[str]:
    """The declared bins no run hit, in group order."""
    return [key for key, _, hits in table(counts) if hits == 0]


def empty_message(empty: list[str]) -> str:
    """The verdict of a campaign that left bins empty."""
    return (f"functional coverage: {len(empty)} empty bin{'' if len(empty) == 1 else 's'}: "
            + "; ".join(empty))
