"""The (2r+1) x (2r+1) window of previous-frame states around the current pixel.

A shift register of 2r+1 columns of 2r+1 state words. Each advance shifts in one new
column, the states at column x + r of rows y + r … y - r (from the state store and the line
buffers). After the shift, cell ``(i, j)`` holds the previous state of pixel
``(y + r - i, x + r - j)``: the predecessor of move ``m = i * (2r+1) + j``, whose
``(dy, dx) = (i - r, j - r)``. Cells are therefore output in move-index order.

The window also registers, per move, whether its predecessor lies inside the image
(``docs/arithmetic.md`` §4.1). Outside the image the cell holds a neighbouring row's state
(the raster stream wraps), which the max tree must ignore.
"""

from __future__ import annotations

from amaranth.hdl import Cat, Module
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.layouts import state_word_layout

__all__ = ["Window"]


class Window(wiring.Component):
    """Window register array with per-move image-edge flags.

    Parameters
    ----------
    cfg : DPConfig
        Radius r, frame size and state widths.

    Members
    -------
    column : In(state_word_layout(cfg)).array(2r+1)
        The new column: ``column[i]`` is the state of row ``y + r - i`` at column ``x + r``.
    shift : In(1)
        Shift ``column`` in at this cycle's edge.
    row_inside, col_inside : In(2r+1), In(2r+1)
        For the centre pixel ``(y, x)`` of the window being shifted in: bit i of
        ``row_inside`` is set when row ``y + r - i`` is inside the image, bit j of
        ``col_inside`` when column ``x + r - j`` is (the controller's
        :func:`~dptbd.hw.controller.inside_flags`, registered there).
    cells : Out(state_word_layout(cfg)).array(M)
        Registered: the predecessor state of each move, in move-index order.
    inside : Out(M)
        Registered: bit m is set when move m's predecessor ``(y - dy, x - dx)`` is inside
        the image. The centre bit is always set.
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        side = 2 * cfg.radius + 1
        layout = state_word_layout(cfg)
        super().__init__({
            "column": In(layout).array(side),
            "shift": In(1),
            "row_inside": In(side),
            "col_inside": In(side),
            "cells": Out(layout).array(side * side),
            "inside": Out(side * side),
        })

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        r = cfg.radius
        side = 2 * r + 1

        row_ok, col_ok = self.row_inside, self.col_inside
        inside = Cat(*[row_ok[i] & col_ok[j] for i in range(side) for j in range(side)])

        with m.If(self.shift):
            m.d.sync += self.inside.eq(inside)
            for i in range(side):
                m.d.sync += self.cells[i * side].eq(self.column[i])
                for j in range(1, side):
                    m.d.sync += self.cells[i * side + j].eq(self.cells[i * side + j - 1])
        return m
