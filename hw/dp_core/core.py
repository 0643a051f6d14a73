"""DPCore, the DP pipeline without its state store: its stages; its output queue is
:func:`~dptbd.hw.dp_core.output_queue.queue_output`'s."""

from __future__ import annotations

from amaranth.hdl import Cat, Module, Mux, Signal, signed, unsigned
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.accumulator import Accumulator, ClampedAccumulator
from dptbd.hw.controller import Controller
from dptbd.hw.delay import delayed, delayed_in_memory
from dptbd.hw.dp_core.options import check_core_options, core_line_buffer
from dptbd.hw.dp_core.output_queue import queue_output
from dptbd.hw.dp_core.ports import family_write_members, lut_write_members, run_time_k_members
from dptbd.hw.family_blocks import FamilyBlocks
from dptbd.hw.forgetting_multiplier import ForgettingMultiplier
from dptbd.hw.layouts import pixel_layout, state_layout, state_word_layout
from dptbd.hw.max_tree import MaxTree
from dptbd.hw.merit_lut import MeritLUT
from dptbd.hw.penalised_candidate import PenalisedCandidate
from dptbd.hw.penalty_lut import PenaltyLUT
from dptbd.hw.pipelined_max import SplitMaxTree
from dptbd.hw.schedule import PipelineSchedule, check_supported
from dptbd.hw.state_store import StateStoreSignature
from dptbd.hw.weight_lut import WeightLUT, resolve_lut_style
from dptbd.hw.weighted_candidate import WeightedCandidate
from dptbd.hw.window import Window

__all__ = ["DPCore"]


class DPCore(wiring.Component):
    """Streaming direction-weighted DP, one pixel per clock, with an external state store.

    Parameters
    ----------
    cfg : DPConfig
        The configuration; refused with :class:`~dptbd.errors.ConfigError` when the
        gateware does not implement it (:func:`~dptbd.hw.schedule.check_supported`).
    output_fifo_depth : int or None
        Entries of the output FIFO. ``None`` (default) is ``latency + 2``, the least that
        sustains one pixel per clock without back-pressure with the input credit decided a
        cycle early (see "credits" in the source); at least 3.
    lut_style : {"auto", "bram", "logic"}
        Storage of the weight LUT (:class:`~dptbd.hw.weight_lut.WeightLUT`): block RAM,
        logic (flip-flops and multiplexers, no block RAM), or ``"auto"`` (default: logic for
        r = 1, block RAM for r = 2). A synthesis choice only: behaviour and latency are the
        same. Anything else raises ``ValueError``.
    line_buffer_style : {"bram", "lutram", "dp16kd"}
        Storage of the line buffer (:class:`~dptbd.hw.line_buffer.LineBuffer`): block RAM
        (default) or LUT RAM (``"lutram"``: ``ram_style = "distributed"``, for ECP5, where
        the block RAM's read is the critical path; on iCE40, which has no LUT RAM, it would
        be built from logic; for an even width read interleaved, ``LineBuffer(
        interleaved_read=True)``), or ECP5 DP16KDs read a cycle ahead through their output
        register (``"dp16kd"``, ``LineBuffer(ram_style="dp16kd")``, ECP5 only; what the
        ECP5 flow builds from 256 pixels wide, :mod:`dptbd.hw.flow.family`). A synthesis
        choice only: behaviour and latency are the same. Anything else raises
        ``ValueError``.
    sideband_delay : {"registers", "memory"}
        How the pixel's side band (pixel value, position flags) is delayed from the fetch
        stage to the accumulator (``best - fetch`` cycles, 7 for the default build):
        a chain of registers (default), or a ring buffer in one small block RAM
        (:func:`~dptbd.hw.delay.delayed_in_memory`; the ``valid`` bit stays in registers),
        which saves ~90 iCE40 logic cells (a chained flip-flop costs a whole cell there)
        and is what the flow builds for iCE40. Behaviour and latency are the same. Anything
        else raises ``ValueError``.
    max_tree : {"compact", "split"}
        The max/argmax tree: :class:`~dptbd.hw.max_tree.MaxTree` (default, one register
        stage per level) or :class:`~dptbd.hw.pipelined_max.SplitMaxTree` (compare and
        select in two stages per level: ``ceil(log2(M))`` cycles more latency, counted by
        :class:`~dptbd.hw.schedule.PipelineSchedule`; what the flow builds for ECP5).
        Behaviour is the same. Anything else raises ``ValueError``.
    state_store_style, histogram_style, control_style : str
        Options of the blocks attached around DPCore (``state_store_style``: the on-chip
        store's block RAM, :class:`~dptbd.hw.read_ahead_store.ReadAheadStore`;
        ``histogram_style``: the segmenter's histogram memory,
        :class:`~dptbd.hw.histogram.Histogram`; ``control_style``: the segmenter's and the
        AXI top's input control, ``"registered"`` flags and enables from registers of their
        own, same bits, same cycles). DPCore checks and keeps them; ``docs/gateware.md``,
        "Implementation options per FPGA family", has their values. Anything else raises
        ``ValueError``.
    output_queue_style : {"binary", "one_hot"}
        The output flags' FIFO's pointers (``ThermometerFIFO(storage="registers")`` or
        ``"one_hot"``, what the flow builds for ECP5): same words, same cycles. Anything
        else raises ``ValueError``.
    register_read : {"one_level", "two_level"}
        The AXI top's register read (:class:`~dptbd.hw.register_file.RegisterFile`
        ``read_registered`` with ``"two_level"``, what the flow builds for ECP5: an
        AXI4-Lite read answered a cycle later). DPCore checks and keeps it. Anything else
        raises ``ValueError``.
    credit_ready : {"one", "per_load"}; lut_write : {"case", "predecoded"}
        The input credit's ``ready`` registers at P > 1 (``DPCoreWide``; DPCore checks and
        keeps it); the weight LUT's write decode (``WeightLUT(write_decode=…)``, same
        cycles). Anything else raises ``ValueError``.

    Members
    -------
    pixels : In(stream.Signature(pixel_layout(cfg)))
        Input pixels in raster order; ``first`` marks pixel (0, 0) of a frame.
        ``pixels.ready`` is a register (it does not depend on ``pixels.valid`` or
        ``states.ready`` combinationally).
    states : Out(stream.Signature(state_layout(cfg)))
        The new (E, d) of every accepted pixel, in acceptance order, with end flags.
        ``states.valid`` and ``states.payload`` come from registers.
    lut_addr, lut_data, lut_we : In
        Weight LUT write port (:class:`~dptbd.hw.weight_lut.WeightLUT`).
    merit_addr, merit_data, merit_we : In
        Merit LUT write port (:class:`~dptbd.hw.merit_lut.MeritLUT`), only when the merit
        LUT is built (paper 000's family, :func:`family_write_members`).
    penalty_addr, penalty_data, penalty_we : In
        Penalty LUT write port (:class:`~dptbd.hw.penalty_lut.PenaltyLUT`), only when the
        penalty LUT is built.
    segment_frames : In(range(1, K_max + 1), init=K)
        Run-time K, sampled in the cycle a segment's first pixel is accepted (clamped to
        [1, K_max]); see :class:`~dptbd.hw.controller.Controller`.
    segment_begin : Out(1)
        Combinational pulse: the pixel accepted in this cycle begins a segment.
    events : Out(event_layout(cfg))
        ``frame_done``, ``segment_done``, ``saturated`` pulses with the ``states``
        handshake (:func:`~dptbd.hw.layouts.event_layout`); ``list_done`` is 0.
    state_store : Out(StateStoreSignature(cfg))
        The state store.
    """

    def __init__(self, cfg: DPConfig, *, output_fifo_depth: int | None = None,
                 lut_style: str = "auto", line_buffer_style: str = "bram",
                 sideband_delay: str = "registers", max_tree: str = "compact",
                 state_store_style: str = "memory", histogram_style: str = "memory",
                 control_style: str = "generic", output_queue_style: str = "binary",
                 register_read: str = "one_level", credit_ready: str = "one",
                 lut_write: str = "case"):
        # the implementation options (per FPGA family), checked
        self._options = dict(line_buffer_style=line_buffer_style, sideband_delay=sideband_delay,
                             max_tree=max_tree, state_store_style=state_store_style,
                             histogram_style=histogram_style, control_style=control_style,
                             output_queue_style=output_queue_style, register_read=register_read,
                             credit_ready=credit_ready, lut_write=lut_write)
        check_core_options(**self._options)
        self._schedule = check_supported(cfg, max_tree=max_tree)   # refuses a bad max_tree
        self._cfg = cfg
        self._lut_style = resolve_lut_style(cfg, lut_style)
        if output_fifo_depth is None:
            output_fifo_depth = self._schedule.latency + 2
        if output_fifo_depth < 3:
            raise ValueError(f"output_fifo_depth must be an integer in [3, inf), got {output_fifo_depth}")
        self._fifo_depth = output_fifo_depth
        super().__init__({
            "pixels": In(stream.Signature(pixel_layout(cfg))),
            "states": Out(stream.Signature(state_layout(cfg))),
            **lut_write_members(cfg),
            **family_write_members(cfg),
            **run_time_k_members(cfg),
            "state_store": Out(StateStoreSignature(cfg)),
        })
        self._resync = Signal(name="resync")
        self._next_read_addr = Signal(range(cfg.width * cfg.height), name="next_read_addr")

    @property
    def config(self) -> DPConfig:
        """The configuration this core was built for."""
        return self._cfg

    @property
    def resync(self) -> Signal:
        """Not a port: pulses with ``segment_begin`` when the segment begins at a
        resynchronisation (an unexpected ``first``, :class:`~dptbd.hw.controller.Controller`),
        for ``DPSegmenter``, which passes only the settings of other segment starts to its
        segmenter."""
        return self._resync

    @property
    def next_read_addr(self) -> Signal:
        """Not a port: the controller's ``next_read_addr`` (the read address of the next
        pixel if it continues the raster), for the on-chip store that reads ahead
        (:class:`~dptbd.hw.read_ahead_store.ReadAheadStore`)."""
        return self._next_read_addr

    @property
    def schedule(self) -> PipelineSchedule:
        """Cycle offsets of every stage."""
        return self._schedule

    @property
    def latency(self) -> int:
        """Cycles from a pixel's acceptance to its result on ``states`` (no back-pressure)."""
        return self._schedule.latency

    @property
    def output_fifo_depth(self) -> int:
        """Entries of the output FIFO."""
        return self._fifo_depth

    @property
    def lut_style(self) -> str:
        """The weight LUT's resolved storage: ``"bram"`` or ``"logic"``."""
        return self._lut_style

    @property
    def line_buffer_style(self) -> str:
        """The line buffer's storage: ``"bram"`` or ``"lutram"``."""
        return self._options["line_buffer_style"]

    @property
    def sideband_delay(self) -> str:
        """How the side band is delayed: ``"registers"`` or ``"memory"``."""
        return self._options["sideband_delay"]

    @property
    def core_options(self) -> dict:
        """The storage options (:data:`CORE_OPTIONS`) this core was built with."""
        return dict(self._options)

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        sched = self._schedule
        moves = cfg.n_moves
        blocks = FamilyBlocks.from_config(cfg)

        # ---- cycle 0: handshake, position, read-ahead -------------------------------
        input_ready = Signal()
        m.d.comb += self.pixels.ready.eq(input_ready)
        accept = self.pixels.valid & input_ready

        m.submodules.controller = controller = Controller(
            cfg, registered=self._options["control_style"] == "registered")
        m.d.comb += [
            controller.accept.eq(accept),
            controller.first.eq(self.pixels.payload.first),
            controller.segment_frames.eq(self.segment_frames),
            self.segment_begin.eq(controller.segment_begin),
            self._resync.eq(accept & controller.resync),
            self._next_read_addr.eq(controller.next_read_addr),
            self.state_store.read_addr.eq(controller.read_addr),
            self.state_store.read_en.eq(accept),
        ]
        m.submodules.line_buffer = line_buffer = core_line_buffer(
            state_word_layout(cfg), cfg.width, 2 * cfg.radius, self._options["line_buffer_style"])
        m.d.comb += line_buffer.advance.eq(accept)

        # ---- cycle 1 (fetch): new window column --------------------------------------
        pixel = delayed(m, self.pixels.payload.pixel, sched.fetch, name="pixel")
        m.d.comb += line_buffer.data_in.eq(self.state_store.read_data)
        m.submodules.window = window = Window(cfg)
        m.d.comb += [
            window.column[0].eq(self.state_store.read_data),
            *[window.column[k + 1].eq(line_buffer.taps[k]) for k in range(2 * cfg.radius)],
            window.shift.eq(controller.valid),
            window.row_inside.eq(controller.row_inside),
            window.col_inside.eq(controller.col_inside),
        ]

        # Side-band travelling with the pixel from the fetch stage to the accumulator.
        sideband = Signal(data.StructLayout({
            "valid": 1, "pixel": cfg.input_bits, "start_of_frame": 1, "segment_start": 1,
            "end_of_line": 1, "end_of_frame": 1, "end_of_segment": 1,
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

        # ---- cycle 2 (window) -> 3 (code): weight lookup -----------------------------
        m.submodules.weight_lut = lut = WeightLUT(cfg, lut_style=self._lut_style,
                                                  write_decode=self._options["lut_write"])
        m.d.comb += [
            lut.write_addr.eq(self.lut_addr),
            lut.write_data.eq(self.lut_data),
            lut.write_en.eq(self.lut_we),
        ]
        for move in range(moves):
            m.d.comb += lut.direction[move].eq(window.cells[move].direction)

        # ---- paper 000's family: merit and penalty lookups, beside the weights' -------
        merit = None
        if blocks.merit_lut:     # looked up at the window stage like the weights (§8.1)
            m.submodules.merit_lut = merit_lut = MeritLUT(cfg)
            m.d.comb += [
                merit_lut.pixel.eq(delayed(m, pixel, sched.window - sched.fetch,
                                           name="pixel_window")),
                merit_lut.write_addr.eq(self.merit_addr),
                merit_lut.write_data.eq(self.merit_data),
                merit_lut.write_en.eq(self.merit_we),
            ]
            merit = delayed(m, merit_lut.merit, sched.faded - sched.code, name="merit",
                            reset_less=True)
        if blocks.penalty_lut:   # §8.2
            m.submodules.penalty_lut = penalty_lut = PenaltyLUT(cfg, lut_style=self._lut_style)
            m.d.comb += [
                penalty_lut.write_addr.eq(self.penalty_addr),
                penalty_lut.write_data.eq(self.penalty_data),
                penalty_lut.write_en.eq(self.penalty_we),
            ]
            for move in range(moves):
                m.d.comb += penalty_lut.direction[move].eq(window.cells[move].direction)
        value_shape = (signed(cfg.candidate_value_bits) if blocks.signed_candidates
                       else unsigned(cfg.energy_bits))
        # ---- end of paper 000's family -------------------------------------------------

        # ---- cycles 3 .. weighted: multipliers ---------------------------------------
        # Each multiplier also gets its move's edge flag at the code's cycle: an
        # out-of-image predecessor weighs 0 (WeightedCandidate), so what its cell holds
        # (power-up garbage, X in a 4-state simulator) never reaches the max tree.
        # SplitMaxTree: compare and select in two stages per level (ECP5 timing)
        tree_kind = SplitMaxTree if self._options["max_tree"] == "split" else MaxTree
        m.submodules.max_tree = tree = tree_kind(moves, value_shape.width,
                                                 signed=blocks.signed_candidates)
        inside_at_code = delayed(m, window.inside, sched.code - sched.window,
                                 name="inside_code", reset_less=True)
        inside = delayed(m, inside_at_code, sched.weighted - sched.code, name="inside",
                         reset_less=True)
        m.d.comb += tree.valid.eq(delayed(m, inside, sched.penalised - sched.weighted,
                                          name="inside_penalised", reset_less=True))
        for move in range(moves):
            candidate = WeightedCandidate(cfg)
            m.submodules[f"weighted_{move}"] = candidate
            energy = delayed(m, window.cells[move].energy, sched.code - sched.window,
                             name=f"energy_{move}", reset_less=True)
            m.d.comb += [
                candidate.energy.eq(energy),
                candidate.code.eq(lut.code[move]),
                candidate.inside.eq(inside_at_code[move]),
            ]
            if blocks.penalty_lut:  # paper 000's family: V = C - Qc (§8.3)
                penalised = PenalisedCandidate(cfg)
                m.submodules[f"penalised_{move}"] = penalised
                m.d.comb += [
                    penalised.weighted.eq(candidate.weighted),
                    penalised.penalty.eq(delayed(
                        m, penalty_lut.code[move], sched.weighted - sched.code,
                        name=f"penalty_{move}", reset_less=True)),
                    penalised.inside.eq(inside[move]),
                    tree.values[move].eq(penalised.value),
                ]
            else:
                m.d.comb += tree.values[move].eq(candidate.weighted)

        # ---- paper 000's family: forgetting multiplier after the tree (§8.4) ----------
        best_value, best_move = tree.best.value, tree.best.index
        if blocks.forgetting:
            m.submodules.forgetting = forgetting = ForgettingMultiplier(cfg, value_shape)
            m.d.comb += forgetting.value.eq(tree.best.value)
            best_value = forgetting.scaled
            best_move = delayed(m, tree.best.index, sched.faded - sched.best, name="best_move",
                                reset_less=True)
        # ---- end of paper 000's family -------------------------------------------------

        # ---- faded (= best) -> state: accumulator ------------------------------------
        # -- side-band delay (an area option): `valid` always in registers --
        if self._options["sideband_delay"] == "memory":
            late_valid = delayed(m, sideband.valid, sched.faded - sched.fetch,
                                 name="sideband_valid")
            late_rest = delayed_in_memory(m, sideband.as_value()[1:], sched.faded - sched.fetch,
                                          name="sideband_memory")
            at_best = Signal(sideband.shape(), name="sideband_best")
            m.d.comb += at_best.as_value().eq(Cat(late_valid, late_rest))
        else:
            at_best = delayed(m, sideband, sched.faded - sched.fetch, name="sideband")
        # -- end --
        if blocks.clamped_accumulator:  # paper 000's family (§8.5)
            m.submodules.accumulator = accumulator = ClampedAccumulator(cfg, value_shape)
            m.d.comb += [
                accumulator.best.eq(best_value),
                accumulator.move.eq(best_move),
                accumulator.merit.eq(at_best.pixel if merit is None else merit),
                accumulator.segment_start.eq(at_best.segment_start),
            ]
        else:
            m.submodules.accumulator = accumulator = Accumulator(cfg)
            m.d.comb += [
                accumulator.best.eq(tree.best.value),
                accumulator.move.eq(tree.best.index),
                accumulator.pixel.eq(at_best.pixel),
                accumulator.segment_start.eq(at_best.segment_start),
            ]
        at_state = delayed(m, at_best, 1, name="sideband_state")
        # Raster address of the pixel leaving the accumulator: pixels come out in
        # acceptance order, so it is 0 at a frame start (also after a resync) and the
        # previous address + 1 otherwise.
        write_addr = Signal(range(cfg.width * cfg.height))
        with m.If(at_best.valid):
            m.d.sync += write_addr.eq(Mux(at_best.start_of_frame, 0, write_addr + 1))

        # ---- cycle `state`: write back and queue for output ---------------------------
        m.d.comb += [
            self.state_store.write_addr.eq(write_addr),
            self.state_store.write_data.energy.eq(accumulator.energy),
            self.state_store.write_data.direction.eq(accumulator.direction),
            self.state_store.write_en.eq(at_state.valid),
        ]
        queue_output(m, cfg, self._fifo_depth, accumulator, at_state, self.states,
                     self.events, accept, input_ready, self._options["output_queue_style"])
        return m
