"""The bins of a run of ``dptbd_dp`` built with ``--state-store axi`` (design ``"dp_axi"``,
:mod:`dptbd.sim.campaign.store`): what a run declares (:func:`declared_store`) and what it
filled (:func:`store_bins`), from the run's draw (:class:`~dptbd.sim.campaign.store.StorePlan`)
and what the memory model reported; the group is described in :mod:`dptbd.sim.coverage.bins`."""

from __future__ import annotations

from dptbd.sim.coverage.bins.groups import key

__all__ = ["LATENCY_CLASSES", "STALLED_CHANNELS", "ERROR_BINS", "BOUNDARY_BINS",
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


def store_bins(plan, *, passed: bool, read_bursts: int = 0, write_bursts: int = 0,
               boundary_bursts: tuple[int, int] = (0, 0)) -> dict[str, int]:
    """The bins of one run: ``plan`` its draw, ``passed`` its verdict (a failed run fills
    none), ``read_bursts`` / ``write_bursts`` the bursts the memory accepted and
    ``boundary_bursts`` (read, write) those of them ending at a 4 KB boundary.

    A latency class is hit by every read burst of a run whose range lies in it; a channel's
    stall by every burst of its direction in a run whose memory drove that ready
    (``axi_ready`` < 1) or valid (``axi_valid`` < 1) low at random; an error bin by a run
    whose injected error was flagged as documented and whose later segments were exact."""
    out = declared_store()
    if not passed:
        return out
    if plan.errors:
        for code, direction in plan.errors:
            out[key(GROUP, f"{code} on a {direction}, flagged, recovered")] += 1
    out[key(GROUP, latency_class(*plan.latency))] += read_bursts
    if plan.axi_ready < 1:
        for channel, bursts in (("AR", read_bursts), ("AW", write_bursts),
                                ("W", write_bursts)):
            out[key(GROUP, f"{channel} ready low")] += bursts
    if plan.axi_valid < 1:
        out[key(GROUP, "R valid low")] += read_bursts
        out[key(GROUP, "B valid low")] += write_bursts
    for label, hits in zip(BOUNDARY_BINS, boundary_bursts):
        out[key(GROUP, label)] += int(hits)
    return out
