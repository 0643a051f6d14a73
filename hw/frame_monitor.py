"""Frame-sync fault monitor of the AXI4-Stream video input.

:class:`FrameMonitor` watches every accepted input beat (``tuser[0]`` = start of frame,
``tlast`` = end of line) and classifies it against the W x H raster. Its counters follow
exactly the rule of the core's :class:`~dptbd.hw.controller.Controller`: a start of frame
where the counters do not expect one restarts them (that beat becomes pixel (0, 0)); a
missing start of frame where one is expected is ignored (the beat is pixel (0, 0) anyway).
So the monitor and the core always agree on where a beat sits.

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
                 on past W x H (or the stream began without a start of frame)
line_length      has ``tlast`` but is not on column W-1, or is on column W-1 without
                 ``tlast`` (column after any restart above)
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
    faults : Out(fault_layout())
        Registered one-cycle pulses, one per fault of the beat accepted in the cycle before.
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "accept": In(1),
            "first": In(1),
            "last": In(1),
            "faults": Out(fault_layout()),
        })

    def elaborate(self, platform):
        m = Module()
        width, height = self._cfg.width, self._cfg.height
        col = Signal(range(width))
        row = Signal(range(height))
        at_start = Signal(init=1)          # the next beat is expected at (0, 0)

        restart = self.first & ~at_start
        eff_col = Mux(restart, 0, col)
        eff_row = Mux(restart, 0, row)
        last_col = eff_col == width - 1
        end_of_frame = last_col & (eff_row == height - 1)

        m.d.sync += [
            self.faults.sof_unexpected.eq(self.accept & restart & (col != 0)),
            self.faults.frame_short.eq(self.accept & restart & (col == 0)),
            self.faults.frame_long.eq(self.accept & at_start & ~self.first),
            self.faults.line_length.eq(self.accept & (self.last != last_col)),
        ]
        with m.If(self.accept):
            m.d.sync += [
                col.eq(Mux(last_col, 0, eff_col + 1)),
                row.eq(Mux(last_col, Mux(eff_row == height - 1, 0, eff_row + 1), eff_row)),
                at_start.eq(end_of_frame),
            ]
        return m
