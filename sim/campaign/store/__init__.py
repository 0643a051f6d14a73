"""The campaign's runs of the designs built with ``--state-store axi``, their state in an
AXI4 memory model: ``dptbd_dp`` (design ``"dp_axi"``,
:class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi`) and the drop-in core ``dptbd_axi``
(design ``"axi_store"``).

* :mod:`dptbd.sim.campaign.store.cases`: their cases, fault classes and read latency
  classes;
* :mod:`dptbd.sim.campaign.store.dp_axi`: a ``"dp_axi"`` run drawn, run (Verilator, or the
  Amaranth simulator for error runs) and checked;
* :mod:`dptbd.sim.campaign.store.axi_store`: an ``"axi_store"`` run drawn, run on Verilator
  and checked, with resets or with an SLVERR / DECERR window;

all importable from here.
"""

from __future__ import annotations

from dptbd.sim.campaign.store.axi_store import (ErrorWindow, MemoryPlan, build_axi_store,
                                                check_axi_store_run, draw_error_window,
                                                draw_memory, error_margin, window_cycles)
from dptbd.sim.campaign.store.cases import (LATENCY_DRAW, STORE_FAULTS, axi_store_cases,
                                            store_cases, store_config)
from dptbd.sim.campaign.store.dp_axi import (StorePlan, boundary_bursts, build_store,
                                             check_store_run, draw_store_run)

__all__ = ["STORE_FAULTS", "LATENCY_DRAW", "store_config", "StorePlan", "draw_store_run",
           "check_store_run", "store_cases", "boundary_bursts", "build_store", "MemoryPlan",
           "draw_memory", "axi_store_cases", "build_axi_store", "check_axi_store_run",
           "ErrorWindow", "draw_error_window", "window_cycles", "error_margin"]
