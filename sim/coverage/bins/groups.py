"""The bins' vocabulary: the groups, the stall bands and frame positions, the labels and
names of the bins every kind of run declares (:mod:`dptbd.sim.coverage.bins`)."""

from __future__ import annotations

import dataclasses

__all__ = ["STREAM", "AXI", "STORE", "BANDS", "POSITIONS", "LIST_LABELS", "LUT_STAGES", "LUT_CODES",
           "Group", "GROUPS", "SATURATION", "TIES", "ARESETN", "FIFO", "RANGE", "ALIGN",
           "BUS_REASONS", "band", "key", "words_in_flight", "declared_stall"]

STREAM = ("dp", "core", "segmenter")
AXI = ("axi",)
#: ``dptbd_dp --state-store axi`` and ``dptbd_axi --state-store axi``
#: (:mod:`dptbd.sim.campaign.store`).
STORE = ("dp_axi", "axi_store")

#: Stall density bands: (name, lowest density, highest density excluded).
BANDS = (("none", 0.0, 0.0), ("light", 0.0, 0.35), ("heavy", 0.35, 1.0))

POSITIONS = ("first row", "last row", "first column", "last column", "interior",
             "segment boundary frame")

LIST_LABELS = ("0 records (empty)", "exactly n records (0 < n < C)", "C records (at capacity)",
               "overflowing (more than C)")

LUT_STAGES = ("written between frames", "written in the first row",
              "written in a middle row", "written in the last row")
LUT_CODES = ("code 0", "code 2**F - 1", "code 2**F (the largest)")


@dataclasses.dataclass(frozen=True)
class Group:
    """A family of bins: its name (the prefix of its bins' names) and the designs whose
    runs fill it."""

    name: str
    designs: tuple[str, ...]


GROUPS = (Group("stall", STREAM + AXI), Group("reset", STREAM), Group("soft reset", AXI),
          Group("aresetn", AXI), Group("fault", STREAM + AXI), Group("LUT", STREAM + AXI),
          Group("saturation", STREAM + AXI), Group("lists", ("segmenter",) + AXI),
          Group("ties", ("segmenter",) + AXI), Group("register", AXI), Group("store", STORE))

SATURATION = "saturation: a state word at E = 2**B_E - 1"
TIES = "ties: two or more pixels in the threshold bin"
ARESETN = "aresetn: 0 words in flight"
FIFO = "more than L words (output FIFO)"
RANGE = " value out of range"
#: A setting with an alignment (``Field.align``: ``STATE_BASE`` of a store build) written a
#: value in range that is not a multiple of it.
ALIGN = " value not aligned"
BUS_REASONS = ("LUT write without wstrb = 1111", "LUT read", "write to a constant register",
               "write to a counter", "write to the status register", "unaligned write",
               "unaligned read", "unmapped write", "unmapped read")


def band(p: float) -> str:
    """The band of a stall density."""
    return "none" if p == 0 else ("light" if p < BANDS[1][2] else "heavy")



def key(group: str, label: str) -> str:
    """The name of the bin ``label`` of ``group``."""
    return f"{group}: {label}"


def words_in_flight(k: int) -> str:
    """The label of a (soft) reset that found ``k`` words in flight."""
    return f"{k} word{'' if k == 1 else 's'} in flight"


def declared_stall() -> dict[str, int]:
    """The stall bins (0 hits) every run declares: each band pair at each position."""
    return {key("stall", f"gaps {g}, back-pressure {b}, {p}"): 0
            for g, *_ in BANDS for b, *_ in BANDS for p in POSITIONS}
