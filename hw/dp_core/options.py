"""DPCore's implementation options: the allowed values of each, and the line buffer each
``line_buffer_style`` builds (:class:`~dptbd.hw.dp_core.core.DPCore`, ``DPCoreWide``)."""

from __future__ import annotations

from dptbd.hw.histogram import HISTOGRAM_STYLES
from dptbd.hw.line_buffer import LineBuffer
from dptbd.hw.read_ahead_store import STATE_STORE_STYLES
from dptbd.hw.schedule import MAX_TREE_STAGES
from dptbd.hw.segmenter import CONTROL_STYLES
from dptbd.hw.weight_lut import WRITE_DECODES

__all__ = ["LINE_BUFFER_STYLES", "SIDEBAND_DELAYS", "OUTPUT_QUEUE_STYLES", "REGISTER_READS",
           "CREDIT_READIES", "LUT_WRITES",
           "CORE_OPTIONS",
           "check_core_options",
           "core_line_buffer"]

#: ``DPCore(line_buffer_style=…)`` and the line buffer memory's ``ram_style`` for each.
LINE_BUFFER_RAM_STYLE = {"bram": None, "lutram": "distributed", "dp16kd": "dp16kd"}
LINE_BUFFER_STYLES = tuple(LINE_BUFFER_RAM_STYLE)
#: ``DPCore(sideband_delay=…)``.
SIDEBAND_DELAYS = ("registers", "memory")
#: ``DPCore(output_queue_style=…)``: the pointers of the output flags' FIFO in flip-flops
#: (:class:`~dptbd.hw.thermometer_fifo.ThermometerFIFO` ``storage="registers"`` or
#: ``"one_hot"``).
OUTPUT_QUEUE_STYLES = ("binary", "one_hot")
#: ``DPCore(register_read=…)``: the AXI top's register read in one level, or its first
#: level registered (:class:`~dptbd.hw.register_file.RegisterFile` ``read_registered``,
#: ``rvalid`` a cycle later).
REGISTER_READS = ("one_level", "two_level")
#: ``DPCore(credit_ready=…)``: the input credit's ``ready`` one register, or a copy per group
#: of loads (:class:`~dptbd.hw.input_credit.InputCredit` ``copies``; P > 1 only).
CREDIT_READIES = ("one", "per_load")
#: ``DPCore(lut_write=…)``: the weight LUT's write found by a case per entry or from two
#: registered one-hot halves of the address (:class:`~dptbd.hw.weight_lut.WeightLUT`
#: ``write_decode``).
LUT_WRITES = WRITE_DECODES

#: DPCore's implementation options (keyword arguments) with their allowed values; none
#: changes behaviour (``max_tree`` changes the latency), the synthesis flow picks them per
#: FPGA family. ``state_store_style`` is the on-chip store's (DPPipeline's) and
#: ``histogram_style`` the segmenter's histogram's, ``control_style`` the control logic of the
#: segmenter and of the AXI top's input, carried here so that one set of options reaches
#: every top; ``output_queue_style`` the output flags' FIFO's (P = 1; the P > 1 cores have
#: no flags twin); ``register_read`` the AXI top's register block's read; ``credit_ready`` the
#: input credit's ``ready`` registers (P > 1); ``lut_write`` the weight LUT's write decode.
CORE_OPTIONS = {"line_buffer_style": LINE_BUFFER_STYLES, "sideband_delay": SIDEBAND_DELAYS,
                "max_tree": tuple(MAX_TREE_STAGES), "state_store_style": STATE_STORE_STYLES,
                "histogram_style": HISTOGRAM_STYLES, "control_style": CONTROL_STYLES,
                "output_queue_style": OUTPUT_QUEUE_STYLES,
                "register_read": REGISTER_READS,
                "credit_ready": CREDIT_READIES,
                "lut_write": LUT_WRITES}


def check_core_options(**options: str) -> None:
    """Refuse an option of :data:`CORE_OPTIONS` whose value is not one it allows
    (``max_tree`` aside: the schedule refuses it, naming the supported builds):
    ``ValueError`` naming the option, the allowed values and the value given."""
    for name, value in options.items():
        allowed = CORE_OPTIONS[name]
        if name != "max_tree" and value not in allowed:
            raise ValueError(f"{name} must be one of {allowed}, got {value!r}")


def core_line_buffer(shape, depth: int, taps: int, style: str) -> LineBuffer:
    """The line buffer of ``line_buffer_style`` ``style`` (DPCore's and DPCoreWide's):
    ``"lutram"`` read interleaved when ``depth`` is even and >= 4, ``"dp16kd"`` the ECP5
    DP16KDs read through their output register (``depth`` >= 3: a row has at least 3
    pixels, a beat row at least 3 beats)."""
    return LineBuffer(shape, depth=depth, taps=taps, ram_style=LINE_BUFFER_RAM_STYLE[style],
                      interleaved_read=style == "lutram" and depth % 2 == 0 and depth >= 4)
