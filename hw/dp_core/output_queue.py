"""DPCore's output queue: the FIFO of the state words, the twin FIFO of their flags, the
events and the input credit (``docs/gateware.md``; :class:`~dptbd.hw.dp_core.core.DPCore`
builds it after the write-back)."""

from __future__ import annotations

from amaranth.hdl import Module, Signal
from amaranth.lib import data

from dptbd.config import DPConfig
from dptbd.hw.dp_core.ports import state_events
from dptbd.hw.input_credit import InputCredit
from dptbd.hw.layouts import state_layout, state_word_layout
from dptbd.hw.thermometer_fifo import ThermometerFIFO

__all__ = ["queue_output"]


def queue_output(m: Module, cfg: DPConfig, fifo_depth: int, accumulator, at_state, states,
                 events, accept, input_ready, style: str = "binary") -> None:
    """Queue the ``accumulator``'s word with the side band ``at_state`` (its flags and valid
    bit at the state stage) for ``states``, drive ``events`` from it, and drive
    ``input_ready`` from a credit of ``fifo_depth`` words taken by ``accept``: a pixel is
    accepted only when the FIFO is sure to have room for its word. ``style`` is the
    flags FIFO's pointers (``output_queue_style``: ``"binary"`` or ``"one_hot"``)."""
    result = Signal(state_layout(cfg))
    m.d.comb += [
        result.energy.eq(accumulator.energy),
        result.direction.eq(accumulator.direction),
        result.end_of_line.eq(at_state.end_of_line),
        result.end_of_frame.eq(at_state.end_of_frame),
        result.end_of_segment.eq(at_state.end_of_segment),
    ]
    # The FIFO also carries the accumulator's saturated flag, for the `saturated` event.
    # Its flags and the input credit are registers of
    # thermometer counters (hw/thermometer_fifo.py, hw/input_credit.py): the cycles
    # of SyncFIFOBuffered and of a binary credit counter, without their adders and
    # comparators on the way to `states.valid`'s successor and to `pixels.ready`.
    # The word's flags (line, frame, segment ends, saturated) go through a twin FIFO in
    # flip-flops, in lockstep with the memory FIFO of (E, d): the segmenter's control,
    # which reads them with the word, does not wait on a block-RAM read.
    flag_layout = data.StructLayout({"end_of_line": 1, "end_of_frame": 1,
                                     "end_of_segment": 1, "saturated": 1})
    m.submodules.output_fifo = output_fifo = ThermometerFIFO(
        state_word_layout(cfg), fifo_depth)
    m.submodules.output_flags = output_flags = ThermometerFIFO(
        flag_layout, fifo_depth, storage="one_hot" if style == "one_hot" else "registers")
    m.d.comb += [
        output_fifo.w.payload.energy.eq(result.energy),
        output_fifo.w.payload.direction.eq(result.direction),
        output_flags.w.payload.end_of_line.eq(result.end_of_line),
        output_flags.w.payload.end_of_frame.eq(result.end_of_frame),
        output_flags.w.payload.end_of_segment.eq(result.end_of_segment),
        output_flags.w.payload.saturated.eq(accumulator.saturated),
        output_fifo.w.valid.eq(at_state.valid),
        output_flags.w.valid.eq(at_state.valid),
        states.payload.energy.eq(output_fifo.r.payload.energy),
        states.payload.direction.eq(output_fifo.r.payload.direction),
        states.payload.end_of_line.eq(output_flags.r.payload.end_of_line),
        states.payload.end_of_frame.eq(output_flags.r.payload.end_of_frame),
        states.payload.end_of_segment.eq(output_flags.r.payload.end_of_segment),
        states.valid.eq(output_fifo.r.valid),
        output_fifo.r.ready.eq(states.ready),
        output_flags.r.ready.eq(states.ready),
    ]
    state_events(m, events, states, output_flags.r.payload.saturated)

    # ---- credits: accept only what the FIFO is sure to have room for -------------
    m.submodules.input_credit = credit = InputCredit(fifo_depth)
    m.d.comb += [
        credit.accept.eq(accept),
        credit.handed_out.eq(states.valid & states.ready),
        input_ready.eq(credit.ready),
    ]
