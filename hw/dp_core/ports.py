"""The port members and event outputs that :class:`~dptbd.hw.dp_core.core.DPCore` shares
with the tops built around it (``DPPipeline``, ``DPPipelineAxi``, the P > 1 pipeline, the
segmenter tops)."""

from __future__ import annotations

from amaranth.hdl import Module, signed
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.family_blocks import FamilyBlocks
from dptbd.hw.layouts import event_layout

__all__ = ["lut_write_members", "family_write_members", "family_write_ports",
           "run_time_k_members", "state_events"]


def lut_write_members(cfg: DPConfig) -> dict:
    """The LUT write port members shared by :class:`~dptbd.hw.dp_core.core.DPCore` and
    ``DPPipeline``."""
    return {
        "lut_addr": In(range(cfg.lut_entries)),
        "lut_data": In(cfg.weight_bits),
        "lut_we": In(1),
    }


# ---- paper 000's family (docs/arithmetic.md §8) ------------------------------------------
def family_write_members(cfg: DPConfig) -> dict:
    """The merit and penalty LUT write ports, shared by
    :class:`~dptbd.hw.dp_core.core.DPCore` and ``DPPipeline``: each exists only when its LUT
    is built (:class:`~dptbd.hw.family_blocks.FamilyBlocks`), so a paper-001 configuration
    has none."""
    blocks = FamilyBlocks.from_config(cfg)
    members = {}
    if blocks.merit_lut:
        members.update({
            "merit_addr": In(cfg.input_bits),
            "merit_data": In(signed(cfg.merit_width)),
            "merit_we": In(1),
        })
    if blocks.penalty_lut:
        members.update({
            "penalty_addr": In(range(cfg.lut_entries)),
            "penalty_data": In(cfg.penalty_width),
            "penalty_we": In(1),
        })
    return members


def family_write_ports(cfg: DPConfig) -> tuple[str, ...]:
    """Names of the members :func:`family_write_members` adds for ``cfg``."""
    return tuple(family_write_members(cfg))
# ---- end of paper 000's family -----------------------------------------------------------


def run_time_k_members(cfg: DPConfig) -> dict:
    """The run-time K port and the DP's event outputs, shared by
    :class:`~dptbd.hw.dp_core.core.DPCore` and ``DPPipeline`` (``docs/gateware.md``,
    "Run-time settings" and "Events")."""
    return {
        "segment_frames": In(range(1, cfg.k_max + 1), init=cfg.segment_frames),
        "segment_begin": Out(1),
        "events": Out(event_layout(cfg)),
    }


def state_events(m: Module, events, states, saturated) -> None:
    """Drive ``events`` from a ``states`` stream: ``frame_done``, ``segment_done`` and
    ``saturated`` (the word's ``saturated`` flag) pulse with the word's handshake."""
    transfer = states.valid & states.ready
    m.d.comb += [
        events.frame_done.eq(transfer & states.payload.end_of_frame),
        events.segment_done.eq(transfer & states.payload.end_of_segment),
        events.saturated.eq(transfer & saturated),
    ]
