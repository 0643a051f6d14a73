"""The cases of the campaign's AXI4 state store (:mod:`dptbd.sim.campaign.store`): the
``"dp_axi"`` cases (``dptbd_dp --state-store axi``, :func:`store_cases`), the ``"axi_store"``
ones (``dptbd_axi --state-store axi``, :func:`axi_store_cases`), their fault classes and the
read latency classes their runs draw from."""

from __future__ import annotations

__all__ = ["STORE_FAULTS", "LATENCY_DRAW", "store_config", "store_cases", "axi_store_cases"]

#: Fault classes of a ``"dp_axi"`` case.
STORE_FAULTS = ("read_error", "write_error")

#: Read latency ranges of the classes (:data:`dptbd.sim.coverage.bins.store.LATENCY_CLASSES`)
#: a run draws from.
LATENCY_DRAW = ((0, 0), (1, 99), (100, 499), (500, 700))


def store_config(case):
    """The :class:`~dptbd.config.AxiStoreConfig` of ``case``."""
    return case.cfg.axi_store(**dict(case.store or {}))


def store_cases():
    """The ``"dp_axi"`` cases of the default campaign (``docs/gateware.md``, "Verification
    campaign"): a 64 × 48 frame (6 KB of state: bursts at 4 KB boundaries) on a 32-bit bus
    with 8-beat bursts, a 40 × 24 r = 2 one on a 64-bit bus with 4-beat bursts and one
    burst in flight, and the error case on the Amaranth simulator (16 × 12)."""
    from dptbd.sim.campaign.cases import Case

    return [
        Case("dp-axi-64x48-k4-d32-b8-o4", dict(width=64, height=48, segment_frames=4),
             "dp_axi", 16, 8, store=dict(data_bits=32, burst_beats=8, outstanding=4)),
        Case("dp-axi-40x24-r2-k3-d64-b4-o1", dict(width=40, height=24, segment_frames=3,
                                                  radius=2, weight_frac_bits=6),
             "dp_axi", 20, 8, store=dict(data_bits=64, burst_beats=4, outstanding=1)),
        Case("dp-axi-16x12-k2-errors", dict(width=16, height=12, segment_frames=2),
             "dp_axi", 6, 4, STORE_FAULTS, store=dict(data_bits=64, burst_beats=4,
                                                      outstanding=2)),
    ]


def axi_store_cases():
    """The ``"axi_store"`` cases of the default campaign: the small ``"axi"`` case's
    parameter set (24 × 16, K = 2 of K_max 4, F = 0, B_E = 9, n = 3 of C = 6) with its state
    in AXI4 memory on a 32-bit bus, 4-beat bursts, 2 in flight: the AXI runs with resets,
    and (the same build) SLVERR / DECERR windows."""
    from dptbd.sim.axi.runs import AXI_FAULTS
    from dptbd.sim.campaign.cases import Case

    frame = dict(width=24, height=16, segment_frames=2, max_segment_frames=4,
                 weight_frac_bits=0, energy_bits=9, candidate_count=3, candidate_capacity=6,
                 histogram_bits=6, histogram_shift=2)
    store = dict(data_bits=32, burst_beats=4, outstanding=2)
    return [
        Case("axi-store-24x16-f0-k2", dict(frame), "axi_store", 40, 8, AXI_FAULTS,
             store=dict(store)),
        Case("axi-store-24x16-f0-k2-errors", dict(frame), "axi_store", 16, 6, STORE_FAULTS,
             store=dict(store)),
    ]
