"""Frame-sync fault monitor of the AXI4-Stream video input.

:class:`FrameMonitor` watches every accepted input beat (``tuser[0]`` = start of frame,
``tlast`` = end of line) and classifies it against the W x H raster. Its frame counters follow
exactly the rule of the core's :class:`~dptbd.hw.controller.Controller`: a start of frame
where the counters do not expect one restarts them (that beat becomes pixel (0, 0)); a
missing start of frame where one is expected is ignored (the beat is pixel (0, 0) anyway).
So the monitor and the core always agree on where a beat sits. Lines are checked on their
own: a *line* is the beats from one end of line (``tlast``) or start of frame to the next
``tlast``, and a line whose length is not W is one ``line_length`` event, whatever the
frame counters make of the beats after it.

Fault classes (one one-cycle pulse each, the cycle after the beat; a beat can raise
``line_length`` together with one of the other three):

================ =====================================================================
fault            the accepted beat …
================ =====================================================================
sof_unexpected   has start of frame while a frame is in progress and the beat is not the
                 first of a line (a line was cut short)
frame_short      has start of frame while a frame is in progress at the first column of a
                 line: the frame had whole lines only, fewer than H
frame_long       has no start of frame where a frame must start: the previous frame went
                 on past W x H (or the stream began without a start of frame); never raised
                 while ``no_sof`` is 1 (a source without start-of-frame markers)
line_length      ends a line of fewer than W beats (``tlast`` before its W-th beat), or is
                 the (W+1)-th beat of a line (no ``tlast`` on its W-th beat): one event per
                 line whose length is not W. A start of frame begins a new line without an
                 event (a line it cuts is ``sof_unexpected``)
================ =====================================================================
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.register_map import FAULTS

__all__ = ["fault_layout", "FrameMonitor"]


def fault_layout() -> data.StructLayout:
    """One bit per fault class (:data:`~dptbd.hw.register_map.FAULTS`)."""
    return data.StructLayout({name: 1 for name in FAULTS})


class FrameMonitor(wiring.Component):
    """Classify accepted beats against W x H (see the module doc).

    Members
    -------
    accept : In(1)
        A beat is accepted in this cycle.
    first, last : In(1)
        Its start-of-frame (``tuser[0]``) and end-of-line (``tlast``) bits.
    no_sof : In(1)
        The source sends no start-of-frame markers: ``frame_long`` is not raised.
    faults : Out(fault_layout())
        Registered one-cycle pulses, one per fault of the beat accepted in the cycle before.

    With ``registered=True`` (the ECP5 build's, ``control_style="registered"``) the
    comparisons of the counters (column W-1, row H-1, column 0) are flags in registers,
    updated with the counters, so that no comparison lies between a counter and the next
    ``row`` / ``col`` / fault. Same pulses, same cycles.
    """

    def __init__(self, cfg: DPConfig, *, registered: bool = False):
        self._cfg = cfg
        self._registered = bool(registered)
        super().__init__({
            "accept": In(1),
            "first": In(1),
            "last": In(1),
            "no_sof": In(1),
            "faults": Out(fault_layout()),
        })

    def elaborate(self, platform):
        m = Module()
        width, height = self._cfg.width, self._cfg.height
        col = Signal(range(width))
        row = Signal(range(height))
        at_start = Signal(init=1)          # the next beat is expected at (0, 0)

        restart = self.first & ~at_start
        # beats of the current line before this one, saturating at W + 1 (a start of frame
        # begins a new line)
        run = Signal(range(width + 2))
        index = Mux(self.first, 0, run)
        bad_line = (self.last & (index < width - 1)) | (index == width)
        if self._registered:
            self._flagged(m, col, row, at_start, restart, run, index)
            return m
        eff_col = Mux(restart, 0, col)
        eff_row = Mux(restart, 0, row)
        last_col = eff_col == width - 1
        end_of_frame = last_col & (eff_row == height - 1)

        m.d.sync += [
            self.faults.sof_unexpected.eq(self.accept & restart & (col != 0)),
            self.faults.frame_short.eq(self.accept & restart & (col == 0)),
            self.faults.frame_long.eq(self.accept & at_start & ~self.first & ~self.no_sof),
            self.faults.line_length.eq(self.accept & bad_line),
        ]
        with m.If(self.accept):
            m.d.sync += [
                col.eq(Mux(last_col, 0, eff_col + 1)),
                row.eq(Mux(last_col, Mux(eff_row == height - 1, 0, eff_row + 1), eff_row)),
                at_start.eq(end_of_frame),
                run.eq(Mux(self.last, 0, Mux(index == width + 1, index, index + 1))),
            ]
        return m

    def _flagged(self, m, col, row, at_start, restart, run, index):
        """``registered``: ``col == W-1``, ``row == H-1`` and ``col == 0`` in registers
        (``col_last``, ``row_last``, ``col_zero``), and the line's ``run`` against W
        (``run < W-1``, ``== W-1``, ``== W``), each next value from the flags,
        the beat's bits and a comparison of the register it follows (``col == W-2``,
        ``row == H-2``, ``run == W-2``, ``run < W-2``); W, H >= 3 (DPConfig's)."""
        width, height = self._cfg.width, self._cfg.height
        col_last = Signal(init=width == 1)
        row_last = Signal(init=height == 1)
        col_zero = Signal(init=1)
        last_col = Mux(restart, width == 1, col_last)           # the beat ends its row
        last_row = Mux(restart, height == 1, row_last)          # the beat is in row H-1
        # a restart's beat is (0, 0): its next row is 1 after a row of one column
        restart_row = int(width == 1 and height > 1)
        run_short = Signal(init=1)                              # run < W-1
        run_before = Signal()                                   # run == W-1
        run_full = Signal()                                     # run == W
        first, last = self.first, self.last                     # index = 0 on a first
        bad_line = (last & (first | run_short)) | (~first & run_full)
        m.d.sync += [
            self.faults.sof_unexpected.eq(self.accept & restart & ~col_zero),
            self.faults.frame_short.eq(self.accept & restart & col_zero),
            self.faults.frame_long.eq(self.accept & at_start & ~self.first & ~self.no_sof),
            self.faults.line_length.eq(self.accept & bad_line),
        ]
        with m.If(self.accept):
            m.d.sync += [
                col.eq(Mux(last_col, 0, Mux(restart, 1, col + 1))),
                col_last.eq(Mux(last_col, width == 1,
                                Mux(restart, width == 2, col == width - 2))),
                col_zero.eq(last_col),
                row.eq(Mux(restart, restart_row,
                           Mux(col_last, Mux(row_last, 0, row + 1), row))),
                row_last.eq(Mux(restart, restart_row == height - 1,
                                Mux(col_last, Mux(row_last, height == 1, row == height - 2),
                                    row_last))),
                at_start.eq(last_col & last_row),
                run.eq(Mux(self.last, 0, Mux(index == width + 1, index, index + 1))),
                run_short.eq(last | first | (run < width - 2)),
                run_before.eq(~last & ~first & (run == width - 2)),
                run_full.eq(~last & ~first & run_before),
            ]
