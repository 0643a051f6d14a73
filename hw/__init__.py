"""Amaranth 0.5 gateware of the streaming DP pipeline (``docs/gateware.md``).

``DPPipeline`` is the top level (on-chip state store) and ``DPCore`` the same pipeline with
its state store outside. ``dptbd.hw.flow.verilog`` converts either to Verilog with a JSON
manifest (``python -m dptbd.hw.flow.verilog --out build/dptbd_dp.v``); ``dptbd.hw.layouts``
holds the payload layouts and pack/unpack helpers for testbenches.
"""

from dptbd.hw.dp_core import DPCore
from dptbd.hw.dp_pipeline import DPPipeline
from dptbd.hw.schedule import PipelineSchedule, check_supported

__all__ = ["DPPipeline", "DPCore", "PipelineSchedule", "check_supported"]
