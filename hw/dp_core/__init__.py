"""The DP pipeline without its state store: streams in, streams out, a state-store port.

Use :class:`~dptbd.hw.dp_pipeline.DPPipeline` for the complete design with on-chip state
memory; use :class:`DPCore` directly when the W*H-word state store lives elsewhere (an
external SRAM, a larger block RAM), attached to the ``state_store`` port
(:class:`~dptbd.hw.state_store.StateStoreSignature`). ``docs/gateware.md`` describes the
pipeline stage by stage; :class:`~dptbd.hw.schedule.PipelineSchedule` gives its timing.

Modules: :mod:`.core` (``DPCore``), :mod:`.options` (its implementation options,
``CORE_OPTIONS``), :mod:`.ports` (the port members and events the tops around it share),
:mod:`.output_queue` (its output FIFOs and input credit); their names are re-exported here.
"""

from __future__ import annotations

from dptbd.hw.dp_core.core import DPCore
from dptbd.hw.dp_core.options import (CORE_OPTIONS, LINE_BUFFER_STYLES, OUTPUT_QUEUE_STYLES,
                                      SIDEBAND_DELAYS, check_core_options, core_line_buffer)
from dptbd.hw.dp_core.ports import (family_write_members, family_write_ports,
                                    lut_write_members, run_time_k_members, state_events)

__all__ = ["DPCore", "LINE_BUFFER_STYLES", "SIDEBAND_DELAYS", "OUTPUT_QUEUE_STYLES",
           "CORE_OPTIONS", "check_core_options",
           "core_line_buffer",
           "lut_write_members", "family_write_members", "family_write_ports",
           "run_time_k_members", "state_events"]
