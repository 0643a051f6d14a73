"""The bins of a run of ``dptbd_dp`` built with ``--state-store axi`` (design ``"dp_axi"``,
:mod:`dptbd.sim.campaign.store`): what a run declares (:func:`declared_store`) and what it
filled (:func:`store_bins`), from the run's draw (:class:`~dptbd.sim.campaign.store.StorePlan`)
and what the memory model observed (its counters: every bin is observed, none inferred);
the group is described in :mod:`dptbd.sim.coverage.bins`."""

from __future__ import annotations

from typing import Mapping

from dptbd.sim.coverage.bins.groups import key

__all__ = ["LATENCY_CLASSES", "STALLED_CHANNELS", "ERROR_BINS", "BOUNDARY_BINS", "OBSERVED",
           "latency_class", "declared_store", "store_bins"]

#: Read latency classes: (label, lowest, highest) cycles from AR handshake to the first beat.
LATENCY_CLASSES = (("read latency 0", 0, 0), ("read latency 1 … 99 cycles", 1, 99),
                   ("read latency 100 … 499 cycles", 100, 499),
                   ("read latency 500 cycles or more", 500, 10**9))

#: Each AXI4 channel's handshake stalled by the memory: the ready (AR, AW, W) or valid
#: (R, B) it drives low at random while the other side waits.
STALLED_CHANNELS = ("AR ready low", "AW ready low", "W ready low", "R valid low",
                    "B valid low")

#: Each error response on each direction, flagged and recovered from.
ERROR_BINS = tuple(f"{code} on a {direction}, flagged, recovered"
                   for direction in ("read", "write") for code in ("SLVERR", "DECERR"))

#: Bursts whose last byte is the last byte of a 4 KB page (the next one starts on it).
BOUNDARY_BINS = ("read burst ending at a 4 KB boundary", "write burst ending at a 4 KB boundary")

#: What the memory model counts in a run (``result.txt`` of the Verilator harnesses,
#: ``sim/harness/axi4_memory.h``), in the order of :data:`STALLED_CHANNELS` and
#: :data:`BOUNDARY_BINS` after the two burst counts.
OBSERVED = ("read_bursts", "write_bursts", "ar_stalls", "aw_stalls", "w_stalls", "r_stalls",
            "b_stalls", "read_boundary_bursts", "write_boundary_bursts")

GROUP = "store"


def latency_class(lo: int, hi: int) -> str:
    """The class of a latency range drawn inside one class."""
    for label, low, high in LATENCY_CLASSES:
        if low <= lo and hi <= high:
            return label
    raise ValueError(f"latency range ({lo}, {hi}) is not inside one class of "
                     f"{[c[1:] for c in LATENCY_CLASSES]}")


def declared_store() -> dict[str, int]:
    """Every bin (0 hits) a run of ``dptbd_dp --state-store axi`` declares."""
    labels = [c[0] for c in LATENCY_CLASSES] + list(STALLED_CHANNELS) + list(ERROR_BINS) \
        + list(BOUNDARY_BINS)
    return {key(GROUP, label): 0 for label in labels}


def store_bins(plan, *, passed: bool, observed: Mapping[str, int] | None = None
               ) -> dict[str, int]:
    """The bins of one run: ``plan`` its draw, ``passed`` its verdict (a failed run fills
    none), ``observed`` what the memory model counted (:data:`OBSERVED`; a key missing: 0).

    A latency class is hit by every read burst (``read_bursts``) of a run whose range lies
    in it; a channel's stall by every cycle the memory model saw it stalled (``ar_stalls``
    … ``b_stalls``: the manager's AR / AW / W valid waiting on a low ready, an R beat or a B
    response due with its valid held low); a boundary bin by every burst whose last byte
    the model saw at the end of a 4 KB page (``read_boundary_bursts``,
    ``write_boundary_bursts``); an error bin by a run whose injected error was flagged as
    documented and whose later segments were exact."""
    out = declared_store()
    if not passed:
        return out
    seen = {name: int((observed or {}).get(name, 0)) for name in OBSERVED}
    if plan.errors:
        for code, direction in plan.errors:
            out[key(GROUP, f"{code} on a {direction}, flagged, recovered")] += 1
    out[key(GROUP, latency_class(*plan.latency))] += seen["read_bursts"]
    for label, name in zip(STALLED_CHANNELS, OBSERVED[2:7]):
        out[key(GROUP, label)] += seen[name]
    for label, name in zip(BOUNDARY_BINS, OBSERVED[7:]):
        out[key(GROUP, label)] += seen[name]
    return out
