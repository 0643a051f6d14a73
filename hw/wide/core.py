"""DPCoreWide: the DP core at P = 2 or 4 pixels per clock, its state store outside, and the
check of a configuration it builds."""

from __future__ import annotations

from amaranth.hdl import Cat, Module, Mux, Signal, unsigned
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.errors import ConfigError
from dptbd.hw.accumulator import Accumulator
from dptbd.hw.controller import Controller
from dptbd.hw.delay import delayed, delayed_in_memory
from dptbd.hw.dp_core import (check_core_options, core_line_buffer, lut_write_members,
                              run_time_k_members, state_events)
from dptbd.hw.input_credit import InputCredit
from dptbd.hw.max_tree import MaxTree
from dptbd.hw.pipelined_max import SplitMaxTree
from dptbd.hw.schedule import PipelineSchedule, check_supported, read_ahead_distance
from dptbd.hw.thermometer_fifo import ThermometerFIFO
from dptbd.hw.weight_lut import WeightLUT, resolve_lut_style
from dptbd.hw.weighted_candidate import WeightedCandidate
from dptbd.hw.wide.layouts import beat_word_layout, wide_pixel_layout, wide_state_layout
from dptbd.hw.wide.state_store import WideStateStoreSignature
from dptbd.hw.wide.window import WideWindow


def check_wide(cfg: DPConfig, *, max_tree: str = "compact") -> PipelineSchedule:
    """Refuse what the P > 1 pipeline does not build; return its schedule.

    Raises
    ------
    dptbd.errors.ConfigError
        * ``pixels_per_clock == 1``: that is :class:`~dptbd.hw.dp_core.DPCore`.
        * a paper-000 family field in use (``docs/arithmetic.md`` §8).
        * a frame too small for the read-ahead counted in beats:
          ``(W/P)*H - r*(W/P + 1) <= write latency`` (``docs/gateware.md``).
        * whatever :func:`~dptbd.hw.schedule.check_supported` refuses for the beat
          configuration (e.g. overlapping segments).
    """
    p = cfg.pixels_per_clock
    if p == 1:
        raise ConfigError("pixels_per_clock=1 is built by DPCore and DPPipeline, not by the "
                          "P-pixel pipeline (pixels_per_clock 2 or 4)")
    used = sorted(cfg.family_fields_in_use)
    if used:
        raise ConfigError(f"pixels_per_clock={p} is built for paper 001's DP only; the "
                          f"paper-000 field(s) {used} need pixels_per_clock=1")
    beats = cfg.beat_config()
    schedule = PipelineSchedule.from_config(beats, max_tree=max_tree)
    margin = cfg.frame_beats - read_ahead_distance(beats)
    if margin <= schedule.write_latency:
        raise ConfigError(
            f"width={cfg.width} x height={cfg.height} is too small for the read-ahead of "
            f"radius={cfg.radius} at pixels_per_clock={p}: the gateware needs "
            f"(width/P)*height - radius*(width/P+1) > write latency {schedule.write_latency} "
            f"cycles, but it is {margin}; each state must be written before the next frame "
            f"reads it; use a larger frame")
    return check_supported(beats, max_tree=max_tree)


class DPCoreWide(wiring.Component):
    """Streaming direction-weighted DP, P = 2 or 4 pixels per clock, external state store.

    Parameters and properties as :class:`~dptbd.hw.dp_core.DPCore` (same options, same
    schedule and latency, counted in beats; ``state_store_style``, ``histogram_style``,
    ``control_style``, ``output_queue_style`` and ``register_read`` are accepted and not
    used here (``histogram_style`` reaches the wide segmenter's histogram banks through
    :class:`~dptbd.hw.wide.dp_segmenter.DPSegmenterWide`); ``credit_ready="per_load"``
    gives the input credit's ``ready`` four registers, one each for the credit's own count,
    the input port and the store's read, the controller, and the line buffer
    (:class:`~dptbd.hw.input_credit.InputCredit` ``copies``; same cycles); ``lut_write`` is
    DPCore's: the wide store is :class:`~dptbd.hw.wide.state_store.WideStateStore`, the wide
    histogram :class:`~dptbd.hw.banked_histogram.BankedHistogram` of ``histogram_style``
    banks, the control logic the generic one, the flags travel with the words in the one
    output FIFO);
    refused with :class:`~dptbd.errors.ConfigError` as :func:`check_wide` says.

    Members
    -------
    pixels : In(stream.Signature(wide_pixel_layout(cfg)))
        Input beats in raster order; ``first`` marks the beat of pixel (0, 0).
    states : Out(stream.Signature(wide_state_layout(cfg)))
        The new (E, d) of the P pixels of every accepted beat, in acceptance order.
    lut_addr, lut_data, lut_we, segment_frames, segment_begin, events
        As :class:`~dptbd.hw.dp_core.DPCore`'s, per beat (``events.saturated``: a lane's E
        was clipped).
    state_store : Out(WideStateStoreSignature(cfg))
    """

    def __init__(self, cfg: DPConfig, *, output_fifo_depth: int | None = None,
                 lut_style: str = "auto", line_buffer_style: str = "bram",
                 sideband_delay: str = "registers", max_tree: str = "compact",
                 state_store_style: str = "memory", histogram_style: str = "memory",
                 control_style: str = "generic", output_queue_style: str = "binary",
                 register_read: str = "one_level", credit_ready: str = "one",
                 lut_write: str = "case"):
        self._options = dict(line_buffer_style=line_buffer_style, sideband_delay=sideband_delay,
                             max_tree=max_tree, state_store_style=state_store_style,
                             histogram_style=histogram_style, control_style=control_style,
                             output_queue_style=output_queue_style, register_read=register_read,
                             credit_ready=credit_ready, lut_write=lut_write)
        check_core_options(**self._options)
        self._schedule = check_wide(cfg, max_tree=max_tree)
        self._cfg = cfg
        self._lut_style = resolve_lut_style(cfg, lut_style)
        if output_fifo_depth is None:
            output_fifo_depth = self._schedule.latency + 2
        if output_fifo_depth < 3:
            raise ValueError(f"output_fifo_depth must be an integer in [3, inf), got "
                             f"{output_fifo_depth}")
        self._fifo_depth = output_fifo_depth
        super().__init__({
            "pixels": In(stream.Signature(wide_pixel_layout(cfg))),
            "states": Out(stream.Signature(wide_state_layout(cfg))),
            **lut_write_members(cfg),
            **run_time_k_members(cfg),
            "state_store": Out(WideStateStoreSignature(cfg)),
        })
        self._resync = Signal(name="resync")

    config = property(lambda self: self._cfg, doc="The configuration.")
    resync = property(lambda self: self._resync, doc="As :attr:`DPCore.resync`, per beat.")
    schedule = property(lambda self: self._schedule, doc="Cycle offsets of every stage.")
    latency = property(lambda self: self._schedule.latency,
                       doc="Cycles from a beat's acceptance to its states on ``states``.")
    output_fifo_depth = property(lambda self: self._fifo_depth, doc="Output FIFO entries.")
    lut_style = property(lambda self: self._lut_style, doc="The weight LUTs' storage.")

    @property
    def core_options(self) -> dict:
        """The storage options (:data:`~dptbd.hw.dp_core.CORE_OPTIONS`) of this core."""
        return dict(self._options)

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        sched = self._schedule
        moves = cfg.n_moves
        lanes = cfg.pixels_per_clock
        r = cfg.radius
        beats = cfg.beat_config()

        # ---- cycle 0: handshake, beat position, read-ahead ---------------------------
        # the input credit's ready: one register, or (credit_ready="per_load") one for each
        # of the credit's count, the port and the store's read, the controller, the line
        # buffer: the same accept in each, from a register beside its loads
        copies = 4 if self._options["credit_ready"] == "per_load" else 1
        input_ready = Signal(copies)
        m.d.comb += self.pixels.ready.eq(input_ready[1] if copies > 1 else input_ready)
        if copies > 1:
            own, accept, control, lines = (self.pixels.valid & input_ready[k] for k in range(4))
        else:
            own = accept = control = lines = self.pixels.valid & input_ready
        m.submodules.controller = controller = Controller(beats)
        m.d.comb += [
            controller.accept.eq(control),
            controller.first.eq(self.pixels.payload.first),
            controller.segment_frames.eq(self.segment_frames),
            self.segment_begin.eq(controller.segment_begin),
            self._resync.eq(control & controller.resync),
            self.state_store.read_addr.eq(controller.read_addr),
            self.state_store.read_en.eq(accept),
        ]
        # DPCore's line buffer of each style, a beat (P words) per entry
        m.submodules.line_buffer = line_buffer = core_line_buffer(
            beat_word_layout(cfg), cfg.row_beats, 2 * r, self._options["line_buffer_style"])
        m.d.comb += line_buffer.advance.eq(lines)

        # ---- cycle 1 (fetch): new beat column ----------------------------------------
        pixel_in = Signal(data.ArrayLayout(unsigned(cfg.input_bits), lanes))
        m.d.comb += pixel_in.as_value().eq(
            Cat(*[getattr(self.pixels.payload, f"pixel_{k}") for k in range(lanes)]))
        pixel = delayed(m, pixel_in, sched.fetch, name="pixel")
        m.d.comb += line_buffer.data_in.eq(self.state_store.read_data)
        m.submodules.window = window = WideWindow(cfg)
        m.d.comb += [
            window.column[0].eq(self.state_store.read_data),
            *[window.column[k + 1].eq(line_buffer.taps[k]) for k in range(2 * r)],
            window.shift.eq(controller.valid),
            window.row_inside.eq(controller.row_inside),
            # the controller's beat-column flags: bit i is beat g + r - i inside the row
            window.first_beat.eq(~controller.col_inside[r + 1]),
            window.last_beat.eq(~controller.col_inside[r - 1]),
        ]
        sideband = Signal(data.StructLayout({
            "valid": 1, "pixel": data.ArrayLayout(unsigned(cfg.input_bits), lanes),
            "start_of_frame": 1, "segment_start": 1, "end_of_line": 1, "end_of_frame": 1,
            "end_of_segment": 1,
        }))
        m.d.comb += [
            sideband.valid.eq(controller.valid),
            sideband.pixel.eq(pixel),
            sideband.start_of_frame.eq(controller.position.start_of_frame),
            sideband.segment_start.eq(controller.position.segment_start),
            sideband.end_of_line.eq(controller.position.end_of_line),
            sideband.end_of_frame.eq(controller.position.end_of_frame),
            sideband.end_of_segment.eq(controller.position.end_of_segment),
        ]
        if self._options["sideband_delay"] == "memory":
            late_valid = delayed(m, sideband.valid, sched.faded - sched.fetch,
                                 name="sideband_valid")
            late_rest = delayed_in_memory(m, sideband.as_value()[1:], sched.faded - sched.fetch,
                                          name="sideband_memory")
            at_best = Signal(sideband.shape(), name="sideband_best")
            m.d.comb += at_best.as_value().eq(Cat(late_valid, late_rest))
        else:
            at_best = delayed(m, sideband, sched.faded - sched.fetch, name="sideband")
        at_state = delayed(m, at_best, 1, name="sideband_state")

        # ---- cycles 2 .. state: one datapath per lane ----------------------------------
        tree_kind = SplitMaxTree if self._options["max_tree"] == "split" else MaxTree
        accumulators = []
        for lane in range(lanes):
            lut = WeightLUT(cfg, lut_style=self._lut_style,
                            write_decode=self._options["lut_write"])
            m.submodules[f"weight_lut_{lane}"] = lut
            m.d.comb += [
                lut.write_addr.eq(self.lut_addr),
                lut.write_data.eq(self.lut_data),
                lut.write_en.eq(self.lut_we),
            ]
            for move in range(moves):
                m.d.comb += lut.direction[move].eq(window.cells[lane][move].direction)
            tree = tree_kind(moves, cfg.energy_bits, signed=False)
            m.submodules[f"max_tree_{lane}"] = tree
            inside_at_code = delayed(m, window.inside[lane], sched.code - sched.window,
                                     name=f"inside_code_{lane}", reset_less=True)
            inside = delayed(m, inside_at_code, sched.weighted - sched.code,
                             name=f"inside_{lane}", reset_less=True)
            m.d.comb += tree.valid.eq(inside)
            for move in range(moves):
                candidate = WeightedCandidate(cfg)
                m.submodules[f"weighted_{lane}_{move}"] = candidate
                energy = delayed(m, window.cells[lane][move].energy, sched.code - sched.window,
                                 name=f"energy_{lane}_{move}", reset_less=True)
                m.d.comb += [
                    candidate.energy.eq(energy),
                    candidate.code.eq(lut.code[move]),
                    candidate.inside.eq(inside_at_code[move]),
                    tree.values[move].eq(candidate.weighted),
                ]
            accumulator = Accumulator(cfg)
            m.submodules[f"accumulator_{lane}"] = accumulator
            m.d.comb += [
                accumulator.best.eq(tree.best.value),
                accumulator.move.eq(tree.best.index),
                accumulator.pixel.eq(at_best.pixel[lane]),
                accumulator.segment_start.eq(at_best.segment_start),
            ]
            accumulators.append(accumulator)

        # Beat address of the beat leaving the accumulators (as DPCore's write_addr).
        write_addr = Signal(range(cfg.frame_beats))
        with m.If(at_best.valid):
            m.d.sync += write_addr.eq(Mux(at_best.start_of_frame, 0, write_addr + 1))

        # ---- cycle `state`: write back and queue for output ---------------------------
        result = Signal(wide_state_layout(cfg))
        m.d.comb += [
            self.state_store.write_addr.eq(write_addr),
            self.state_store.write_en.eq(at_state.valid),
            result.end_of_line.eq(at_state.end_of_line),
            result.end_of_frame.eq(at_state.end_of_frame),
            result.end_of_segment.eq(at_state.end_of_segment),
        ]
        for lane, accumulator in enumerate(accumulators):
            m.d.comb += [
                self.state_store.write_data[lane].energy.eq(accumulator.energy),
                self.state_store.write_data[lane].direction.eq(accumulator.direction),
                getattr(result, f"energy_{lane}").eq(accumulator.energy),
                getattr(result, f"direction_{lane}").eq(accumulator.direction),
            ]
        m.submodules.output_fifo = output_fifo = ThermometerFIFO(
            data.StructLayout({"state": wide_state_layout(cfg), "saturated": 1}),
            self._fifo_depth)
        m.d.comb += [
            output_fifo.w.payload.state.eq(result),
            output_fifo.w.payload.saturated.eq(
                Cat(*[a.saturated for a in accumulators]).any()),
            output_fifo.w.valid.eq(at_state.valid),
            self.states.payload.eq(output_fifo.r.payload.state),
            self.states.valid.eq(output_fifo.r.valid),
            output_fifo.r.ready.eq(self.states.ready),
        ]
        state_events(m, self.events, self.states, output_fifo.r.payload.saturated)

        m.submodules.input_credit = credit = InputCredit(self._fifo_depth, copies=copies)
        m.d.comb += [
            credit.accept.eq(own),
            credit.handed_out.eq(self.states.valid & self.states.ready),
            input_ready.eq(credit.ready),
        ]
        return m
