"""The candidate emitter: the record cap, the list trailer and the output FIFO of the
segmenter (``docs/arithmetic.md`` §6.4, ``docs/gateware.md`` "Segmenter").
"""

from __future__ import annotations

from amaranth.hdl import Module, Signal
from amaranth.lib import data, fifo, stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import candidate_layout, record_layout, trailer_layout
from dptbd.hw.thermometer_fifo import ThermometerFIFO

__all__ = ["CandidateEmitter"]


class CandidateEmitter(wiring.Component):
    """Turns the scored pixels of one frame into a list of at most C records and a trailer.

    In a cycle with ``valid`` high (one scored pixel, raster order):

    * if ``selected`` and fewer than C records were emitted since the last trailer, the
      record is written to the output FIFO now; if ``selected`` but C were emitted, the
      record is dropped and the list's ``overflow`` bit set;
    * if ``end_of_list``, the trailer — count (including this pixel's record), ``threshold``,
      ``overflow``, ``primed``, ``aligned``, ``missed`` sampled now — is written to the
      FIFO in the next cycle, and the count and overflow restart from 0.

    The caller must not present a selected pixel in the cycle after an ``end_of_list`` (the
    segmenter never does: the next scored pixel waits for the threshold scan), so at most one
    word is written per cycle.

    Parameters
    ----------
    cfg : DPConfig
        Widths, C (``record_capacity``).
    fifo_depth : int
        Entries of the output FIFO (``SyncFIFOBuffered``), at least 6.
    registered_cap : bool
        ``True`` (the ECP5 build): "fewer than C emitted" is a register updated with the
        count, so no comparison lies between the count and the FIFO's write; ``False``
        (default): the comparison. Same words, same cycles.
    staged_fifo : bool
        ``True`` (the ECP5 build): the output FIFO is a
        :class:`~dptbd.hw.thermometer_fifo.ThermometerFIFO` whose write goes through a stage
        register (``staged=True``), with its level's flags in registers, and a trailer's
        count is completed in the cycle it is written (the record of the list's last pixel
        added there), so that the push ends at registers: no adder, level counter or memory
        write enable after it. ``False`` (default): the library's ``SyncFIFOBuffered``.
        Same words, same cycles.

    Members
    -------
    valid, selected, end_of_list, aligned, missed, primed : In(1)
    record : In(record_layout(cfg))
        row, col, E, d of the pixel.
    threshold : In(b + 1)
    candidates : Out(stream.Signature(candidate_layout(cfg)))
        Records and trailers; ``valid`` and ``payload`` come from registers.
    space : Out(1)
        A register: the FIFO held at most ``fifo_depth - 5`` words in the previous cycle, so
        it holds at most ``fifo_depth - 4`` now (one write per cycle): room for the words of
        the pixel in this stage (a record, then a trailer) and of one more pixel. A pixel
        may be accepted towards this stage only while ``space`` is high.
    space_next : Out(1)
        Only with ``registered_cap``: ``space`` of the next cycle (combinational), for a
        register of the caller's own that must follow it.
    """

    def __init__(self, cfg: DPConfig, *, fifo_depth: int = 8, registered_cap: bool = False,
                 staged_fifo: bool = False):
        if fifo_depth < 6:
            raise ValueError(f"fifo_depth must be an integer in [6, inf), got {fifo_depth}")
        self._cfg = cfg
        self._depth = fifo_depth
        self._registered_cap = registered_cap
        self._staged = bool(staged_fifo)
        super().__init__({
            "valid": In(1),
            "selected": In(1),
            "end_of_list": In(1),
            "aligned": In(1),
            "missed": In(1),
            "primed": In(1),
            "record": In(record_layout(cfg)),
            "threshold": In(cfg.threshold_bits),
            "candidates": Out(stream.Signature(candidate_layout(cfg))),
            "space": Out(1),
            **({"space_next": Out(1)} if registered_cap else {}),
        })

    @property
    def fifo_depth(self) -> int:
        return self._depth

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        capacity = cfg.record_capacity
        layout = candidate_layout(cfg)

        emitted = Signal(range(capacity + 1))
        overflow = Signal()
        if self._registered_cap:
            below = Signal(init=capacity > 0)          # emitted < C
            push = self.valid & self.selected & below
            dropped = self.valid & self.selected & ~below
            with m.If(self.valid & self.end_of_list):
                m.d.sync += below.eq(capacity > 0)
            with m.Elif(push):
                m.d.sync += below.eq(emitted != capacity - 1)
        else:
            push = self.valid & self.selected & (emitted < capacity)
            dropped = self.valid & self.selected & (emitted == capacity)

        trailer = Signal(trailer_layout(cfg))
        trailer_pending = Signal()
        m.d.sync += trailer_pending.eq(self.valid & self.end_of_list)
        if self._staged:                             # the list's last pixel's record
            last_pushed = Signal()
            with m.If(self.valid & self.end_of_list):
                m.d.sync += last_pushed.eq(push)
        with m.If(self.valid & self.end_of_list):
            m.d.sync += [
                trailer.count.eq(emitted if self._staged else emitted + push),
                trailer.threshold.eq(self.threshold),
                trailer.overflow.eq(overflow | dropped),
                trailer.primed.eq(self.primed),
                trailer.aligned.eq(self.aligned),
                trailer.missed.eq(self.missed),
                emitted.eq(0),
                overflow.eq(0),
            ]
        with m.Else():
            with m.If(push):
                m.d.sync += emitted.eq(emitted + 1)
            with m.If(dropped):
                m.d.sync += overflow.eq(1)

        word = Signal(layout)
        with m.If(trailer_pending):
            m.d.comb += [word.body.trailer.eq(trailer), word.end_of_list.eq(1)]
            if self._staged:
                m.d.comb += word.body.trailer.count.eq(trailer.count + last_pushed)
        with m.Else():
            m.d.comb += word.body.record.eq(self.record)

        if self._staged:
            m.submodules.fifo = staged = ThermometerFIFO(layout, self._depth, staged=True,
                                                         low_mark=self._depth - 5)
            m.d.comb += [
                staged.w.payload.eq(word),
                staged.w.valid.eq(push | trailer_pending),
                self.candidates.payload.eq(staged.r.payload),
                self.candidates.valid.eq(staged.r.valid),
                staged.r.ready.eq(self.candidates.ready),
            ]
            space_next = staged.low
            if self._registered_cap:
                m.d.comb += self.space_next.eq(space_next)
            m.d.sync += self.space.eq(space_next)
            return m

        m.submodules.fifo = out = fifo.SyncFIFOBuffered(
            width=data.Layout.cast(layout).size, depth=self._depth)
        m.d.comb += [
            out.w_data.eq(word),
            out.w_en.eq(push | trailer_pending),
            self.candidates.payload.eq(out.r_data),
            self.candidates.valid.eq(out.r_rdy),
            out.r_en.eq(self.candidates.ready),
        ]
        if self._registered_cap:
            m.d.comb += self.space_next.eq(out.level <= self._depth - 5)
            m.d.sync += self.space.eq(self.space_next)
        else:
            m.d.sync += self.space.eq(out.level <= self._depth - 5)
        return m
